"""What Nav2's docking server knows beside its tasks: settings, dock database, charger, scans.

Settings are Nav2's (``opennav_docking``'s server, ``SimpleChargingDock`` and graceful
controller parameters; reference/nav2_ros_facts.md §6), with the bringup's 0.15 m/s approach.
The dock database is the world's ``docks:`` unless a dock database file (Nav2's format,
:func:`~baobab.sim.docks.load_dock_database`) replaces it: the server believes the database,
the lidar tells it where the dock really is. The charger is a ``SimpleChargingDock`` without a
battery topic: charging means docked, here the charger's spring contacts touching the base
(:data:`~baobab.sim.docks.CHARGING_CONTACT`), and undocking switches charging off first.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from baobab.nav.dock_detection import DetectorParams
from baobab.nav.graceful_control import GracefulParams
from baobab.nav.interfaces import MobileBase
from baobab.sim.docks import CHARGING_CONTACT, Dock
from baobab.sim.lidar import LaserScan
from baobab.sim.world import Pose2D


@dataclass(frozen=True)
class DockingParams:
    """The docking server's settings: Nav2's names, units and defaults (s, m, rad)."""

    initial_perception_timeout: float = 5.0
    """s to find the dock at the staging pose before FAILED_TO_DETECT_DOCK."""
    wait_charge_timeout: float = 5.0
    """s to wait for charging once docked before FAILED_TO_CHARGE."""
    dock_approach_timeout: float = 30.0
    """s of approach (and of each return to staging) before FAILED_TO_CONTROL."""
    undock_linear_tolerance: float = 0.05
    """How close (m) undocking and a retry bring the base to the staging pose."""
    undock_angular_tolerance: float = 0.05
    """How close (rad) in heading."""
    max_retries: int = 3
    """Approaches tried again after a detection, control or charging failure."""
    dock_prestaging_tolerance: float = 0.5
    """Within this (m, over x, y and yaw) of the staging pose, no navigation to it."""
    staging_x_offset: float = -0.7
    """Staging pose: this far (m) along the dock's heading from the dock pose."""
    staging_yaw_offset: float = 0.0
    """Staging heading: the dock's plus this (rad)."""
    docking_threshold: float = 0.05
    """Docked: the base within this (m) of the detected dock pose."""
    detection_timeout: float = 1.0
    """s without a detection during the approach before FAILED_TO_DETECT_DOCK (Nav2's
    ``external_detection_timeout``)."""
    blind_distance: float = 0.30
    """Within this (m) of the dock the plate is nearer the lidar than its ``range_min``: the
    approach goes on with the last detection."""
    use_collision_detection: bool = True
    """Check the law's projected path on the local costmap before each command."""
    projection_time: float = 5.0
    """s of the projected path that is checked."""
    dock_collision_threshold: float = 0.3
    """Projected poses within this (m) of the dock are not checked (the dock itself is an
    obstacle in the costmap)."""
    controller: GracefulParams = field(
        default_factory=lambda: GracefulParams(v_linear_min=0.15, v_linear_max=0.15)
    )
    detector: DetectorParams = field(default_factory=DetectorParams)


def staging_pose(dock: Pose2D, params: DockingParams) -> Pose2D:
    """Where the approach starts: ``staging_x_offset`` m along the dock's heading (m, rad)."""
    cos, sin = math.cos(dock.yaw), math.sin(dock.yaw)
    return Pose2D(
        x=dock.x + params.staging_x_offset * cos,
        y=dock.y + params.staging_x_offset * sin,
        yaw=math.remainder(dock.yaw + params.staging_yaw_offset, math.tau),
    )


def pose_of(dock: Dock) -> Pose2D:
    """A database entry's docked base pose (m, rad)."""
    return Pose2D(x=dock.x, y=dock.y, yaw=dock.yaw)


def pose_distance(a: Pose2D, b: Pose2D) -> float:
    """Nav2's ``l2Norm`` of two poses: x, y (m) and yaw (rad) together."""
    return math.sqrt(
        (a.x - b.x) ** 2 + (a.y - b.y) ** 2 + math.remainder(a.yaw - b.yaw, math.tau) ** 2
    )


class Charger:
    """The chargers of the world, as the robot's charging circuit feels them.

    Args:
        base: the robot's base.
        docks: the docks that stand in the world (not the database: the real ones).
    """

    def __init__(self, base: MobileBase, docks: dict[str, Dock]) -> None:
        self._base = base
        self._docks = docks
        self.enabled = True
        """False while undocking: the charging circuit is switched off."""

    def contact(self) -> str | None:
        """The dock whose contacts touch the base now, or None."""
        here = self._base.pose()
        reach, turn = CHARGING_CONTACT
        for name, dock in self._docks.items():
            if (
                math.hypot(here.x - dock.x, here.y - dock.y) <= reach
                and abs(math.remainder(here.yaw - dock.yaw, math.tau)) <= turn
            ):
                return name
        return None

    def is_charging(self) -> bool:
        """True when charging is on and a dock's contacts touch the base."""
        return self.enabled and self.contact() is not None


class LatestScan:
    """The lidar's latest scan (a subscriber); ``take`` hands each scan out once."""

    def __init__(self) -> None:
        self.scan: LaserScan | None = None
        self._taken: float | None = None

    def __call__(self, scan: LaserScan) -> None:
        self.scan = scan

    def take(self) -> LaserScan | None:
        """The latest scan if it was not taken yet, else None."""
        scan = self.scan
        if scan is None or scan.stamp == self._taken:
            return None
        self._taken = scan.stamp
        return scan


__all__ = ["Charger", "DockingParams", "LatestScan", "pose_distance", "pose_of", "staging_pose"]
