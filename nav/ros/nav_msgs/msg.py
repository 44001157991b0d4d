"""``nav_msgs.msg``: paths, goal lists and occupancy grids."""

from __future__ import annotations

from baobab.nav.msgs import Goals, MapMetaData, OccupancyGrid, Path

__all__ = ["Goals", "MapMetaData", "OccupancyGrid", "Path"]
