"""Layered costmaps: the global one over the whole map and the local rolling window.

A :class:`LayeredCostmap` combines a static layer (the world's geometry), an obstacle layer
(lidar) and an inflation layer into one master :class:`~baobab.nav.costmap.Costmap2D`, the way
Nav2's ``Costmap2DROS`` does: static cells first, then the maximum with the obstacle layer, then
inflation. Updates are incremental: each change records the cells it touched, and the master is
recomputed only there (plus the inflation radius) and only when someone reads it.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from baobab.nav.costmap import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
    Costmap2D,
)
from baobab.nav.layers import (
    Bounds,
    InflationLayer,
    InflationParams,
    ObstacleLayer,
    ObstacleParams,
    StaticLayer,
    union_bounds,
)
from baobab.sim.lidar import LaserScan
from baobab.sim.world import Pose2D, World


@dataclass(frozen=True)
class CostmapParams:
    """Costmap settings: Nav2's defaults with the TurtleBot3 Burger's footprint radius (m)."""

    resolution: float = 0.05
    robot_radius: float = 0.105
    inflation_radius: float = 0.55
    cost_scaling_factor: float = 3.0
    obstacle: ObstacleParams = field(default_factory=ObstacleParams)
    use_static_layer: bool = True
    use_obstacle_layer: bool = True

    @property
    def inflation(self) -> InflationParams:
        """The inflation layer's parameters."""
        return InflationParams(self.robot_radius, self.inflation_radius, self.cost_scaling_factor)


class LayeredCostmap:
    """A master costmap built from static, obstacle and inflation layers on one lattice.

    Use :meth:`global_costmap` and :meth:`local_costmap` to build one. The window is the lattice
    rectangle ``[ix0, ix0 + size_x) x [iy0, iy0 + size_y)`` of the static layer's raster.

    Args:
        static: the rasterised world (shared by the global and local costmaps).
        window: ``(ix0, iy0, size_x, size_y)`` in lattice cells.
        rolling: True for a window that follows the robot.
        params: layer settings.
    """

    def __init__(
        self,
        static: StaticLayer,
        window: tuple[int, int, int, int],
        rolling: bool,
        params: CostmapParams | None = None,
    ) -> None:
        self.params = params or CostmapParams()
        self.static_layer = static
        self.rolling = rolling
        ix0, iy0, size_x, size_y = window
        self._ix0, self._iy0 = ix0, iy0
        res = static.resolution
        origin = (static.origin_x + ix0 * res, static.origin_y + iy0 * res)
        self._master = Costmap2D(
            size_x, size_y, res, origin, inscribed_radius=self.params.robot_radius
        )
        obstacle_grid = Costmap2D(size_x, size_y, res, origin)
        self.obstacle_layer = ObstacleLayer(obstacle_grid, self.params.obstacle)
        self.inflation_layer = InflationLayer(self.params.inflation)
        self.revision = 0
        self._dirty: Bounds | None = (0, 0, size_x, size_y)

    @classmethod
    def global_costmap(
        cls, world: World, params: CostmapParams | None = None, static: StaticLayer | None = None
    ) -> LayeredCostmap:
        """The costmap over the whole floor (and its lethal border)."""
        params = params or CostmapParams()
        static = static or StaticLayer(world, params.resolution)
        return cls(static, (0, 0, static.size_x, static.size_y), rolling=False, params=params)

    @classmethod
    def local_costmap(
        cls,
        world: World,
        center: Pose2D,
        params: CostmapParams | None = None,
        size: tuple[float, float] = (3.0, 3.0),
        static: StaticLayer | None = None,
    ) -> LayeredCostmap:
        """A rolling window of ``size`` (m), Nav2's 3 m x 3 m by default, centred on ``center``.

        Unlike Nav2's bringup (obstacle and inflation layers only) the window keeps the static
        layer by default: localisation is perfect here, and the floor's edge is invisible to
        the lidar. ``CostmapParams(use_static_layer=False)`` gives Nav2's local layers.
        """
        params = params or CostmapParams()
        static = static or StaticLayer(world, params.resolution)
        size_x = round(size[0] / params.resolution)
        size_y = round(size[1] / params.resolution)
        costmap = cls(static, (0, 0, size_x, size_y), rolling=True, params=params)
        costmap.update_origin(center.x, center.y)
        return costmap

    @property
    def costmap(self) -> Costmap2D:
        """The master costmap, brought up to date with every change so far."""
        self._refresh()
        return self._master

    @property
    def resolution(self) -> float:
        """Cell side (m)."""
        return self._master.resolution

    def update_origin(self, x: float, y: float) -> None:
        """Centre a rolling window on ``(x, y)`` (m), moving by whole lattice cells."""
        if not self.rolling:
            raise ValueError("only a rolling costmap moves its origin")
        size_x, size_y = self._master.size_x, self._master.size_y
        res = self.resolution
        ix0, iy0 = self.static_layer.lattice_index(x - size_x * res / 2, y - size_y * res / 2)
        dix, diy = ix0 - self._ix0, iy0 - self._iy0
        if dix == 0 and diy == 0:
            return
        self.obstacle_layer.shift(dix, diy)
        self._ix0, self._iy0 = ix0, iy0
        self._master.origin_x = self.obstacle_layer.grid.origin_x
        self._master.origin_y = self.obstacle_layer.grid.origin_y
        self._dirty = (0, 0, size_x, size_y)

    def add_scan(self, scan: LaserScan) -> None:
        """Mark and clear obstacles from one scan (ignored without an obstacle layer)."""
        if self.params.use_obstacle_layer:
            self._dirty = union_bounds(self._dirty, self.obstacle_layer.add_scan(scan))

    def update(self, robot_pose: Pose2D | None = None, scans: Iterable[LaserScan] = ()) -> None:
        """One update cycle: follow the robot (rolling window), then take in the scans."""
        if self.rolling and robot_pose is not None:
            self.update_origin(robot_pose.x, robot_pose.y)
        for scan in scans:
            self.add_scan(scan)

    def clear(self) -> None:
        """Reset the obstacle layer (clearEntireCostmap); the static layer stays."""
        self.obstacle_layer.reset()
        self._dirty = (0, 0, self._master.size_x, self._master.size_y)

    def _refresh(self) -> None:
        """Recompute the master where something changed, plus the inflation reach."""
        if self._dirty is None:
            return
        size_x, size_y = self._master.size_x, self._master.size_y
        margin = self.inflation_layer.margin_cells(self.resolution)
        x0, y0, x1, y1 = self._dirty
        # Cells that may change, and the cells whose lethal state decides them.
        wx0, wy0 = max(x0 - margin, 0), max(y0 - margin, 0)
        wx1, wy1 = min(x1 + margin, size_x), min(y1 + margin, size_y)
        ix0, iy0, ix1, iy1 = wx0 - margin, wy0 - margin, wx1 + margin, wy1 + margin
        combined = self._combined(ix0, iy0, ix1, iy1)
        inflation = self.inflation_layer.inflate(combined == LETHAL_OBSTACLE, self.resolution)
        inner = (slice(wy0 - iy0, wy1 - iy0), slice(wx0 - ix0, wx1 - ix0))
        base, inflated = combined[inner], inflation[inner]
        # Nav2's inflation update: unknown cells only take inscribed or lethal inflation.
        self._master.data[wy0:wy1, wx0:wx1] = np.where(
            base == NO_INFORMATION,
            np.where(inflated >= INSCRIBED_INFLATED_OBSTACLE, inflated, NO_INFORMATION),
            np.maximum(base, inflated),
        )
        self._dirty = None
        self.revision += 1

    def _combined(self, ix0: int, iy0: int, ix1: int, iy1: int) -> np.ndarray:
        """Static cells combined with obstacles over window cells ``[ix0, ix1) x [iy0, iy1)``.

        The rectangle may reach beyond the window: static cells come from the raster (lethal
        beyond the floor), obstacle cells there are unknown to this costmap and left out.
        """
        shape = (iy1 - iy0, ix1 - ix0)
        if self.params.use_static_layer:
            combined = self.static_layer.window(self._ix0 + ix0, self._iy0 + iy0, *shape[::-1])
        else:
            combined = np.full(shape, FREE_SPACE, dtype=np.uint8)
        if self.params.use_obstacle_layer:
            size_x, size_y = self._master.size_x, self._master.size_y
            cx0, cy0, cx1, cy1 = max(ix0, 0), max(iy0, 0), min(ix1, size_x), min(iy1, size_y)
            if cx0 < cx1 and cy0 < cy1:
                view = combined[cy0 - iy0 : cy1 - iy0, cx0 - ix0 : cx1 - ix0]
                np.maximum(view, self.obstacle_layer.grid.data[cy0:cy1, cx0:cx1], out=view)
        return combined
