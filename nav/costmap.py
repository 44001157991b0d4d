"""The 2D costmap grid: Nav2's cost values and the world <-> map transforms.

A :class:`Costmap2D` is a ``uint8`` grid in the map frame. Cell ``(ix, iy)`` covers
``[origin_x + ix * resolution, origin_x + (ix + 1) * resolution)`` along x and likewise along y;
the array is indexed ``data[iy, ix]`` (row = y), so ``data`` printed upside down is the map seen
from above. Layers fill it (:mod:`baobab.nav.layers`); the planner, the controller and the
collision checks read it.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from baobab.robots.footprint import Footprint
from baobab.sim.records import record

FREE_SPACE = 0
"""No obstacle near the cell."""
MAX_NON_OBSTACLE = 252
"""The highest cost a robot centre may occupy (Nav2's ``MAX_NON_OBSTACLE``)."""
INSCRIBED_INFLATED_OBSTACLE = 253
"""The cell is within the robot's inscribed radius of an obstacle: a circular robot collides."""
LETHAL_OBSTACLE = 254
"""An obstacle covers the cell."""
NO_INFORMATION = 255
"""Nothing is known about the cell."""

GRID = np.dtype(
    [
        ("origin_x", np.float64),  # map-frame x of the lower-left corner (m)
        ("origin_y", np.float64),  # m
        ("resolution", np.float64),  # cell side (m)
        ("inscribed_radius", np.float64),  # m
    ]
)
"""A costmap's geometry as compiled kernels read it (:meth:`Costmap2D.pack`); the cells travel
beside it as their own array."""


class CostmapArrays(NamedTuple):
    """A costmap as compiled kernels read it (:meth:`Costmap2D.arrays`)."""

    cells: np.ndarray
    """``uint8`` costs, ``[row, col]``."""
    grid: np.ndarray
    """The :data:`GRID` record."""
    outline: np.ndarray
    """``(N, 2)`` polygon footprint in ``base_link`` (m); no rows for a circle."""


class Costmap2D:
    """A grid of Nav2 cost values over a rectangle of the map frame.

    Args:
        size_x: number of cells along x.
        size_y: number of cells along y.
        resolution: cell side (m).
        origin: map-frame position (m) of the grid's lower-left corner.
        default_value: cost every cell starts with.
        inscribed_radius: the robot's inscribed radius (m) the inflation used, for consumers
            that turn costs back into distances (Regulated Pure Pursuit's cost regulation).
        footprint: the robot's footprint the collision checks lay on the cells; None or a
            circle: a robot centre collides at ``INSCRIBED_INFLATED_OBSTACLE``.
    """

    def __init__(
        self,
        size_x: int,
        size_y: int,
        resolution: float,
        origin: tuple[float, float] = (0.0, 0.0),
        default_value: int = FREE_SPACE,
        inscribed_radius: float = 0.0,
        footprint: Footprint | None = None,
    ) -> None:
        if size_x <= 0 or size_y <= 0:
            raise ValueError(f"a costmap needs at least one cell, got {size_x} x {size_y}")
        if not resolution > 0:
            raise ValueError(f"resolution must be positive, got {resolution}")
        self.resolution = float(resolution)
        self.origin_x = float(origin[0])
        self.origin_y = float(origin[1])
        self.default_value = int(default_value)
        self.inscribed_radius = float(inscribed_radius)
        self.footprint = footprint
        vertices = () if footprint is None else footprint.polygon
        self.outline = np.asarray(vertices, dtype=float).reshape(-1, 2)
        """The polygon footprint's vertices in ``base_link`` (m); no rows for a circle."""
        self.data = np.full((size_y, size_x), default_value, dtype=np.uint8)
        self._packed_key: tuple[float, float, float, float] | None = None
        self._packed = np.empty(0, dtype=GRID)

    @property
    def size_x(self) -> int:
        """Cells along x."""
        return int(self.data.shape[1])

    @property
    def size_y(self) -> int:
        """Cells along y."""
        return int(self.data.shape[0])

    @property
    def has_polygon(self) -> bool:
        """True when collisions are checked with a polygon footprint (:attr:`outline`)."""
        return len(self.outline) > 0

    @property
    def origin(self) -> tuple[float, float]:
        """Map-frame position (m) of the lower-left corner."""
        return (self.origin_x, self.origin_y)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """Covered rectangle as (x_min, y_min, x_max, y_max) in metres."""
        return (
            self.origin_x,
            self.origin_y,
            self.origin_x + self.size_x * self.resolution,
            self.origin_y + self.size_y * self.resolution,
        )

    def world_to_map(self, x: float, y: float) -> tuple[int, int] | None:
        """The cell ``(ix, iy)`` that contains map point ``(x, y)`` (m), or None outside."""
        ix = math.floor((x - self.origin_x) / self.resolution)
        iy = math.floor((y - self.origin_y) / self.resolution)
        size_y, size_x = self.data.shape
        if 0 <= ix < size_x and 0 <= iy < size_y:
            return ix, iy
        return None

    def world_to_map_array(
        self, xs: np.ndarray, ys: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Vectorised :meth:`world_to_map`: cell indices and a mask of points inside the grid.

        Indices of points outside the grid are returned unclipped; use the mask.
        """
        ix = np.floor((np.asarray(xs, dtype=float) - self.origin_x) / self.resolution)
        iy = np.floor((np.asarray(ys, dtype=float) - self.origin_y) / self.resolution)
        inside = (ix >= 0) & (ix < self.size_x) & (iy >= 0) & (iy < self.size_y)
        return ix.astype(np.int64), iy.astype(np.int64), inside

    def map_to_world(self, ix: float, iy: float) -> tuple[float, float]:
        """Map-frame centre (m) of cell ``(ix, iy)``."""
        return (
            self.origin_x + (ix + 0.5) * self.resolution,
            self.origin_y + (iy + 0.5) * self.resolution,
        )

    def map_to_world_array(self, ix: np.ndarray, iy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Vectorised :meth:`map_to_world`."""
        return (
            self.origin_x + (np.asarray(ix) + 0.5) * self.resolution,
            self.origin_y + (np.asarray(iy) + 0.5) * self.resolution,
        )

    def contains(self, x: float, y: float) -> bool:
        """True when map point ``(x, y)`` (m) lies on the grid."""
        return self.world_to_map(x, y) is not None

    def cost(self, x: float, y: float, outside: int = NO_INFORMATION) -> int:
        """Cost of the cell under map point ``(x, y)`` (m); ``outside`` beyond the grid."""
        cell = self.world_to_map(x, y)
        if cell is None:
            return outside
        return int(self.data.item(cell[1], cell[0]))

    def costs(self, xs: np.ndarray, ys: np.ndarray, outside: int = NO_INFORMATION) -> np.ndarray:
        """Vectorised :meth:`cost` (``uint8`` array shaped like ``xs``)."""
        ix, iy, inside = self.world_to_map_array(xs, ys)
        result = np.full(np.shape(ix), outside, dtype=np.uint8)
        result[inside] = self.data[iy[inside], ix[inside]]
        return result

    def pack(self) -> np.ndarray:
        """The geometry as a :data:`GRID` record (:mod:`baobab.sim.records`); read only.

        Built again only when the geometry changed (a rolling window moves its origin).
        """
        key = (self.origin_x, self.origin_y, self.resolution, self.inscribed_radius)
        if key != self._packed_key:
            self._packed, self._packed_key = record(GRID, self), key
        return self._packed

    def arrays(self) -> CostmapArrays:
        """The cells, geometry and footprint as one :class:`CostmapArrays` (no copies)."""
        return CostmapArrays(self.data, self.pack(), self.outline)

    def copy(self) -> Costmap2D:
        """An independent copy (geometry, metadata and cells)."""
        twin = Costmap2D(
            self.size_x,
            self.size_y,
            self.resolution,
            self.origin,
            self.default_value,
            self.inscribed_radius,
            self.footprint,
        )
        twin.data[:] = self.data
        return twin

    def __repr__(self) -> str:
        return (
            f"Costmap2D({self.size_x} x {self.size_y} cells of {self.resolution} m, "
            f"origin ({self.origin_x:.3f}, {self.origin_y:.3f}))"
        )
