"""Where the navigation stack meets the robot, and where the server meets its tasks.

:class:`MobileBase` and :class:`ScanSource` are what navigation needs from a robot. They are
Protocols, so ``baobab.nav`` imports no robot's running code (only the registry's facts): the
differential drive's ``DiffDriveBase`` and ``Lidar`` satisfy them as they are, and so would any
planar base whose pose is known in the map frame (the simulation localises perfectly).
:class:`ServerTask` is what the navigation server runs: navigation trees, the waypoint
follower, FollowPath and the behaviours.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

from baobab.sim.lidar import LaserScan
from baobab.sim.tasks import TaskOutcome
from baobab.sim.world import Pose2D

ScanCallback = Callable[[LaserScan], None]
"""Receives every new scan."""


class MobileBase(Protocol):
    """A planar base driven by ``cmd_vel``: forward speed and yaw rate."""

    def pose(self) -> Pose2D:
        """The base's pose in the map frame (m, rad)."""
        ...

    def body_velocity(self) -> tuple[float, float]:
        """Forward speed (m/s) and yaw rate (rad/s)."""
        ...

    def command(self, linear: float, angular: float) -> None:
        """Set ``cmd_vel``: ``linear`` (m/s) and ``angular`` (rad/s), held until the next call."""
        ...

    def stop(self) -> None:
        """Command zero velocity."""
        ...


class ScanSource(Protocol):
    """A lidar that calls its subscribers with each new scan (a ``sensor_msgs/LaserScan`` topic)."""

    def subscribe(self, subscriber: ScanCallback) -> None:
        """Call ``subscriber(scan)`` with every scan from now on."""
        ...

    def unsubscribe(self, subscriber: ScanCallback) -> None:
        """Stop calling ``subscriber``."""
        ...


class ServerTask(Protocol):
    """One goal the navigation server runs: ticked every ``period`` seconds of sim time."""

    period: float
    """Seconds of sim time between ticks."""
    feedback: dict[str, Any]
    """Nav2-named feedback fields, updated by :meth:`tick`."""

    def tick(self, now: float) -> TaskOutcome | None:
        """Advance at sim time ``now`` (s); the outcome once the goal ended, else None."""
        ...

    def halt(self) -> None:
        """Stop at once (cancel or preemption); the robot is left commanded to stop."""
        ...
