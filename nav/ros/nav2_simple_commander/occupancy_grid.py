"""``nav2_simple_commander.occupancy_grid``: ``PyOccupancyGrid``, PyCostmap2D's API over a map.

The same conversions and accessors as :class:`~.costmap_2d.PyCostmap2D`, over a
``nav_msgs/OccupancyGrid``; values are ``numpy.int8`` (0..100, -1 unknown).
"""

from __future__ import annotations

import numpy as np

from baobab.nav.msgs import OccupancyGrid
from baobab.nav.ros.nav2_simple_commander.costmap_2d import GridView

__all__ = ["PyOccupancyGrid"]


class PyOccupancyGrid(GridView):
    """An occupancy grid message as a grid view (its cells are a copy)."""

    def __init__(self, occupancy_map: OccupancyGrid) -> None:
        info = occupancy_map.info
        super().__init__(
            info.width,
            info.height,
            info.resolution,
            (info.origin.position.x, info.origin.position.y),
            occupancy_map.header.frame_id,
            occupancy_map.header.stamp,
            np.array(occupancy_map.data, dtype=np.int8),
        )
