"""Costmap layers: static (world geometry), obstacle (lidar marking and clearing), inflation.

Each layer works on whole arrays, with numpy or compiled (numba) kernels for ray tracing and
the distance transform; there is no per-cell Python loop. The layers share one cell lattice:
cell ``(i, j)`` of the lattice is the square
``[origin_x + i * res, origin_x + (i + 1) * res) x [origin_y + j * res, ...)`` of the static
raster, and a rolling window is a rectangle of whole lattice cells, so its static cells are a
slice of the raster.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from baobab.nav.costmap import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    MAX_NON_OBSTACLE,
    Costmap2D,
)
from baobab.nav.raytrace_kernels import OBSTACLE_RANGES, RayTracer, cell_thresholds, trace_scan
from baobab.nav.static_map import StaticLayerParams, map_costs
from baobab.nav.window_kernels import inflation_costs, shift_grid
from baobab.robots.catalog import default_mobile_robot
from baobab.sim.errors import BaobabError
from baobab.sim.lidar import LaserScan
from baobab.sim.records import record
from baobab.sim.world import MAX_COSTMAP_CELLS, Box, Cylinder, World

# Touching is not overlapping: a box whose face lies on a cell boundary leaves the next cell free.
_TOUCH_EPS = 1e-9

Bounds = tuple[int, int, int, int]
"""A rectangle of cells ``(ix_min, iy_min, ix_max, iy_max)``, max exclusive."""


def union_bounds(a: Bounds | None, b: Bounds | None) -> Bounds | None:
    """The smallest cell rectangle holding both (None is empty)."""
    if a is None:
        return b
    if b is None:
        return a
    return (min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3]))


class CostmapSizeError(BaobabError):
    """A costmap with more than :data:`~baobab.sim.world.MAX_COSTMAP_CELLS` cells."""


class StaticLayer:
    """The world's fixed geometry rasterised once: a cell is lethal when an obstacle overlaps it.

    On a world that stands on a map, the raster is the map itself, read as Nav2's static layer
    reads it (:func:`~baobab.nav.static_map.map_costs`): the map's cells, resolution and
    origin, no border; the world's own boxes and cylinders are rasterised on top.

    Boxes (with yaw) and cylinders are lethal where they overlap a cell with positive area
    (an exact separating-axis test, not a centre sample); every cell not wholly on the floor is
    lethal, so the floor edge keeps the robot on the floor. The raster covers the floor plus
    ``margin_cells`` of lethal border; cells beyond it read as lethal too.

    Args:
        world: the world to rasterise.
        resolution: cell side (m); Nav2's 0.05 by default (a map's own on a map).
        margin_cells: lethal cells kept around the floor (none around a map).
        params: how a map's values become costs.

    Raises:
        CostmapSizeError: more than ``MAX_COSTMAP_CELLS`` cells (a resolution finer than the
            0.05 m the world was checked at).
    """

    def __init__(
        self,
        world: World,
        resolution: float = 0.05,
        margin_cells: int = 1,
        params: StaticLayerParams | None = None,
    ) -> None:
        self._inflated_key: tuple[bytes, int] | None = None
        self._inflated = np.empty((0, 0), dtype=np.uint8)
        grid = world.grid
        if grid is not None:
            self.resolution = grid.resolution
            self.origin_x, self.origin_y = grid.origin
            self.raster = map_costs(grid.data, params)
            self._rasterise_obstacles(world)
            return
        x_min, y_min, x_max, y_max = world.bounds
        self.resolution = float(resolution)
        self.origin_x = x_min - margin_cells * resolution
        self.origin_y = y_min - margin_cells * resolution
        floor_x = math.ceil(round((x_max - x_min) / resolution, 9))
        floor_y = math.ceil(round((y_max - y_min) / resolution, 9))
        if floor_x * floor_y > MAX_COSTMAP_CELLS:  # a finer resolution than the world checked
            raise CostmapSizeError(
                f"a costmap of world '{world.name}' at {resolution:g} m would have "
                f"{floor_x * floor_y:,} cells; the limit is {MAX_COSTMAP_CELLS:,} "
                "(MAX_COSTMAP_CELLS)"
            )
        size_x, size_y = floor_x + 2 * margin_cells, floor_y + 2 * margin_cells
        self.raster = np.full((size_y, size_x), FREE_SPACE, dtype=np.uint8)
        half = resolution / 2
        centres_x = self.origin_x + (np.arange(size_x) + 0.5) * resolution
        centres_y = self.origin_y + (np.arange(size_y) + 0.5) * resolution
        off_x = (centres_x - half < x_min - _TOUCH_EPS) | (centres_x + half > x_max + _TOUCH_EPS)
        off_y = (centres_y - half < y_min - _TOUCH_EPS) | (centres_y + half > y_max + _TOUCH_EPS)
        self.raster[off_y[:, None] | off_x[None, :]] = LETHAL_OBSTACLE
        self._rasterise_obstacles(world)

    def _rasterise_obstacles(self, world: World) -> None:
        for box in [*world.boxes, *world.dock_boxes]:
            self._rasterise_box(box)
        for cylinder in world.cylinders:
            self._rasterise_cylinder(cylinder)

    @property
    def size_x(self) -> int:
        """Raster cells along x."""
        return int(self.raster.shape[1])

    @property
    def size_y(self) -> int:
        """Raster cells along y."""
        return int(self.raster.shape[0])

    def lattice_index(self, x: float, y: float) -> tuple[int, int]:
        """Lattice cell (unbounded) whose lower-left corner is nearest to ``(x, y)`` (m)."""
        return (
            round((x - self.origin_x) / self.resolution),
            round((y - self.origin_y) / self.resolution),
        )

    def window(self, ix0: int, iy0: int, size_x: int, size_y: int) -> np.ndarray:
        """Raster cells ``[iy0, iy0 + size_y) x [ix0, ix0 + size_x)``; lethal beyond the raster."""
        out = np.full((size_y, size_x), LETHAL_OBSTACLE, dtype=np.uint8)
        sx0, sy0 = max(ix0, 0), max(iy0, 0)
        sx1, sy1 = min(ix0 + size_x, self.size_x), min(iy0 + size_y, self.size_y)
        if sx0 < sx1 and sy0 < sy1:
            out[sy0 - iy0 : sy1 - iy0, sx0 - ix0 : sx1 - ix0] = self.raster[sy0:sy1, sx0:sx1]
        return out

    def inflation_costs(self, table: np.ndarray, reach: int) -> np.ndarray:
        """The raster's own inflation costs (cells beyond it lethal), computed once per table.

        Args:
            table: cost by squared cell distance (see :meth:`InflationLayer.cost_table`).
            reach: cells beyond which the table is free.
        """
        key = (table.tobytes(), reach)
        if self._inflated_key != key:
            pad = reach + 1
            lethal = np.pad(self.raster == LETHAL_OBSTACLE, pad, constant_values=True)
            costs = inflation_costs(lethal, reach, table)
            self._inflated = np.ascontiguousarray(costs[pad:-pad, pad:-pad])
            self._inflated_key = key
        return self._inflated

    def _cell_window(
        self, x0: float, y0: float, x1: float, y1: float
    ) -> tuple[slice, slice, np.ndarray, np.ndarray] | None:
        """Raster slices and cell-centre grids of the cells meeting ``[x0, x1] x [y0, y1]``."""
        res = self.resolution
        i0 = max(math.floor((x0 - self.origin_x) / res) - 1, 0)
        j0 = max(math.floor((y0 - self.origin_y) / res) - 1, 0)
        i1 = min(math.ceil((x1 - self.origin_x) / res) + 1, self.size_x)
        j1 = min(math.ceil((y1 - self.origin_y) / res) + 1, self.size_y)
        if i0 >= i1 or j0 >= j1:
            return None
        cx = self.origin_x + (np.arange(i0, i1) + 0.5) * res
        cy = self.origin_y + (np.arange(j0, j1) + 0.5) * res
        return slice(j0, j1), slice(i0, i1), cx[None, :], cy[:, None]

    def _rasterise_box(self, box: Box) -> None:
        a, b = box.size[0] / 2, box.size[1] / 2
        c, s = abs(math.cos(box.yaw)), abs(math.sin(box.yaw))
        extent_x, extent_y = a * c + b * s, a * s + b * c
        bx, by = box.center
        found = self._cell_window(bx - extent_x, by - extent_y, bx + extent_x, by + extent_y)
        if found is None:
            return
        rows, cols, cx, cy = found
        h = self.resolution / 2
        dx, dy = cx - bx, cy - by
        cos_yaw, sin_yaw = math.cos(box.yaw), math.sin(box.yaw)
        # Separating axes of a rotated rectangle and an axis-aligned square: x, y, u, v.
        overlap = (
            (np.abs(dx) < h + extent_x - _TOUCH_EPS)
            & (np.abs(dy) < h + extent_y - _TOUCH_EPS)
            & (np.abs(dx * cos_yaw + dy * sin_yaw) < a + h * (c + s) - _TOUCH_EPS)
            & (np.abs(-dx * sin_yaw + dy * cos_yaw) < b + h * (c + s) - _TOUCH_EPS)
        )
        self.raster[rows, cols][overlap] = LETHAL_OBSTACLE

    def _rasterise_cylinder(self, cylinder: Cylinder) -> None:
        ox, oy, r = cylinder.center[0], cylinder.center[1], cylinder.radius
        found = self._cell_window(ox - r, oy - r, ox + r, oy + r)
        if found is None:
            return
        rows, cols, cx, cy = found
        h = self.resolution / 2
        # Distance from the circle's centre to the nearest point of each cell square.
        gap_x = np.maximum(np.abs(cx - ox) - h, 0.0)
        gap_y = np.maximum(np.abs(cy - oy) - h, 0.0)
        overlap = gap_x**2 + gap_y**2 < (r - _TOUCH_EPS) ** 2
        self.raster[rows, cols][overlap] = LETHAL_OBSTACLE


@dataclass(frozen=True)
class ObstacleParams:
    """Obstacle layer ranges (m), Nav2's defaults."""

    obstacle_max_range: float = 2.5
    obstacle_min_range: float = 0.0
    raytrace_max_range: float = 3.0
    raytrace_min_range: float = 0.0

    def pack(self) -> np.ndarray:
        """These ranges as the kernel's :data:`~baobab.nav.raytrace_kernels.OBSTACLE_RANGES`."""
        return record(OBSTACLE_RANGES, self)


class ObstacleLayer:
    """Obstacles seen by the lidar: hits mark cells lethal, beams clear the cells they cross.

    Per scan, every beam first clears the cells from the sensor up to its hit (the hit cell
    itself excluded) or, for a beam that hit nothing, up to ``raytrace_max_range``; then every
    hit closer than ``obstacle_max_range`` marks its cell lethal. So an obstacle that appears
    is marked and one that leaves is cleared by the beams that now pass through. A beam is
    sampled every half cell; the cells of its samples are the cells it crosses.

    Args:
        grid: the layer's own cells; its geometry is the costmap's.
        params: marking and clearing ranges.
    """

    def __init__(self, grid: Costmap2D, params: ObstacleParams | None = None) -> None:
        self.grid = grid
        self.params = params or ObstacleParams()
        cells = grid.size_x * grid.size_y
        self._ranges = self.params.pack()
        self._tracer = RayTracer(
            threshold_x=cell_thresholds(grid.size_x, grid.resolution),
            threshold_y=cell_thresholds(grid.size_y, grid.resolution),
            samples=np.arange(
                max(self.params.raytrace_min_range, 0.0),
                self.params.raytrace_max_range,
                grid.resolution / 2,
            ),
            touched=np.zeros(grid.data.shape, dtype=np.uint8),
            changed_index=np.empty(cells, dtype=np.int64),
            changed_old=np.empty(cells, dtype=np.uint8),
            bounds=np.zeros(4, dtype=np.int64),
        )
        self._changed_count = 0

    @property
    def last_changes(self) -> tuple[np.ndarray, np.ndarray]:
        """Cells the last :meth:`add_scan` changed: indices ``iy * size_x + ix``, old values."""
        count = self._changed_count
        return self._tracer.changed_index[:count], self._tracer.changed_old[:count]

    def reset(self) -> None:
        """Forget every obstacle (Nav2's clear-costmap service on this layer)."""
        self.grid.data[:] = FREE_SPACE
        self._changed_count = 0

    def shift(self, dix: int, diy: int) -> None:
        """Move the grid by whole cells (rolling window); cells entering the window are free."""
        shift_grid(self.grid.data, dix, diy, FREE_SPACE)
        self.grid.origin_x += dix * self.grid.resolution
        self.grid.origin_y += diy * self.grid.resolution
        self._changed_count = 0

    def add_scan(self, scan: LaserScan) -> Bounds | None:
        """Clear along every beam, then mark the hits.

        Returns:
            The bounds of the cells whose value changed, None when none did (so a scan of an
            unchanged scene costs the costmap no inflation update).
        """
        self._changed_count = 0
        ranges = np.ascontiguousarray(scan.ranges, dtype=np.float64)
        if ranges.size == 0:
            return None
        grid = self.grid
        count = trace_scan(grid.data, grid.pack(), scan.pack(), ranges, self._ranges, self._tracer)
        self._changed_count = count
        if count == 0:
            return None
        x0, y0, x1, y1 = self._tracer.bounds.tolist()
        return (x0, y0, x1, y1)


@dataclass(frozen=True)
class InflationParams:
    """Inflation around lethal cells (m, 1/m): a robot's inscribed radius (the default mobile
    robot's unless :class:`~baobab.nav.layered_costmap.CostmapParams` gives one) and Nav2
    Humble's defaults."""

    inscribed_radius: float = default_mobile_robot().tuning.footprint.inscribed_radius
    inflation_radius: float = 0.55
    cost_scaling_factor: float = 3.0


class InflationLayer:
    """Nav2's inflation: cost falls off exponentially with the distance to the nearest lethal cell.

    For the distance ``d`` (m) between cell centres: 254 at ``d = 0``, 253 for
    ``d <= inscribed_radius``, ``floor(252 * exp(-k * (d - inscribed_radius)))`` up to
    ``inflation_radius``, 0 beyond. Distances are exact (compiled, separable: the vertical
    distance to the nearest lethal cell of each column, then the nearest over the columns
    within the inflation radius), the same numbers as ``scipy.ndimage.distance_transform_edt``.
    """

    def __init__(self, params: InflationParams | None = None) -> None:
        self.params = params or InflationParams()
        self._table: np.ndarray | None = None
        self._table_resolution = 0.0
        self._reach = 0
        self._monotone = True

    def cost_of_distance(self, distance: np.ndarray) -> np.ndarray:
        """Inflation cost (``uint8``) at the given distances (m) from the nearest lethal cell."""
        p = self.params
        d = np.asarray(distance, dtype=float)
        decay = MAX_NON_OBSTACLE * np.exp(-p.cost_scaling_factor * (d - p.inscribed_radius))
        cost = np.where(d <= p.inflation_radius + 1e-9, np.floor(decay), FREE_SPACE)
        cost = np.where(d <= p.inscribed_radius + 1e-9, INSCRIBED_INFLATED_OBSTACLE, cost)
        cost = np.where(d <= 0.0, LETHAL_OBSTACLE, cost)
        return cost.astype(np.uint8)

    def inflate(self, lethal: np.ndarray, resolution: float) -> np.ndarray:
        """Inflation cost of every cell of a window given its lethal cells (bool array)."""
        if not lethal.any():
            return np.zeros(lethal.shape, dtype=np.uint8)
        table, reach = self.cost_table(resolution)
        return inflation_costs(np.ascontiguousarray(lethal), reach, table)

    def cost_table(self, resolution: float) -> tuple[np.ndarray, int]:
        """Cost by squared cell distance, and the reach (cells) beyond which the cost is free.

        Squared distances between cell centres are whole numbers of cells squared, so the cost
        is a table lookup instead of an exp() per cell. The table's last entry, the first
        square beyond :meth:`margin_cells`, is free and stands for every larger distance; so
        is every entry beyond ``reach^2``.
        """
        if self._table is None or self._table_resolution != resolution:
            margin = self.margin_cells(resolution)
            squared = np.arange((margin + 1) ** 2 + 1)
            table = self.cost_of_distance(np.sqrt(squared) * resolution)
            table[-1] = FREE_SPACE
            # reach: the least r with r^2 >= every squared distance of non-zero cost.
            farthest = int(np.flatnonzero(table)[-1])
            reach = math.isqrt(farthest - 1) + 1 if farthest > 0 else 0
            self._table, self._reach = table, min(reach, margin)
            self._monotone = bool(np.all(np.diff(table.astype(np.int64)) <= 0))
            self._table_resolution = resolution
        return self._table, self._reach

    def cost_falls_with_distance(self, resolution: float) -> bool:
        """Whether the cost table never rises with the distance (true for positive scaling)."""
        self.cost_table(resolution)
        return self._monotone

    def margin_cells(self, resolution: float) -> int:
        """How many cells a lethal cell's inflation reaches."""
        return math.ceil(self.params.inflation_radius / resolution - 1e-9)
