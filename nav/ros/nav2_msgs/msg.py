"""``nav2_msgs.msg``: costmaps."""

from __future__ import annotations

from baobab.nav.msgs import Costmap, CostmapMetaData

__all__ = ["Costmap", "CostmapMetaData"]
