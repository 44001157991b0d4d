"""The actions of Nav2's newer servers: docking, object following and the route server.

Fields, types and defaults of Nav2's current release (reference/nav2_ros_facts.md §5).
FollowObject is Rolling's (``nav2_msgs``; it started in ``opennav_following_msgs``).
"""

from __future__ import annotations

from baobab.nav.errors import (
    ComputeAndTrackRouteError,
    ComputeRouteError,
    DockRobotError,
    FollowObjectError,
    UndockRobotError,
)
from baobab.nav.msgs import Path, PoseStamped
from baobab.nav.ros.nav2_msgs.msg import Route
from baobab.nav.rosaction import Action, result_codes
from baobab.nav.rosmsg import Message
from baobab.nav.rostime import DurationMsg

# --- DockRobot, UndockRobot -------------------------------------------------------------------


class DockRobot_Goal(Message):
    """Dock at the dock ``dock_id`` (``use_dock_id``) or at ``dock_pose`` of ``dock_type``."""

    _type_name = "nav2_msgs/action/DockRobot_Goal"
    _fields_and_field_types = {
        "use_dock_id": "boolean",
        "dock_id": "string",
        "dock_pose": "geometry_msgs/PoseStamped",
        "dock_type": "string",
        "max_staging_time": "float",
        "navigate_to_staging_pose": "boolean",
    }
    _defaults = {"use_dock_id": True, "max_staging_time": 1000.0, "navigate_to_staging_pose": True}
    use_dock_id: bool
    dock_id: str
    dock_pose: PoseStamped
    dock_type: str
    max_staging_time: float
    navigate_to_staging_pose: bool


@result_codes(DockRobotError)
class DockRobot_Result(Message):
    """Whether docking worked, its code and the retries it took."""

    _type_name = "nav2_msgs/action/DockRobot_Result"
    _fields_and_field_types = {
        "success": "boolean",
        "error_code": "uint16",
        "num_retries": "uint16",
        "error_msg": "string",
    }
    _defaults = {"success": True}
    success: bool
    error_code: int
    num_retries: int
    error_msg: str


class DockRobot_Feedback(Message):
    """The docking state, time so far and retries."""

    NONE = 0
    NAV_TO_STAGING_POSE = 1
    INITIAL_PERCEPTION = 2
    CONTROLLING = 3
    WAIT_FOR_CHARGE = 4
    RETRY = 5

    _type_name = "nav2_msgs/action/DockRobot_Feedback"
    _fields_and_field_types = {
        "state": "uint16",
        "docking_time": "builtin_interfaces/Duration",
        "num_retries": "uint16",
    }
    state: int
    docking_time: DurationMsg
    num_retries: int


class DockRobot(Action):
    """``nav2_msgs/action/DockRobot``."""

    _type_name = "nav2_msgs/action/DockRobot"
    Goal = DockRobot_Goal
    Result = DockRobot_Result
    Feedback = DockRobot_Feedback


class UndockRobot_Goal(Message):
    """Undock from the current dock (of ``dock_type``) within ``max_undocking_time`` (s)."""

    _type_name = "nav2_msgs/action/UndockRobot_Goal"
    _fields_and_field_types = {"dock_type": "string", "max_undocking_time": "float"}
    _defaults = {"max_undocking_time": 30.0}
    dock_type: str
    max_undocking_time: float


@result_codes(UndockRobotError)
class UndockRobot_Result(Message):
    """Whether undocking worked, and its code."""

    _type_name = "nav2_msgs/action/UndockRobot_Result"
    _fields_and_field_types = {"success": "boolean", "error_code": "uint16", "error_msg": "string"}
    _defaults = {"success": True}
    success: bool
    error_code: int
    error_msg: str


class UndockRobot_Feedback(Message):
    """No feedback."""

    _type_name = "nav2_msgs/action/UndockRobot_Feedback"


class UndockRobot(Action):
    """``nav2_msgs/action/UndockRobot``."""

    _type_name = "nav2_msgs/action/UndockRobot"
    Goal = UndockRobot_Goal
    Result = UndockRobot_Result
    Feedback = UndockRobot_Feedback


# --- FollowObject -----------------------------------------------------------------------------


class FollowObject_Goal(Message):
    """Follow the poses on ``pose_topic`` (or the TF frame ``tracked_frame``)."""

    _type_name = "nav2_msgs/action/FollowObject_Goal"
    _fields_and_field_types = {
        "pose_topic": "string",
        "tracked_frame": "string",
        "max_duration": "builtin_interfaces/Duration",
    }
    pose_topic: str
    tracked_frame: str
    max_duration: DurationMsg


@result_codes(FollowObjectError)
class FollowObject_Result(Message):
    """How long the following lasted, its code and retries."""

    _type_name = "nav2_msgs/action/FollowObject_Result"
    _fields_and_field_types = {
        "total_elapsed_time": "builtin_interfaces/Duration",
        "error_code": "uint16",
        "num_retries": "uint16",
        "error_msg": "string",
    }
    total_elapsed_time: DurationMsg
    error_code: int
    num_retries: int
    error_msg: str


class FollowObject_Feedback(Message):
    """The following state, time so far and retries."""

    NONE = 0
    INITIAL_PERCEPTION = 1
    CONTROLLING = 2
    STOPPING = 3
    RETRY = 4

    _type_name = "nav2_msgs/action/FollowObject_Feedback"
    _fields_and_field_types = {
        "state": "uint16",
        "following_time": "builtin_interfaces/Duration",
        "num_retries": "uint16",
    }
    state: int
    following_time: DurationMsg
    num_retries: int


class FollowObject(Action):
    """``nav2_msgs/action/FollowObject``."""

    _type_name = "nav2_msgs/action/FollowObject"
    Goal = FollowObject_Goal
    Result = FollowObject_Result
    Feedback = FollowObject_Feedback


# --- ComputeRoute, ComputeAndTrackRoute -------------------------------------------------------

_ROUTE_GOAL = {
    "start_id": "uint16",
    "start": "geometry_msgs/PoseStamped",
    "goal_id": "uint16",
    "goal": "geometry_msgs/PoseStamped",
    "use_start": "boolean",
    "use_poses": "boolean",
}


class ComputeRoute_Goal(Message):
    """Route between graph nodes (ids) or, with ``use_poses``, between poses."""

    _type_name = "nav2_msgs/action/ComputeRoute_Goal"
    _fields_and_field_types = dict(_ROUTE_GOAL)
    start_id: int
    start: PoseStamped
    goal_id: int
    goal: PoseStamped
    use_start: bool
    use_poses: bool


@result_codes(ComputeRouteError)
class ComputeRoute_Result(Message):
    """The route (sparse nodes and edges) and its dense path."""

    _type_name = "nav2_msgs/action/ComputeRoute_Result"
    _fields_and_field_types = {
        "planning_time": "builtin_interfaces/Duration",
        "path": "nav_msgs/Path",
        "route": "nav2_msgs/Route",
        "error_code": "uint16",
        "error_msg": "string",
    }
    planning_time: DurationMsg
    path: Path
    route: Route
    error_code: int
    error_msg: str


class ComputeRoute_Feedback(Message):
    """No feedback."""

    _type_name = "nav2_msgs/action/ComputeRoute_Feedback"


class ComputeRoute(Action):
    """``nav2_msgs/action/ComputeRoute``."""

    _type_name = "nav2_msgs/action/ComputeRoute"
    Goal = ComputeRoute_Goal
    Result = ComputeRoute_Result
    Feedback = ComputeRoute_Feedback


class ComputeAndTrackRoute_Goal(Message):
    """As ComputeRoute's goal; the route is then tracked as the robot drives it."""

    _type_name = "nav2_msgs/action/ComputeAndTrackRoute_Goal"
    _fields_and_field_types = dict(_ROUTE_GOAL)
    start_id: int
    start: PoseStamped
    goal_id: int
    goal: PoseStamped
    use_start: bool
    use_poses: bool


@result_codes(ComputeAndTrackRouteError)
class ComputeAndTrackRoute_Result(Message):
    """How long the tracking ran and how it ended."""

    _type_name = "nav2_msgs/action/ComputeAndTrackRoute_Result"
    _fields_and_field_types = {
        "execution_duration": "builtin_interfaces/Duration",
        "error_code": "uint16",
        "error_msg": "string",
    }
    execution_duration: DurationMsg
    error_code: int
    error_msg: str


class ComputeAndTrackRoute_Feedback(Message):
    """Progress along the route; ``rerouted`` when ``route`` and ``path`` are new."""

    _type_name = "nav2_msgs/action/ComputeAndTrackRoute_Feedback"
    _fields_and_field_types = {
        "last_node_id": "uint16",
        "next_node_id": "uint16",
        "current_edge_id": "uint16",
        "route": "nav2_msgs/Route",
        "path": "nav_msgs/Path",
        "operations_triggered": "sequence<string>",
        "rerouted": "boolean",
    }
    last_node_id: int
    next_node_id: int
    current_edge_id: int
    route: Route
    path: Path
    operations_triggered: list[str]
    rerouted: bool


class ComputeAndTrackRoute(Action):
    """``nav2_msgs/action/ComputeAndTrackRoute``."""

    _type_name = "nav2_msgs/action/ComputeAndTrackRoute"
    Goal = ComputeAndTrackRoute_Goal
    Result = ComputeAndTrackRoute_Result
    Feedback = ComputeAndTrackRoute_Feedback
