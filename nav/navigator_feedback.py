"""Nav2 action feedback and result messages, built from the navigation server's task feedback.

The server keeps each task's feedback as a dict of plain values (sim seconds, a ``Pose2D``);
a Nav2 script reads messages: ``feedback.navigation_time`` is a ``builtin_interfaces``
Duration, ``feedback.current_pose`` a ``PoseStamped``. The classes here carry Nav2's field
names and types (Kilted's, reference/nav2.md §2), one per action the navigator sends:

============================  ==============================================================
NavigateToPose                current_pose, navigation_time, estimated_time_remaining,
                              number_of_recoveries, distance_remaining
NavigateThroughPoses          the same, plus number_of_poses_remaining
FollowWaypoints               current_waypoint (plus baobab's missed_waypoints so far)
FollowPath                    distance_to_goal, speed
Spin                          angular_distance_traveled
BackUp, DriveOnHeading        distance_traveled
AssistedTeleop                current_teleop_duration
============================  ==============================================================

Results follow ``action_msgs``: a :class:`GetResultResponse` with the goal ``status``
(:class:`GoalStatus` codes) and the action's ``result`` (``error_code``, ``error_msg``, and
``missed_waypoints`` for FollowWaypoints), which is what Nav2 users reach through
``navigator.result_future.result().result``.
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from baobab.nav.msgs import PoseStamped, from_pose2d
from baobab.nav.rostime import Duration, DurationMsg
from baobab.sim.tasks import TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D


class RunningTask(enum.Enum):
    """The kind of task a navigator is running (Nav2 Kilted's ``RunningTask``)."""

    NONE = 0
    NAVIGATE_TO_POSE = 1
    NAVIGATE_THROUGH_POSES = 2
    FOLLOW_PATH = 3
    FOLLOW_WAYPOINTS = 4
    FOLLOW_GPS_WAYPOINTS = 5
    SPIN = 6
    BACKUP = 7
    DRIVE_ON_HEADING = 8
    ASSISTED_TELEOP = 9
    DOCK_ROBOT = 10
    UNDOCK_ROBOT = 11
    COMPUTE_AND_TRACK_ROUTE = 12


class GoalStatus(enum.IntEnum):
    """``action_msgs/GoalStatus`` codes."""

    STATUS_UNKNOWN = 0
    STATUS_ACCEPTED = 1
    STATUS_EXECUTING = 2
    STATUS_CANCELING = 3
    STATUS_SUCCEEDED = 4
    STATUS_CANCELED = 5
    STATUS_ABORTED = 6


def _duration(seconds: float) -> DurationMsg:
    return Duration(seconds=seconds).to_msg()


@dataclass(slots=True, kw_only=True)
class NavigateToPoseFeedback:
    """``nav2_msgs/action/NavigateToPose`` feedback."""

    current_pose: PoseStamped = field(default_factory=PoseStamped)
    navigation_time: DurationMsg = field(default_factory=DurationMsg)
    estimated_time_remaining: DurationMsg = field(default_factory=DurationMsg)
    number_of_recoveries: int = 0
    distance_remaining: float = 0.0


@dataclass(slots=True, kw_only=True)
class NavigateThroughPosesFeedback(NavigateToPoseFeedback):
    """``nav2_msgs/action/NavigateThroughPoses`` feedback."""

    number_of_poses_remaining: int = 0


@dataclass(slots=True, kw_only=True)
class WaypointStatus:
    """``nav2_msgs/WaypointStatus``: how one waypoint went."""

    PENDING = 0
    COMPLETED = 1
    SKIPPED = 2
    FAILED = 3

    waypoint_status: int = PENDING
    waypoint_index: int = 0
    waypoint_pose: PoseStamped = field(default_factory=PoseStamped)
    error_code: int = 0
    error_msg: str = ""


@dataclass(slots=True, kw_only=True)
class FollowWaypointsFeedback:
    """``nav2_msgs/action/FollowWaypoints`` feedback.

    ``current_waypoint`` is Nav2's field (0-based); ``missed_waypoints`` is baobab's addition,
    the waypoints missed so far (Nav2 reports them only in the result).
    """

    current_waypoint: int = 0
    missed_waypoints: list[WaypointStatus] = field(default_factory=list)


@dataclass(slots=True, kw_only=True)
class FollowPathFeedback:
    """``nav2_msgs/action/FollowPath`` feedback (Humble to Kilted fields)."""

    distance_to_goal: float = 0.0
    speed: float = 0.0


@dataclass(slots=True, kw_only=True)
class SpinFeedback:
    """``nav2_msgs/action/Spin`` feedback: the signed turn so far (rad)."""

    angular_distance_traveled: float = 0.0


@dataclass(slots=True, kw_only=True)
class BackUpFeedback:
    """``nav2_msgs/action/BackUp`` feedback: the straight-line distance so far (m)."""

    distance_traveled: float = 0.0


@dataclass(slots=True, kw_only=True)
class DriveOnHeadingFeedback:
    """``nav2_msgs/action/DriveOnHeading`` feedback: the straight-line distance so far (m)."""

    distance_traveled: float = 0.0


@dataclass(slots=True, kw_only=True)
class AssistedTeleopFeedback:
    """``nav2_msgs/action/AssistedTeleop`` feedback."""

    current_teleop_duration: DurationMsg = field(default_factory=DurationMsg)


@dataclass(slots=True, kw_only=True)
class ActionResult:
    """A Nav2 action result: ``error_code`` (0 on success) and ``error_msg``."""

    error_code: int = 0
    error_msg: str = ""


@dataclass(slots=True, kw_only=True)
class FollowWaypointsResult(ActionResult):
    """``nav2_msgs/action/FollowWaypoints`` result: the missed waypoints and the error."""

    missed_waypoints: list[WaypointStatus] = field(default_factory=list)


@dataclass(slots=True, kw_only=True)
class GetResultResponse:
    """What a goal's result future holds: the final ``status`` and the action ``result``."""

    status: int
    result: ActionResult


Feedback = (
    NavigateToPoseFeedback
    | FollowWaypointsFeedback
    | FollowPathFeedback
    | SpinFeedback
    | BackUpFeedback
    | DriveOnHeadingFeedback
    | AssistedTeleopFeedback
)
"""Any of the feedback messages above."""

StampedPose = Callable[[Pose2D], PoseStamped]
"""Turns a map-frame pose into a stamped message (the navigator stamps with sim time)."""


def feedback_message(
    task: RunningTask, values: Mapping[str, Any], stamped: StampedPose
) -> Feedback | None:
    """The feedback message of ``task`` from the server's feedback ``values``.

    Returns None before the task has reported anything (Nav2's "no feedback yet").
    """
    if not values:
        return None
    get = values.get
    if task in (RunningTask.NAVIGATE_TO_POSE, RunningTask.NAVIGATE_THROUGH_POSES):
        fields: dict[str, Any] = {
            "navigation_time": _duration(get("navigation_time", 0.0)),
            "estimated_time_remaining": _duration(get("estimated_time_remaining", 0.0)),
            "number_of_recoveries": int(get("number_of_recoveries", 0)),
            "distance_remaining": float(get("distance_remaining", 0.0)),
        }
        pose = get("current_pose")
        if pose is not None:
            fields["current_pose"] = stamped(pose)
        if task is RunningTask.NAVIGATE_TO_POSE:
            return NavigateToPoseFeedback(**fields)
        return NavigateThroughPosesFeedback(
            **fields, number_of_poses_remaining=int(get("number_of_poses_remaining", 0))
        )
    if task is RunningTask.FOLLOW_WAYPOINTS:
        return FollowWaypointsFeedback(
            current_waypoint=int(get("current_waypoint", 0)),
            missed_waypoints=missed_waypoints(get("missed_waypoints", ())),
        )
    if task is RunningTask.FOLLOW_PATH:
        return FollowPathFeedback(
            distance_to_goal=float(get("distance_to_goal", 0.0)), speed=float(get("speed", 0.0))
        )
    if task is RunningTask.SPIN:
        return SpinFeedback(angular_distance_traveled=float(get("angular_distance_traveled", 0.0)))
    if task is RunningTask.BACKUP:
        return BackUpFeedback(distance_traveled=float(get("distance_traveled", 0.0)))
    if task is RunningTask.DRIVE_ON_HEADING:
        return DriveOnHeadingFeedback(distance_traveled=float(get("distance_traveled", 0.0)))
    if task is RunningTask.ASSISTED_TELEOP:
        return AssistedTeleopFeedback(
            current_teleop_duration=_duration(get("current_teleop_duration", 0.0))
        )
    return None


def missed_waypoints(entries: Any) -> list[WaypointStatus]:
    """``WaypointStatus`` messages (FAILED) for the server's missed-waypoint records."""
    return [
        WaypointStatus(
            waypoint_status=WaypointStatus.FAILED,
            waypoint_index=int(entry["index"]),
            waypoint_pose=from_pose2d(entry["pose"]),
            error_code=int(entry["error_code"]),
            error_msg=str(entry["error_msg"]),
        )
        for entry in entries
    ]


def goal_status(outcome: TaskOutcome | None) -> GoalStatus:
    """The ``action_msgs`` status of a task: EXECUTING until it ends."""
    if outcome is None:
        return GoalStatus.STATUS_EXECUTING
    return {
        TaskStatus.SUCCEEDED: GoalStatus.STATUS_SUCCEEDED,
        TaskStatus.CANCELED: GoalStatus.STATUS_CANCELED,
        TaskStatus.FAILED: GoalStatus.STATUS_ABORTED,
        TaskStatus.RUNNING: GoalStatus.STATUS_EXECUTING,
    }[outcome.status]


class ResultFuture:
    """The result future of one goal (``rclpy.task.Future``'s ``done()`` / ``result()``).

    Args:
        task: the kind of task.
        outcome: reads the task's outcome, None while it runs.
        feedback: reads the server's feedback values (for the missed waypoints).
    """

    def __init__(
        self,
        task: RunningTask,
        outcome: Callable[[], TaskOutcome | None],
        feedback: Callable[[], Mapping[str, Any]],
    ) -> None:
        self.task = task
        self._outcome = outcome
        self._feedback = feedback

    def done(self) -> bool:
        """True once the goal has ended."""
        return self._outcome() is not None

    def result(self) -> GetResultResponse | None:
        """The final status and result message; None while the goal runs."""
        outcome = self._outcome()
        if outcome is None:
            return None
        if self.task is RunningTask.FOLLOW_WAYPOINTS:
            result: ActionResult = FollowWaypointsResult(
                error_code=outcome.error_code,
                error_msg=outcome.error_msg,
                missed_waypoints=missed_waypoints(self._feedback().get("missed_waypoints", ())),
            )
        else:
            result = ActionResult(error_code=outcome.error_code, error_msg=outcome.error_msg)
        return GetResultResponse(status=int(goal_status(outcome)), result=result)
