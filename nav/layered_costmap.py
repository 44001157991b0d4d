"""Layered costmaps: the global one over the whole map and the local rolling window.

A :class:`LayeredCostmap` combines a static layer (the world's geometry), an obstacle layer
(lidar) and an inflation layer into one master :class:`~baobab.nav.costmap.Costmap2D`, the way
Nav2's ``Costmap2DROS`` does: static cells first, then the obstacle layer's over them (Nav2's
``updateWithMax``: a lidar hit is lethal on any static cell, an unknown one included), then
inflation. Updates are incremental and lazy: a scan records the cells whose combined value it
changed, a rolling window's move shifts the master and records the cells that entered, and the
master is recomputed only there (plus the inflation radius around changed cells) and only when
someone reads it.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from baobab.nav.costmap import FREE_SPACE, Costmap2D
from baobab.nav.costmap_filters import KeepoutFilter
from baobab.nav.layers import (
    Bounds,
    InflationLayer,
    InflationParams,
    ObstacleLayer,
    ObstacleParams,
    StaticLayer,
    union_bounds,
)
from baobab.nav.static_map import StaticLayerParams
from baobab.nav.window_kernels import (
    WINDOW,
    Layers,
    Scratch,
    base_change_bounds,
    dropped_base_bounds,
    refresh_window,
    refresh_window_static,
    shift_grid,
)
from baobab.robots.catalog import default_mobile_robot
from baobab.robots.footprint import Footprint
from baobab.sim.lidar import LaserScan
from baobab.sim.records import record
from baobab.sim.world import Pose2D, World

_ROBOT = default_mobile_robot().tuning
"""The default mobile robot's settings (:mod:`baobab.robots.tuning`), for costmaps built
without a robot's (:func:`baobab.nav.robot_params.navigation_params`)."""


@dataclass(frozen=True)
class CostmapParams:
    """Costmap settings (m, 1/m): Nav2's defaults with a robot's footprint and inflation.

    ``footprint`` is Nav2's ``robot_radius`` or padded ``footprint`` polygon; its inscribed
    radius is the inflation layer's.
    """

    resolution: float = 0.05
    footprint: Footprint = _ROBOT.footprint
    inflation_radius: float = _ROBOT.inflation_radius
    cost_scaling_factor: float = _ROBOT.cost_scaling_factor
    obstacle: ObstacleParams = field(default_factory=ObstacleParams)
    static: StaticLayerParams = field(default_factory=StaticLayerParams)
    use_static_layer: bool = True
    use_obstacle_layer: bool = True

    @property
    def robot_radius(self) -> float:
        """The footprint's inscribed radius (m)."""
        return self.footprint.inscribed_radius

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
        keepout: a keepout filter on the static layer's lattice, applied last.
    """

    def __init__(
        self,
        static: StaticLayer,
        window: tuple[int, int, int, int],
        rolling: bool,
        params: CostmapParams | None = None,
        keepout: KeepoutFilter | None = None,
    ) -> None:
        self.params = params or CostmapParams()
        self.static_layer = static
        self.keepout = keepout
        self._in_keepout = False
        self.rolling = rolling
        ix0, iy0, size_x, size_y = window
        self._ix0, self._iy0 = ix0, iy0
        res = static.resolution
        origin = (static.origin_x + ix0 * res, static.origin_y + iy0 * res)
        self._master = Costmap2D(
            size_x,
            size_y,
            res,
            origin,
            inscribed_radius=self.params.robot_radius,
            footprint=self.params.footprint,
        )
        obstacle_grid = Costmap2D(size_x, size_y, res, origin)
        self.obstacle_layer = ObstacleLayer(obstacle_grid, self.params.obstacle)
        self.inflation_layer = InflationLayer(self.params.inflation)
        self.revision = 0
        # Pending work: cells whose combined value changed (their inflation reach changes too)
        # and cells to recompute by themselves (entered a rolling window).
        self._changed: list[Bounds] = []
        self._stale: list[Bounds] = [(0, 0, size_x, size_y)]
        self._bounds = np.zeros(4, dtype=np.int64)
        margin = self.inflation_layer.margin_cells(res)
        scratch = (size_y + 2 * margin, size_x + 2 * margin)
        self._scratch = Scratch(
            gap=np.empty(scratch, dtype=np.int32),
            base=np.empty(scratch, dtype=np.uint8),
            costs=np.empty(scratch, dtype=np.uint8),
        )
        self._no_static_costs = np.zeros((1, 1), dtype=np.uint8)
        self._static_inflation: np.ndarray | None = None
        self._window_record = np.empty(0, dtype=WINDOW)
        self._window_key: tuple[int, int] | None = None
        self._layers: Layers | None = None

    @classmethod
    def global_costmap(
        cls,
        world: World,
        params: CostmapParams | None = None,
        static: StaticLayer | None = None,
        keepout: KeepoutFilter | None = None,
    ) -> LayeredCostmap:
        """The costmap over the whole floor (and its lethal border), or over the map."""
        params = params or CostmapParams()
        static = static or StaticLayer(world, params.resolution, params=params.static)
        window = (0, 0, static.size_x, static.size_y)
        return cls(static, window, rolling=False, params=params, keepout=keepout)

    @classmethod
    def local_costmap(
        cls,
        world: World,
        center: Pose2D,
        params: CostmapParams | None = None,
        size: tuple[float, float] = (3.0, 3.0),
        static: StaticLayer | None = None,
        keepout: KeepoutFilter | None = None,
    ) -> LayeredCostmap:
        """A rolling window of ``size`` (m), Nav2's 3 m x 3 m by default, centred on ``center``.

        Unlike Nav2's bringup (obstacle and inflation layers only) the window keeps the static
        layer by default: localisation is perfect here, and the floor's edge is invisible to
        the lidar. ``CostmapParams(use_static_layer=False)`` gives Nav2's local layers.
        """
        params = params or CostmapParams()
        static = static or StaticLayer(world, params.resolution, params=params.static)
        size_x = round(size[0] / static.resolution)
        size_y = round(size[1] / static.resolution)
        costmap = cls(static, (0, 0, size_x, size_y), rolling=True, params=params, keepout=keepout)
        costmap.update_origin(center.x, center.y)
        return costmap

    @property
    def costmap(self) -> Costmap2D:
        """The master costmap, brought up to date with every change so far (recomputed only
        when a layer changed since it was last read: the controller reads it at 20 Hz, the
        scans and the window's moves change it at 5 Hz)."""
        if self._changed or self._stale:
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
        if abs(dix) >= size_x or abs(diy) >= size_y:
            self._changed, self._stale = [], [(0, 0, size_x, size_y)]
        else:
            self._shift_master(dix, diy)
        self.obstacle_layer.shift(dix, diy)
        self._ix0, self._iy0 = ix0, iy0
        self._master.origin_x = self.obstacle_layer.grid.origin_x
        self._master.origin_y = self.obstacle_layer.grid.origin_y

    def add_scan(self, scan: LaserScan) -> None:
        """Mark and clear obstacles from one scan (ignored without an obstacle layer)."""
        if not self.params.use_obstacle_layer:
            return
        if self.obstacle_layer.add_scan(scan) is None:
            return
        index, old = self.obstacle_layer.last_changes
        grid, raster = self.obstacle_layer.grid.data, self.static_layer.raster
        if base_change_bounds(grid, raster, self._window(), index, old, self._bounds):
            b = self._bounds
            self._changed.append((int(b[0]), int(b[1]), int(b[2]), int(b[3])))

    def _window(self) -> np.ndarray:
        """The window's placement and layers as the kernels' :data:`WINDOW` record (built
        again when the window moved; read only)."""
        if self._window_key != (self._ix0, self._iy0):
            params, resolution = self.params, self.resolution
            self._window_key = (self._ix0, self._iy0)
            self._window_record = record(
                WINDOW,
                raster_x0=self._ix0,
                raster_y0=self._iy0,
                use_static=params.use_static_layer,
                use_obstacle=params.use_obstacle_layer,
                margin=self.inflation_layer.margin_cells(resolution),
                reach=self.inflation_layer.cost_table(resolution)[1],
            )
        return self._window_record

    def update(self, robot_pose: Pose2D | None = None, scans: Iterable[LaserScan] = ()) -> None:
        """One update cycle: follow the robot (rolling window), then take in the scans."""
        if robot_pose is not None:
            if self.rolling:
                self.update_origin(robot_pose.x, robot_pose.y)
            self._locate_keepout(robot_pose)
        for scan in scans:
            self.add_scan(scan)

    def _locate_keepout(self, robot_pose: Pose2D) -> None:
        """Whether the robot stands in a keepout zone; on a change, redo the zone's cells."""
        keepout = self.keepout
        if keepout is None or keepout.bounds is None:
            return
        res = self.resolution
        lattice_x = math.floor((robot_pose.x - self.static_layer.origin_x) / res)
        lattice_y = math.floor((robot_pose.y - self.static_layer.origin_y) / res)
        inside = keepout.overrides_at(lattice_x, lattice_y)
        if inside == self._in_keepout:
            return
        self._in_keepout = inside
        x0, y0, x1, y1 = keepout.bounds
        self._stale.append((x0 - self._ix0, y0 - self._iy0, x1 - self._ix0, y1 - self._iy0))

    def clear(self) -> None:
        """Reset the obstacle layer (clearEntireCostmap); the static layer stays."""
        self.obstacle_layer.reset()
        self._changed, self._stale = [], [(0, 0, self._master.size_x, self._master.size_y)]

    def clear_region(self, x: float, y: float, reset_distance: float, *, inside: bool) -> None:
        """Clear the obstacle layer in (or outside) a square, as Nav2's clearing services do.

        The square has side ``reset_distance`` (m) and is centred on map point ``(x, y)``: its
        corners fall in cells ``start`` and ``end`` (Nav2's ``worldToMapNoBounds``, which
        truncates towards zero), and the cells strictly between them along both axes are
        inside. ``inside`` clears those (``clear_around_*``); otherwise every other cell is
        cleared (``clear_except_*``). The static layer stays.
        """
        grid = self.obstacle_layer.grid
        res = grid.resolution
        start_x, start_y = x - reset_distance / 2, y - reset_distance / 2
        first_x = int((start_x - grid.origin_x) / res)
        first_y = int((start_y - grid.origin_y) / res)
        last_x = int((start_x + reset_distance - grid.origin_x) / res)
        last_y = int((start_y + reset_distance - grid.origin_y) / res)
        columns = np.arange(grid.size_x)
        rows = np.arange(grid.size_y)
        in_x = (columns > first_x) & (columns < last_x)
        in_y = (rows > first_y) & (rows < last_y)
        square = in_y[:, None] & in_x[None, :]
        grid.data[square if inside else ~square] = FREE_SPACE
        self._changed, self._stale = [], [(0, 0, self._master.size_x, self._master.size_y)]

    def _shift_master(self, dix: int, diy: int) -> None:
        """Move the master by whole cells, keeping what stays valid, before the obstacles move.

        A kept cell keeps its value: its static and obstacle neighbours move with it, except
        obstacles that leave the window (recorded as changed cells, outside the new window) and
        cells that enter it (free of obstacles, and their static cells counted already).
        """
        size_x, size_y = self._master.size_x, self._master.size_y
        grid, raster = self.obstacle_layer.grid.data, self.static_layer.raster
        window = self._window()
        if self.params.use_obstacle_layer and dropped_base_bounds(
            grid, raster, window, dix, diy, self._bounds
        ):
            b = self._bounds
            self._changed.append((int(b[0]), int(b[1]), int(b[2]), int(b[3])))
        shift_grid(self._master.data, dix, diy, FREE_SPACE)
        if self._changed:
            self._changed = [(a - dix, b - diy, c - dix, d - diy) for a, b, c, d in self._changed]
        if self._stale:
            self._stale = [(a - dix, b - diy, c - dix, d - diy) for a, b, c, d in self._stale]
        if dix > 0:
            self._stale.append((size_x - dix, 0, size_x, size_y))
        elif dix < 0:
            self._stale.append((0, 0, -dix, size_y))
        if diy > 0:
            self._stale.append((0, size_y - diy, size_x, size_y))
        elif diy < 0:
            self._stale.append((0, 0, size_x, -diy))

    def _static_costs(self, table: np.ndarray, reach: int) -> np.ndarray | None:
        """The static layer's own inflation, when the master may be built on it (else None).

        The cost of the nearest of two lethal sets is the larger of their costs only when the
        cost never rises with the distance.
        """
        if not self.inflation_layer.cost_falls_with_distance(self.resolution):
            return None
        if not self.params.use_static_layer:
            return self._no_static_costs
        if self._static_inflation is None:
            self._static_inflation = self.static_layer.inflation_costs(table, reach)
        return self._static_inflation

    def _refresh(self) -> None:
        """Recompute the master where something changed, plus the inflation reach."""
        size_x, size_y = self._master.size_x, self._master.size_y
        margin = self.inflation_layer.margin_cells(self.resolution)
        table, reach = self.inflation_layer.cost_table(self.resolution)
        grown = [
            (x0 - margin, y0 - margin, x1 + margin, y1 + margin) for x0, y0, x1, y1 in self._changed
        ]
        rects: list[Bounds] = []
        for x0, y0, x1, y1 in grown + self._stale:
            rect = (max(x0, 0), max(y0, 0), min(x1, size_x), min(y1, size_y))
            if rect[0] < rect[2] and rect[1] < rect[3]:
                rects = _merge_rect(rects, rect, margin)
        static_costs = self._static_costs(table, reach)
        if self._layers is None or self._layers.table is not table:
            self._layers = Layers(
                master=self._master.data,
                raster=self.static_layer.raster,
                obstacle=self.obstacle_layer.grid.data,
                table=table,
            )
        layers = self._layers
        window = self._window()
        for rect in rects:
            if static_costs is not None:
                refresh_window_static(layers, static_costs, window, rect, self._scratch.costs)
            else:
                refresh_window(layers, window, rect, self._scratch)
        if self.keepout is not None:
            master = self._master.data
            for x0, y0, x1, y1 in rects:
                self.keepout.apply(
                    master[y0:y1, x0:x1], self._ix0 + x0, self._iy0 + y0, self._in_keepout
                )
        self._changed, self._stale = [], []
        self.revision += 1


def _merge_rect(rects: list[Bounds], rect: Bounds, margin: int) -> list[Bounds]:
    """Add ``rect`` to ``rects``, merged with those whose bounding box costs less to refresh.

    Refreshing a rectangle reads it grown by ``margin`` on every side; two rectangles are
    refreshed as their bounding box when that reads no more cells than both apart. Overlapping
    rectangles that stay apart are refreshed twice where they overlap, which is harmless.
    """

    def cost(r: Bounds) -> int:
        return (r[2] - r[0] + 2 * margin) * (r[3] - r[1] + 2 * margin)

    merged = rect
    grew = True
    while grew:
        grew = False
        apart = []
        for other in rects:
            box = union_bounds(merged, other) or merged
            if cost(box) <= cost(merged) + cost(other):
                merged = box
                grew = True
            else:
                apart.append(other)
        rects = apart
    return [*rects, merged]
