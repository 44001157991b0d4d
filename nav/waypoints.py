"""Nav2's waypoint follower: NavigateToPose to each waypoint in turn, then a task at each.

The loop (reference/nav2.md §4.4), ticked at ``loop_rate`` (20 Hz) of sim time: navigate to
waypoint ``i`` with a fresh NavigateToPose; on success run the task executor (wait
``wait_at_waypoint`` s of sim time, Nav2's WaitAtWaypoint, which always succeeds); on failure
record the waypoint in ``missed_waypoints`` with the navigation's error and either stop
(``stop_on_failure``: STOP_ON_MISSED_WAYPOINT) or move on. After the last waypoint the task
succeeds, even with missed waypoints, unless ``number_of_loops`` asks for more passes.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from enum import IntEnum
from typing import Any

from baobab.nav.errors import FollowWaypointsError
from baobab.nav.interfaces import ServerTask
from baobab.sim.tasks import TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D


class WaypointStatus(IntEnum):
    """How one waypoint of a goal list went (``nav2_msgs/WaypointStatus`` values)."""

    PENDING = 0
    COMPLETED = 1
    SKIPPED = 2
    FAILED = 3


def _failed(code: FollowWaypointsError, message: str) -> TaskOutcome:
    return TaskOutcome(TaskStatus.FAILED, int(code), message, code.name)


class WaypointFollower:
    """One FollowWaypoints goal.

    Args:
        waypoints: the poses to visit, in order.
        navigate: starts a NavigateToPose task towards a pose.
        wait_at_waypoint: pause (s) at each reached waypoint.
        stop_on_failure: end the task at the first missed waypoint.
        loop_rate: how often the loop runs (Hz).
        number_of_loops: extra passes over the list after the first.
        goal_index: the waypoint to start at.
    """

    def __init__(
        self,
        waypoints: Sequence[Pose2D],
        navigate: Callable[[Pose2D], ServerTask],
        *,
        wait_at_waypoint: float = 0.0,
        stop_on_failure: bool = True,
        loop_rate: float = 20.0,
        number_of_loops: int = 0,
        goal_index: int = 0,
    ) -> None:
        self.waypoints = list(waypoints)
        self._navigate = navigate
        self.wait_at_waypoint = wait_at_waypoint
        self.stop_on_failure = stop_on_failure
        self.number_of_loops = number_of_loops
        self.period = 1.0 / loop_rate
        self.index = goal_index
        self.loops_done = 0
        self.missed_waypoints: list[dict[str, Any]] = []
        self.feedback: dict[str, Any] = {"current_waypoint": goal_index, "missed_waypoints": []}
        self._child: ServerTask | None = None
        self._wait_until: float | None = None

    def preempt(
        self,
        waypoints: Sequence[Pose2D],
        *,
        wait_at_waypoint: float,
        stop_on_failure: bool,
        number_of_loops: int = 0,
    ) -> None:
        """Take a new goal in place: the current navigation stops, the index goes back to 0."""
        self.halt()
        self.waypoints = list(waypoints)
        self.wait_at_waypoint = wait_at_waypoint
        self.stop_on_failure = stop_on_failure
        self.number_of_loops = number_of_loops
        self.index = 0
        self.loops_done = 0
        self.missed_waypoints = []
        self.feedback.clear()
        self.feedback.update(current_waypoint=0, missed_waypoints=[])

    def tick(self, now: float) -> TaskOutcome | None:
        """One loop iteration at sim time ``now`` (s); the outcome once done."""
        if not self.waypoints:
            return _failed(FollowWaypointsError.NO_VALID_WAYPOINTS, "no waypoints given")
        if not 0 <= self.index < len(self.waypoints):
            return _failed(
                FollowWaypointsError.NO_VALID_WAYPOINTS,
                f"goal_index {self.index} is not an index of the {len(self.waypoints)} waypoints",
            )
        if not (self.wait_at_waypoint >= 0 and self.number_of_loops >= 0):
            return _failed(
                FollowWaypointsError.UNKNOWN, "wait_at_waypoint and number_of_loops must be >= 0"
            )
        self.feedback["current_waypoint"] = self.index
        if self._wait_until is not None:
            if now < self._wait_until - 1e-9:
                return None
            self._wait_until = None
            return self._next()
        if self._child is None:
            self._child = self._navigate(self.waypoints[self.index])
        outcome = self._child.tick(now)
        self.feedback["current_pose"] = self._child.feedback.get("current_pose")
        if outcome is None:
            return None
        self._child = None
        if outcome.status is TaskStatus.SUCCEEDED:
            if self.wait_at_waypoint == 0:
                return self._next()
            self._wait_until = now + self.wait_at_waypoint
            return None
        self.missed_waypoints.append(
            {
                "index": self.index,
                "pose": self.waypoints[self.index],
                "error_code": outcome.error_code,
                "error_name": outcome.error_name,
                "error_msg": outcome.error_msg,
            }
        )
        self.feedback["missed_waypoints"] = list(self.missed_waypoints)
        if self.stop_on_failure:
            return _failed(
                FollowWaypointsError.STOP_ON_MISSED_WAYPOINT,
                f"missed waypoint {self.index}: {outcome.error_name} ({outcome.error_code}) "
                f"{outcome.error_msg}",
            )
        return self._next()

    def _next(self) -> TaskOutcome | None:
        self.index += 1
        if self.index < len(self.waypoints):
            self.feedback["current_waypoint"] = self.index
            return None
        if self.loops_done < self.number_of_loops:
            self.loops_done += 1
            self.index = 0
            self.feedback["current_waypoint"] = 0
            return None
        self.index = len(self.waypoints) - 1
        return TaskOutcome(TaskStatus.SUCCEEDED)

    def halt(self) -> None:
        """Stop the navigation in progress."""
        if self._child is not None:
            self._child.halt()
            self._child = None
        self._wait_until = None
