"""``nav2_simple_commander.costmap_2d``: ``PyCostmap2D``, Nav2's Python view of a costmap.

A :class:`PyCostmap2D` wraps a ``nav2_msgs/Costmap`` (what ``getGlobalCostmap()`` returns)
or one of baobab's :class:`~baobab.nav.costmap.Costmap2D` grids, with Nav2's conversions:

* ``mapToWorld(mx, my)`` is the centre of the cell: ``origin + (m + 0.5) * resolution``;
* ``worldToMapValidated(wx, wy)`` is ``floor((w - origin) / resolution)`` per axis, or
  ``(None, None)`` for a point below the origin or beyond the grid;
* ``getIndex(mx, my)`` is ``my * size_x + mx``, the row-major index of the message's data.

Costs are ``numpy.uint8``: 0 free, 253 inscribed, 254 lethal, 255 unknown. Indices are not
range-checked beyond what numpy does, as in Nav2.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from baobab.nav.costmap import Costmap2D
from baobab.nav.msgs import Costmap, TimeMsg

__all__ = ["PyCostmap2D"]


class GridView:
    """The cell geometry and cost access shared by ``PyCostmap2D`` and ``PyOccupancyGrid``.

    Args:
        size_x: cells along x.
        size_y: cells along y.
        resolution: cell side (m).
        origin: map-frame position (m) of the lower-left corner of cell (0, 0).
        frame_id: the frame the grid is in.
        stamp: when the grid was made.
        cells: the row-major cell values.
    """

    def __init__(
        self,
        size_x: int,
        size_y: int,
        resolution: float,
        origin: tuple[float, float],
        frame_id: str,
        stamp: TimeMsg,
        cells: np.ndarray,
    ) -> None:
        self.size_x = int(size_x)
        self.size_y = int(size_y)
        self.resolution = float(resolution)
        self.origin_x, self.origin_y = float(origin[0]), float(origin[1])
        self.global_frame_id = frame_id
        self.costmap_timestamp = stamp
        self.costmap = cells

    def getSizeInCellsX(self) -> int:
        """Cells along x."""
        return self.size_x

    def getSizeInCellsY(self) -> int:
        """Cells along y."""
        return self.size_y

    def getSizeInMetersX(self) -> float:
        """Extent along x (m)."""
        return self.size_x * self.resolution

    def getSizeInMetersY(self) -> float:
        """Extent along y (m)."""
        return self.size_y * self.resolution

    def getOriginX(self) -> float:
        """x (m) of the grid's lower-left corner."""
        return self.origin_x

    def getOriginY(self) -> float:
        """y (m) of the grid's lower-left corner."""
        return self.origin_y

    def getResolution(self) -> float:
        """Cell side (m)."""
        return self.resolution

    def getGlobalFrameID(self) -> str:
        """The grid's frame."""
        return self.global_frame_id

    def getCostmapTimestamp(self) -> TimeMsg:
        """When the grid was made."""
        return self.costmap_timestamp

    def getIndex(self, mx: int, my: int) -> int:
        """Row-major index of cell ``(mx, my)``."""
        return my * self.size_x + mx

    def getCostXY(self, mx: int, my: int) -> Any:
        """Value of cell ``(mx, my)``."""
        return self.costmap.dtype.type(self.costmap[self.getIndex(mx, my)])

    def getCostIdx(self, index: int) -> Any:
        """Value of the cell at row-major ``index``."""
        return self.costmap.dtype.type(self.costmap[index])

    def setCost(self, mx: int, my: int, cost: int) -> None:
        """Set the value of cell ``(mx, my)``."""
        self.costmap[self.getIndex(mx, my)] = cost

    def mapToWorld(self, mx: int, my: int) -> tuple[float, float]:
        """Map-frame centre (m) of cell ``(mx, my)``."""
        return (
            self.origin_x + (mx + 0.5) * self.resolution,
            self.origin_y + (my + 0.5) * self.resolution,
        )

    def worldToMapValidated(self, wx: float, wy: float) -> tuple[int, int] | tuple[None, None]:
        """The cell containing map point ``(wx, wy)`` (m), or ``(None, None)`` off the grid."""
        if wx < self.origin_x or wy < self.origin_y:
            return (None, None)
        mx = int((wx - self.origin_x) // self.resolution)
        my = int((wy - self.origin_y) // self.resolution)
        if mx < self.size_x and my < self.size_y:
            return (mx, my)
        return (None, None)


class PyCostmap2D(GridView):
    """A costmap from a ``nav2_msgs/Costmap`` message or a baobab ``Costmap2D``.

    The cells are a copy: ``setCost`` changes this view only.

    Args:
        occupancy_map: the costmap message (Nav2's argument name), or a baobab grid, which is
            taken as being in the ``map`` frame with a zero stamp.
    """

    def __init__(self, occupancy_map: Costmap | Costmap2D) -> None:
        if isinstance(occupancy_map, Costmap2D):
            grid = occupancy_map
            super().__init__(
                grid.size_x,
                grid.size_y,
                grid.resolution,
                grid.origin,
                "map",
                TimeMsg(),
                np.array(grid.data, dtype=np.uint8).reshape(-1),
            )
            return
        meta = occupancy_map.metadata
        super().__init__(
            meta.size_x,
            meta.size_y,
            meta.resolution,
            (meta.origin.position.x, meta.origin.position.y),
            occupancy_map.header.frame_id,
            occupancy_map.header.stamp,
            np.array(occupancy_map.data, dtype=np.uint8),
        )
