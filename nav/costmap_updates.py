"""How the lidar's scans reach the navigation server's costmaps, and how they are cleared.

Each costmap takes the latest scan when it updates (Nav2's ``observation_persistence`` 0):
the local one at its update rate (5 Hz), which also moves its rolling window with the robot,
the global one at its own (1 Hz). A scan is marked once per costmap; a clear marks the latest
one again at once.
"""

from __future__ import annotations

from baobab.nav.behaviors import ClearCostmaps
from baobab.nav.interfaces import MobileBase
from baobab.nav.layered_costmap import LayeredCostmap
from baobab.sim.lidar import LaserScan


class CostmapUpdates:
    """Marks the latest scan into the local and global costmaps, and clears them.

    Args:
        base: the robot's base (the local costmap's window follows its pose).
        local: the rolling local costmap.
        global_: the global costmap.
    """

    def __init__(self, base: MobileBase, local: LayeredCostmap, global_: LayeredCostmap):
        self._base = base
        self._local = local
        self._global = global_
        self._clear = ClearCostmaps(local, global_)
        self._latest_scan: LaserScan | None = None
        self._local_scan: LaserScan | None = None
        self._global_scan: LaserScan | None = None

    def on_scan(self, scan: LaserScan) -> None:
        """Keep ``scan`` as the latest (a lidar subscriber)."""
        self._latest_scan = scan

    def update_local(self) -> None:
        """Move the local window to the robot and mark the latest scan if it is new."""
        scan = self._latest_scan
        fresh = scan is not None and scan is not self._local_scan
        self._local_scan = scan
        self._local.update(self._base.pose(), [scan] if fresh and scan is not None else [])

    def update_global(self) -> None:
        """Locate the robot for the keepout filter; mark the latest scan if it is new."""
        scan = self._latest_scan
        fresh = scan is not None and scan is not self._global_scan
        self._global_scan = scan
        self._global.update(self._base.pose(), [scan] if fresh and scan is not None else [])

    def clear_and_remark(self, which: str) -> None:
        """Clear the ``local``, ``global`` or ``all`` obstacle layers, then mark the latest scan
        again: what the lidar still sees stays.

        Nav2's obstacle layer re-marks its latest observation on every update, and its planner
        and controller wait after a clear until the costmap is current again, so a clear only
        forgets obstacles the sensor no longer sees; here a scan is marked once, so the latest
        one is marked again at once.

        Raises:
            ValueError: for any other name.
        """
        self._clear(which)
        scan = self._latest_scan
        if scan is None:
            return
        if which in ("local", "all"):
            self._local.add_scan(scan)
        if which in ("global", "all"):
            self._global.add_scan(scan)
