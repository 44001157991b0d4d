"""Nav2's navigation actions: navigators, waypoint followers, controller, planner, smoother.

Fields, types and defaults of Nav2's current release (reference/nav2_ros_facts.md §5). Older
fields a release still has are kept: FollowPath's feedback carries Kilted's
``distance_to_goal`` and ``speed`` beside ``tracking_feedback``. FollowWaypoints' feedback has
baobab's ``missed_waypoints`` (the ones missed so far; Nav2 reports them in the result only).
"""

from __future__ import annotations

from baobab.nav.errors import (
    ComputePathThroughPosesError,
    ComputePathToPoseError,
    FollowGPSWaypointsError,
    FollowPathError,
    FollowWaypointsError,
    NavigateThroughPosesError,
    NavigateToPoseError,
    SmoothPathError,
)
from baobab.nav.msgs import Goals, Path, PoseStamped
from baobab.nav.ros.geographic_msgs.msg import GeoPose
from baobab.nav.ros.nav2_msgs.msg import TrackingFeedback, WaypointStatus
from baobab.nav.ros.std_msgs.msg import Empty
from baobab.nav.rosaction import Action, result_codes
from baobab.nav.rosmsg import Message
from baobab.nav.rostime import DurationMsg

_ERROR = {"error_code": "uint16", "error_msg": "string"}

_NAVIGATION_FEEDBACK = {
    "current_pose": "geometry_msgs/PoseStamped",
    "navigation_time": "builtin_interfaces/Duration",
    "estimated_time_remaining": "builtin_interfaces/Duration",
    "number_of_recoveries": "int16",
    "distance_remaining": "float",
    "position_tracking_error": "float",
    "heading_tracking_error": "float",
}


# --- NavigateToPose ---------------------------------------------------------------------------


class NavigateToPose_Goal(Message):
    """Go to ``pose`` with the navigator's default tree (``behavior_tree`` '')."""

    _type_name = "nav2_msgs/action/NavigateToPose_Goal"
    _fields_and_field_types = {"pose": "geometry_msgs/PoseStamped", "behavior_tree": "string"}
    pose: PoseStamped
    behavior_tree: str


@result_codes(NavigateToPoseError)
class NavigateToPose_Result(Message):
    """How the navigation ended (``error_code`` 0 on success)."""

    _type_name = "nav2_msgs/action/NavigateToPose_Result"
    _fields_and_field_types = dict(_ERROR)
    error_code: int
    error_msg: str


class NavigateToPose_Feedback(Message):
    """Where the robot is, how long it has been going and how far it has left (m, s)."""

    _type_name = "nav2_msgs/action/NavigateToPose_Feedback"
    _fields_and_field_types = dict(_NAVIGATION_FEEDBACK)
    current_pose: PoseStamped
    navigation_time: DurationMsg
    estimated_time_remaining: DurationMsg
    number_of_recoveries: int
    distance_remaining: float
    position_tracking_error: float
    heading_tracking_error: float


class NavigateToPose(Action):
    """``nav2_msgs/action/NavigateToPose``."""

    _type_name = "nav2_msgs/action/NavigateToPose"
    Goal = NavigateToPose_Goal
    Result = NavigateToPose_Result
    Feedback = NavigateToPose_Feedback


# --- NavigateThroughPoses ---------------------------------------------------------------------


class NavigateThroughPoses_Goal(Message):
    """Go through ``poses`` in order without stopping."""

    _type_name = "nav2_msgs/action/NavigateThroughPoses_Goal"
    _fields_and_field_types = {"poses": "nav_msgs/Goals", "behavior_tree": "string"}
    poses: Goals
    behavior_tree: str


@result_codes(NavigateThroughPosesError)
class NavigateThroughPoses_Result(Message):
    """How the navigation ended, and how each pose went."""

    _type_name = "nav2_msgs/action/NavigateThroughPoses_Result"
    _fields_and_field_types = {
        **_ERROR,
        "waypoint_statuses": "sequence<nav2_msgs/WaypointStatus>",
    }
    error_code: int
    error_msg: str
    waypoint_statuses: list[WaypointStatus]


class NavigateThroughPoses_Feedback(Message):
    """NavigateToPose's feedback, the poses left and how each pose went so far."""

    _type_name = "nav2_msgs/action/NavigateThroughPoses_Feedback"
    _fields_and_field_types = {
        **_NAVIGATION_FEEDBACK,
        "number_of_poses_remaining": "int16",
        "waypoint_statuses": "sequence<nav2_msgs/WaypointStatus>",
    }
    current_pose: PoseStamped
    navigation_time: DurationMsg
    estimated_time_remaining: DurationMsg
    number_of_recoveries: int
    distance_remaining: float
    position_tracking_error: float
    heading_tracking_error: float
    number_of_poses_remaining: int
    waypoint_statuses: list[WaypointStatus]


class NavigateThroughPoses(Action):
    """``nav2_msgs/action/NavigateThroughPoses``."""

    _type_name = "nav2_msgs/action/NavigateThroughPoses"
    Goal = NavigateThroughPoses_Goal
    Result = NavigateThroughPoses_Result
    Feedback = NavigateThroughPoses_Feedback


# --- FollowWaypoints, FollowGPSWaypoints ------------------------------------------------------


class FollowWaypoints_Goal(Message):
    """Visit ``poses`` in turn from ``goal_index``, ``number_of_loops`` extra times."""

    _type_name = "nav2_msgs/action/FollowWaypoints_Goal"
    _fields_and_field_types = {
        "number_of_loops": "uint32",
        "goal_index": "uint32",
        "poses": "sequence<geometry_msgs/PoseStamped>",
    }
    number_of_loops: int
    goal_index: int
    poses: list[PoseStamped]


@result_codes(FollowWaypointsError, common=False)
class FollowWaypoints_Result(Message):
    """The waypoints missed, and how the task ended."""

    _type_name = "nav2_msgs/action/FollowWaypoints_Result"
    _fields_and_field_types = {"missed_waypoints": "sequence<nav2_msgs/WaypointStatus>", **_ERROR}
    missed_waypoints: list[WaypointStatus]
    error_code: int
    error_msg: str


class FollowWaypoints_Feedback(Message):
    """The waypoint being processed (0-based), and baobab's waypoints missed so far."""

    _type_name = "nav2_msgs/action/FollowWaypoints_Feedback"
    _fields_and_field_types = {
        "current_waypoint": "uint32",
        "missed_waypoints": "sequence<nav2_msgs/WaypointStatus>",
    }
    current_waypoint: int
    missed_waypoints: list[WaypointStatus]


class FollowWaypoints(Action):
    """``nav2_msgs/action/FollowWaypoints``."""

    _type_name = "nav2_msgs/action/FollowWaypoints"
    Goal = FollowWaypoints_Goal
    Result = FollowWaypoints_Result
    Feedback = FollowWaypoints_Feedback


class FollowGPSWaypoints_Goal(Message):
    """Visit GPS poses in turn (each converted to the map frame by ``/fromLL``)."""

    _type_name = "nav2_msgs/action/FollowGPSWaypoints_Goal"
    _fields_and_field_types = {
        "number_of_loops": "uint32",
        "goal_index": "uint32",
        "gps_poses": "sequence<geographic_msgs/GeoPose>",
    }
    number_of_loops: int
    goal_index: int
    gps_poses: list[GeoPose]


@result_codes(FollowGPSWaypointsError, common=False)
class FollowGPSWaypoints_Result(Message):
    """The waypoints missed, and how the task ended (``error_code`` is int16 here)."""

    _type_name = "nav2_msgs/action/FollowGPSWaypoints_Result"
    _fields_and_field_types = {
        "missed_waypoints": "sequence<nav2_msgs/WaypointStatus>",
        "error_code": "int16",
        "error_msg": "string",
    }
    missed_waypoints: list[WaypointStatus]
    error_code: int
    error_msg: str


class FollowGPSWaypoints_Feedback(Message):
    """The waypoint being processed (0-based)."""

    _type_name = "nav2_msgs/action/FollowGPSWaypoints_Feedback"
    _fields_and_field_types = {"current_waypoint": "uint32"}
    current_waypoint: int


class FollowGPSWaypoints(Action):
    """``nav2_msgs/action/FollowGPSWaypoints``."""

    _type_name = "nav2_msgs/action/FollowGPSWaypoints"
    Goal = FollowGPSWaypoints_Goal
    Result = FollowGPSWaypoints_Result
    Feedback = FollowGPSWaypoints_Feedback


# --- FollowPath -------------------------------------------------------------------------------


class FollowPath_Goal(Message):
    """Track ``path`` with the named plugins ('' = the server's default)."""

    _type_name = "nav2_msgs/action/FollowPath_Goal"
    _fields_and_field_types = {
        "path": "nav_msgs/Path",
        "controller_id": "string",
        "goal_checker_id": "string",
        "progress_checker_id": "string",
        "path_handler_id": "string",
    }
    path: Path
    controller_id: str
    goal_checker_id: str
    progress_checker_id: str
    path_handler_id: str


@result_codes(FollowPathError)
class FollowPath_Result(Message):
    """How the path following ended."""

    _type_name = "nav2_msgs/action/FollowPath_Result"
    _fields_and_field_types = {"result": "std_msgs/Empty", **_ERROR}
    result: Empty
    error_code: int
    error_msg: str


class FollowPath_Feedback(Message):
    """Rolling's ``tracking_feedback``, and Kilted's path length left (m) and speed (m/s)."""

    _type_name = "nav2_msgs/action/FollowPath_Feedback"
    _fields_and_field_types = {
        "tracking_feedback": "nav2_msgs/TrackingFeedback",
        "distance_to_goal": "float",
        "speed": "float",
    }
    tracking_feedback: TrackingFeedback
    distance_to_goal: float
    speed: float


class FollowPath(Action):
    """``nav2_msgs/action/FollowPath``."""

    _type_name = "nav2_msgs/action/FollowPath"
    Goal = FollowPath_Goal
    Result = FollowPath_Result
    Feedback = FollowPath_Feedback


# --- ComputePathToPose, ComputePathThroughPoses, SmoothPath -----------------------------------


class ComputePathToPose_Goal(Message):
    """Plan to ``goal`` from the robot (from ``start`` with ``use_start``)."""

    _type_name = "nav2_msgs/action/ComputePathToPose_Goal"
    _fields_and_field_types = {
        "goal": "geometry_msgs/PoseStamped",
        "start": "geometry_msgs/PoseStamped",
        "viapoints": "sequence<geometry_msgs/PoseStamped>",
        "planner_id": "string",
        "use_start": "boolean",
    }
    goal: PoseStamped
    start: PoseStamped
    viapoints: list[PoseStamped]
    planner_id: str
    use_start: bool


@result_codes(ComputePathToPoseError)
class ComputePathToPose_Result(Message):
    """The path and how long planning took."""

    _type_name = "nav2_msgs/action/ComputePathToPose_Result"
    _fields_and_field_types = {
        "path": "nav_msgs/Path",
        "planning_time": "builtin_interfaces/Duration",
        **_ERROR,
    }
    path: Path
    planning_time: DurationMsg
    error_code: int
    error_msg: str


class ComputePathToPose_Feedback(Message):
    """No feedback."""

    _type_name = "nav2_msgs/action/ComputePathToPose_Feedback"


class ComputePathToPose(Action):
    """``nav2_msgs/action/ComputePathToPose``."""

    _type_name = "nav2_msgs/action/ComputePathToPose"
    Goal = ComputePathToPose_Goal
    Result = ComputePathToPose_Result
    Feedback = ComputePathToPose_Feedback


class ComputePathThroughPoses_Goal(Message):
    """Plan through ``goals`` in order."""

    _type_name = "nav2_msgs/action/ComputePathThroughPoses_Goal"
    _fields_and_field_types = {
        "goals": "nav_msgs/Goals",
        "start": "geometry_msgs/PoseStamped",
        "planner_id": "string",
        "use_start": "boolean",
    }
    goals: Goals
    start: PoseStamped
    planner_id: str
    use_start: bool


@result_codes(ComputePathThroughPosesError)
class ComputePathThroughPoses_Result(Message):
    """The path, the last goal it reaches (``ALL_GOALS`` -1: every one) and the planning time."""

    ALL_GOALS = -1

    _type_name = "nav2_msgs/action/ComputePathThroughPoses_Result"
    _fields_and_field_types = {
        "path": "nav_msgs/Path",
        "last_reached_index": "int16",
        "planning_time": "builtin_interfaces/Duration",
        **_ERROR,
    }
    path: Path
    last_reached_index: int
    planning_time: DurationMsg
    error_code: int
    error_msg: str


class ComputePathThroughPoses_Feedback(Message):
    """No feedback."""

    _type_name = "nav2_msgs/action/ComputePathThroughPoses_Feedback"


class ComputePathThroughPoses(Action):
    """``nav2_msgs/action/ComputePathThroughPoses``."""

    _type_name = "nav2_msgs/action/ComputePathThroughPoses"
    Goal = ComputePathThroughPoses_Goal
    Result = ComputePathThroughPoses_Result
    Feedback = ComputePathThroughPoses_Feedback


class SmoothPath_Goal(Message):
    """Smooth ``path`` within ``max_smoothing_duration``."""

    _type_name = "nav2_msgs/action/SmoothPath_Goal"
    _fields_and_field_types = {
        "path": "nav_msgs/Path",
        "smoother_id": "string",
        "max_smoothing_duration": "builtin_interfaces/Duration",
        "check_for_collisions": "boolean",
    }
    path: Path
    smoother_id: str
    max_smoothing_duration: DurationMsg
    check_for_collisions: bool


@result_codes(SmoothPathError)
class SmoothPath_Result(Message):
    """The smoothed path, how long it took and whether the smoother converged."""

    _type_name = "nav2_msgs/action/SmoothPath_Result"
    _fields_and_field_types = {
        "path": "nav_msgs/Path",
        "smoothing_duration": "builtin_interfaces/Duration",
        "was_completed": "boolean",
        **_ERROR,
    }
    path: Path
    smoothing_duration: DurationMsg
    was_completed: bool
    error_code: int
    error_msg: str


class SmoothPath_Feedback(Message):
    """No feedback."""

    _type_name = "nav2_msgs/action/SmoothPath_Feedback"


class SmoothPath(Action):
    """``nav2_msgs/action/SmoothPath``."""

    _type_name = "nav2_msgs/action/SmoothPath"
    Goal = SmoothPath_Goal
    Result = SmoothPath_Result
    Feedback = SmoothPath_Feedback
