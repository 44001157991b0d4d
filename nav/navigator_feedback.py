"""Nav2 action feedback and result messages, built from the navigation server's task feedback.

The server keeps each task's feedback as a dict of plain values (sim seconds, a ``Pose2D``);
a Nav2 script reads messages: ``feedback.navigation_time`` is a ``builtin_interfaces``
Duration, ``feedback.current_pose`` a ``PoseStamped``. The messages are the action types of
:mod:`baobab.nav.ros.nav2_msgs.action` (Nav2's current fields, older ones kept). What each
field holds here:

============================  ==============================================================
NavigateToPose                pose, times, distance, recoveries; tracking errors from the
                              controller's last cycle (0 before its first)
NavigateThroughPoses          the same, plus poses remaining and each pose's status
FollowWaypoints               current_waypoint (plus baobab's missed_waypoints so far)
FollowPath                    tracking_feedback (errors, index, pose, distances, speed), and
                              Kilted's distance_to_goal (path length left) and speed
Spin / BackUp, DriveOnHeading angular_distance_traveled / distance_traveled
AssistedTeleop                current_teleop_duration
============================  ==============================================================

Results carry ``error_code`` and ``error_msg`` and, as each action defines,
``total_elapsed_time`` (behaviours), ``waypoint_statuses`` (NavigateThroughPoses) and
``missed_waypoints`` (FollowWaypoints).
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Mapping
from typing import Any

from baobab.nav.msgs import PoseStamped, from_pose2d
from baobab.nav.ros.nav2_msgs import action
from baobab.nav.ros.nav2_msgs.msg import TrackingFeedback, WaypointStatus
from baobab.nav.rosaction import Action
from baobab.nav.rosmsg import Message
from baobab.nav.rostime import Duration, DurationMsg
from baobab.sim.tasks import TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D


class RunningTask(enum.Enum):
    """The kind of task a navigator is running (Nav2 Rolling's ``RunningTask``)."""

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
    FOLLOW_OBJECT = 13


ACTIONS: dict[RunningTask, type[Action]] = {
    RunningTask.NAVIGATE_TO_POSE: action.NavigateToPose,
    RunningTask.NAVIGATE_THROUGH_POSES: action.NavigateThroughPoses,
    RunningTask.FOLLOW_PATH: action.FollowPath,
    RunningTask.FOLLOW_WAYPOINTS: action.FollowWaypoints,
    RunningTask.FOLLOW_GPS_WAYPOINTS: action.FollowGPSWaypoints,
    RunningTask.SPIN: action.Spin,
    RunningTask.BACKUP: action.BackUp,
    RunningTask.DRIVE_ON_HEADING: action.DriveOnHeading,
    RunningTask.ASSISTED_TELEOP: action.AssistedTeleop,
    RunningTask.DOCK_ROBOT: action.DockRobot,
    RunningTask.UNDOCK_ROBOT: action.UndockRobot,
    RunningTask.COMPUTE_AND_TRACK_ROUTE: action.ComputeAndTrackRoute,
    RunningTask.FOLLOW_OBJECT: action.FollowObject,
}
"""The Nav2 action type behind each task."""


class GoalStatus(enum.IntEnum):
    """``action_msgs/GoalStatus`` codes."""

    STATUS_UNKNOWN = 0
    STATUS_ACCEPTED = 1
    STATUS_EXECUTING = 2
    STATUS_CANCELING = 3
    STATUS_SUCCEEDED = 4
    STATUS_CANCELED = 5
    STATUS_ABORTED = 6


Feedback = Message
"""Any action's feedback message."""

StampedPose = Callable[[Pose2D], PoseStamped]
"""Turns a map-frame pose into a stamped message (the navigator stamps with sim time)."""


def duration(seconds: float) -> DurationMsg:
    """A ``builtin_interfaces/Duration`` of ``seconds`` (s)."""
    return Duration(seconds=float(seconds)).to_msg()


def feedback_message(
    task: RunningTask, values: Mapping[str, Any], stamped: StampedPose
) -> Message | None:
    """The feedback message of ``task`` from the server's feedback ``values``.

    Returns None before the task has reported anything (Nav2's "no feedback yet").
    """
    if not values:
        return None
    get = values.get
    if task in (RunningTask.NAVIGATE_TO_POSE, RunningTask.NAVIGATE_THROUGH_POSES):
        return _navigation_feedback(task, values, stamped)
    if task is RunningTask.FOLLOW_WAYPOINTS:
        return action.FollowWaypoints.Feedback(
            current_waypoint=int(get("current_waypoint", 0)),
            missed_waypoints=missed_waypoints(get("missed_waypoints", ())),
        )
    if task is RunningTask.FOLLOW_PATH:
        return action.FollowPath.Feedback(
            tracking_feedback=tracking_feedback(get("tracking_feedback", {}), stamped),
            distance_to_goal=float(get("distance_to_goal", 0.0)),
            speed=float(get("speed", 0.0)),
        )
    if task is RunningTask.SPIN:
        return action.Spin.Feedback(
            angular_distance_traveled=float(get("angular_distance_traveled", 0.0))
        )
    if task in (RunningTask.BACKUP, RunningTask.DRIVE_ON_HEADING):
        kind = action.BackUp if task is RunningTask.BACKUP else action.DriveOnHeading
        return kind.Feedback(distance_traveled=float(get("distance_traveled", 0.0)))
    if task is RunningTask.ASSISTED_TELEOP:
        return action.AssistedTeleop.Feedback(
            current_teleop_duration=duration(get("current_teleop_duration", 0.0))
        )
    return None


def _navigation_feedback(
    task: RunningTask, values: Mapping[str, Any], stamped: StampedPose
) -> Message:
    get = values.get
    tracking = get("tracking_feedback", {})
    fields: dict[str, Any] = {
        "navigation_time": duration(get("navigation_time", 0.0)),
        "estimated_time_remaining": duration(get("estimated_time_remaining", 0.0)),
        "number_of_recoveries": int(get("number_of_recoveries", 0)),
        "distance_remaining": float(get("distance_remaining", 0.0)),
        "position_tracking_error": float(tracking.get("position_tracking_error", 0.0)),
        "heading_tracking_error": float(tracking.get("heading_tracking_error", 0.0)),
    }
    pose = get("current_pose")
    if pose is not None:
        fields["current_pose"] = stamped(pose)
    if task is RunningTask.NAVIGATE_TO_POSE:
        return action.NavigateToPose.Feedback(**fields)
    return action.NavigateThroughPoses.Feedback(
        **fields,
        number_of_poses_remaining=int(get("number_of_poses_remaining", 0)),
        waypoint_statuses=waypoint_statuses(get("waypoint_statuses", ())),
    )


def tracking_feedback(values: Mapping[str, Any], stamped: StampedPose) -> TrackingFeedback:
    """``nav2_msgs/TrackingFeedback`` from the controller's ``tracking_feedback`` values
    (all zero before the controller's first cycle)."""
    get = values.get
    message = TrackingFeedback(
        position_tracking_error=float(get("position_tracking_error", 0.0)),
        heading_tracking_error=float(get("heading_tracking_error", 0.0)),
        current_path_index=int(get("current_path_index", 0)),
        distance_to_goal=float(get("distance_to_goal", 0.0)),
        speed=float(get("speed", 0.0)),
        remaining_path_length=float(get("remaining_path_length", 0.0)),
    )
    pose = get("robot_pose")
    if pose is not None:
        message.robot_pose = stamped(pose)
        message.header = message.robot_pose.header
    return message


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


def waypoint_statuses(entries: Any) -> list[WaypointStatus]:
    """``WaypointStatus`` messages for the server's per-pose status records."""
    return [
        WaypointStatus(
            waypoint_status=int(entry["status"]),
            waypoint_index=int(entry["index"]),
            waypoint_pose=from_pose2d(entry["pose"]),
            error_code=int(entry.get("error_code", 0)),
            error_msg=str(entry.get("error_msg", "")),
        )
        for entry in entries
    ]


def result_message(
    task: RunningTask, outcome: TaskOutcome, values: Mapping[str, Any], elapsed: float
) -> Message:
    """The result message of a finished ``task``: its last feedback ``values`` and the time
    (s) from acceptance to the end, ``elapsed``, included."""
    result: Any = ACTIONS[task].Result(
        error_code=int(outcome.error_code), error_msg=outcome.error_msg
    )
    fields = result.get_fields_and_field_types()
    if "total_elapsed_time" in fields:
        result.total_elapsed_time = duration(elapsed)
    if task is RunningTask.FOLLOW_WAYPOINTS:
        result.missed_waypoints = missed_waypoints(values.get("missed_waypoints", ()))
    elif task is RunningTask.NAVIGATE_THROUGH_POSES:
        result.waypoint_statuses = waypoint_statuses(values.get("waypoint_statuses", ()))
    message: Message = result
    return message


def unknown_code(task: RunningTask) -> int:
    """The UNKNOWN error code of ``task``'s action (what a rejected send reports)."""
    code: int = getattr(ACTIONS[task].Result, "UNKNOWN")  # noqa: B009 (set by result_codes)
    return code


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
