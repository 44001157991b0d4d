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
from baobab.sim.tasks import TaskHandle, TaskOutcome
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


FEEDBACK_KEY = "feedback"
"""Where an :class:`ActionServer`'s handle keeps the action's latest Feedback message."""
FEEDBACK_QUEUE_KEY = "queue"
"""Where it keeps every Feedback message in order, for actions whose feedback queues (routes)."""
RESULT_KEY = "result"
"""Where it puts the action's Result message when the goal ends."""


class ActionServer(Protocol):
    """A server for one Nav2 action the navigation server does not run itself.

    Docking, object following, routes and GPS waypoints plug in here: register one under its
    action name in ``NavigationServer.action_servers`` (``"dock_robot"``, ``"undock_robot"``,
    ``"follow_object"``, ``"compute_route"``, ``"compute_and_track_route"``,
    ``"follow_gps_waypoints"``) and the navigator's methods send it the action's Goal message
    (``nav2_msgs.action.DockRobot.Goal`` ...). The returned handle's ``feedback`` dict holds
    messages under :data:`FEEDBACK_KEY`, :data:`FEEDBACK_QUEUE_KEY` and :data:`RESULT_KEY`.
    """

    def send_goal(self, goal: Any) -> TaskHandle:
        """Start working on ``goal``; raise ``GoalRejectedError`` to reject it."""
        ...
