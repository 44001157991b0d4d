"""The Simple Commander surface against Nav2's current release, written from its documentation.

The tables below restate Nav2 Rolling's ``BasicNavigator`` signatures, enums, action and
message definitions (docs.nav2.org, docs.ros.org nav2_msgs, reference/nav2_ros_facts.md §4-5);
every method and every message field is one test. Fields baobab adds beside Nav2's are listed
in ``BAOBAB_FIELDS``; nothing else may differ.
"""

from __future__ import annotations

import inspect
from typing import Any

import numpy as np
import pytest

from baobab.nav import BasicNavigator, NavigationResult, RunningTask, TaskResult
from baobab.nav.ros.action_msgs.msg import GoalStatus
from baobab.nav.ros.geographic_msgs.msg import GeoPoint, GeoPose
from baobab.nav.ros.nav2_msgs import action
from baobab.nav.ros.nav2_msgs.msg import (
    MissedWaypoint,
    Route,
    RouteEdge,
    RouteNode,
    TrackingFeedback,
    WaypointStatus,
)
from baobab.nav.ros.rclpy.node import Node
from baobab.nav.rosmsg import Message

REQUIRED = inspect.Parameter.empty

METHODS: dict[str, tuple[tuple[str, object], ...]] = {
    "setInitialPose": (("initial_pose", REQUIRED),),
    "goThroughPoses": (("poses", REQUIRED), ("behavior_tree", "")),
    "goToPose": (("pose", REQUIRED), ("behavior_tree", "")),
    "followWaypoints": (("poses", REQUIRED), ("number_of_loops", 0), ("goal_index", 0)),
    "followGpsWaypoints": (("gps_poses", REQUIRED),),
    "spin": (("spin_dist", 1.57), ("time_allowance", 10), ("disable_collision_checks", False)),
    "backup": (
        ("backup_dist", 0.15),
        ("backup_speed", 0.025),
        ("time_allowance", 10),
        ("disable_collision_checks", False),
    ),
    "driveOnHeading": (
        ("dist", 0.15),
        ("speed", 0.025),
        ("time_allowance", 10),
        ("disable_collision_checks", False),
    ),
    "assistedTeleop": (("time_allowance", 30),),
    "followPath": (
        ("path", REQUIRED),
        ("controller_id", ""),
        ("goal_checker_id", ""),
        ("progress_checker_id", ""),
        ("path_handler_id", ""),
    ),
    "dockRobotByPose": (("dock_pose", REQUIRED), ("dock_type", ""), ("nav_to_dock", True)),
    "dockRobotByID": (("dock_id", REQUIRED), ("nav_to_dock", True)),
    "undockRobot": (("dock_type", ""),),
    "followObjectByTopic": (("topic", REQUIRED), ("max_duration", 0)),
    "followObjectByFrame": (("frame", REQUIRED), ("max_duration", 0)),
    "cancelTask": (),
    "isTaskComplete": (("task", RunningTask.NONE),),
    "getFeedback": (("task", RunningTask.NONE),),
    "getResult": (),
    "getTaskError": (),
    "setTaskError": (("error_code", REQUIRED), ("error_msg", REQUIRED)),
    "clearPreviousState": (),
    "waitUntilNav2Active": (("navigator", "bt_navigator"), ("localizer", "amcl")),
    "getPath": (("start", REQUIRED), ("goal", REQUIRED), ("planner_id", ""), ("use_start", False)),
    "getPathThroughPoses": (
        ("start", REQUIRED),
        ("goals", REQUIRED),
        ("planner_id", ""),
        ("use_start", False),
    ),
    "getRoute": (("start", REQUIRED), ("goal", REQUIRED), ("use_start", False)),
    "getAndTrackRoute": (("start", REQUIRED), ("goal", REQUIRED), ("use_start", False)),
    "smoothPath": (
        ("path", REQUIRED),
        ("smoother_id", ""),
        ("max_duration", 2.0),
        ("check_for_collision", False),
    ),
    "changeMap": (("map_filepath", REQUIRED),),
    "clearAllCostmaps": (),
    "clearLocalCostmap": (),
    "clearGlobalCostmap": (),
    "clearCostmapExceptRegion": (("reset_distance", REQUIRED),),
    "clearCostmapAroundRobot": (("reset_distance", REQUIRED),),
    "clearLocalCostmapAroundPose": (("pose", REQUIRED), ("reset_distance", REQUIRED)),
    "clearGlobalCostmapAroundPose": (("pose", REQUIRED), ("reset_distance", REQUIRED)),
    "getGlobalCostmap": (),
    "getLocalCostmap": (),
    "toggleCollisionMonitor": (("enable", REQUIRED),),
    "lifecycleStartup": (),
    "lifecycleShutdown": (),
    "destroyNode": (),
    "destroy_node": (),
    "info": (("msg", REQUIRED),),
    "warn": (("msg", REQUIRED),),
    "error": (("msg", REQUIRED),),
    "debug": (("msg", REQUIRED),),
}
"""Every public method of Rolling's BasicNavigator: its parameters and their defaults."""

OLDER_METHODS: dict[str, tuple[tuple[str, object], ...]] = {
    "clearTaskError": (),  # Kilted (Rolling: clearPreviousState)
    "clearCostmapAroundPose": (("pose", REQUIRED), ("reset_distance", REQUIRED)),  # Jazzy
    "isNavComplete": (("task", RunningTask.NONE),),  # Foxy, Galactic: called without one
    "cancelNav": (),  # Foxy, Galactic
}
"""Methods older releases had and Rolling dropped or renamed."""

ATTRIBUTES = (
    "initial_pose",
    "goal_handle",
    "result_future",
    "feedback",
    "status",
    "route_goal_handle",
    "route_result_future",
    "route_feedback",
    "last_action_error_code",
    "last_action_error_msg",
    "initial_pose_received",
)
"""The attributes Rolling's BasicNavigator sets in its constructor, which scripts read."""


def test_the_constructor_takes_nav2s_arguments_and_baobabs_keyword_only() -> None:
    parameters = list(inspect.signature(BasicNavigator).parameters.values())
    assert [(p.name, p.default) for p in parameters[:2]] == [
        ("node_name", "basic_navigator"),
        ("namespace", ""),
    ]
    assert all(p.kind is p.KEYWORD_ONLY for p in parameters[2:])
    assert [p.name for p in parameters[2:]] == [
        "world",
        "robot",
        "start",
        "seed",
        "realtime",
        "params_file",
        "nav2_substitute",
        "collision_monitor",
    ]


def test_the_method_table_holds_rollings_47_public_methods() -> None:
    assert len(METHODS) == 47


@pytest.mark.parametrize("name", [*METHODS, *OLDER_METHODS])
def test_method_has_nav2s_parameters_and_defaults(name: str) -> None:
    expected = {**METHODS, **OLDER_METHODS}[name]
    parameters = list(inspect.signature(getattr(BasicNavigator, name)).parameters.values())[1:]
    positional = [
        parameter
        for parameter in parameters
        if parameter.kind in (parameter.POSITIONAL_OR_KEYWORD, parameter.POSITIONAL_ONLY)
    ]
    assert [(p.name, p.default) for p in positional] == list(expected)
    # Anything baobab adds is keyword-only with a default, so Nav2's calls bind the same way.
    extra = [p for p in parameters if p not in positional]
    assert all(p.kind is p.KEYWORD_ONLY and p.default is not REQUIRED for p in extra)


def test_every_public_method_is_nav2s_or_a_documented_baobab_addition() -> None:
    baobab_additions = {
        "backUp",  # Galactic's spelling of backup
        "publishTeleop",  # what Nav2 scripts publish on cmd_vel_teleop
        "preemptTeleop",  # what Nav2 scripts publish on preempt_teleop
        "getLastError",  # 2024 development names of the task-error API
        "setLastError",
        "clearLastError",
        "robot_pose",
    }
    ours = {
        name
        for name, value in vars(BasicNavigator).items()
        if callable(value) and not name.startswith("_")
    }
    for base in BasicNavigator.__mro__[1:]:
        if base.__module__.startswith("baobab.nav.navigator"):
            ours |= {
                name
                for name, value in vars(base).items()
                if callable(value) and not name.startswith("_")
            }
    rclpy_node = set(dir(Node))  # BasicNavigator is an rclpy Node, as in Nav2
    assert ours - set(METHODS) - set(OLDER_METHODS) - rclpy_node == baobab_additions


def test_enums_have_the_current_releases_members() -> None:
    assert [(m.name, m.value) for m in TaskResult] == [
        ("UNKNOWN", 0),
        ("SUCCEEDED", 1),
        ("CANCELED", 2),
        ("FAILED", 3),
    ]
    assert NavigationResult is TaskResult
    assert [(m.name, m.value) for m in RunningTask] == [
        ("NONE", 0),
        ("NAVIGATE_TO_POSE", 1),
        ("NAVIGATE_THROUGH_POSES", 2),
        ("FOLLOW_PATH", 3),
        ("FOLLOW_WAYPOINTS", 4),
        ("FOLLOW_GPS_WAYPOINTS", 5),
        ("SPIN", 6),
        ("BACKUP", 7),
        ("DRIVE_ON_HEADING", 8),
        ("ASSISTED_TELEOP", 9),
        ("DOCK_ROBOT", 10),
        ("UNDOCK_ROBOT", 11),
        ("COMPUTE_AND_TRACK_ROUTE", 12),
        ("FOLLOW_OBJECT", 13),
    ]


def test_a_navigator_has_the_attributes_scripts_read() -> None:
    navigator = BasicNavigator(world="walls")
    try:
        for name in ATTRIBUTES:
            assert hasattr(navigator, name), name
        assert navigator.goal_handle is None and navigator.result_future is None
        assert navigator.feedback is None and navigator.status is None
        assert navigator.route_feedback == [] and navigator.initial_pose_received is True
        assert (navigator.last_action_error_code, navigator.last_action_error_msg) == (0, "")
        assert navigator.initial_pose.header.frame_id == "map"
    finally:
        navigator.destroy_node()


# --- messages ---------------------------------------------------------------------------------

POSE = "geometry_msgs/PoseStamped"
DURATION = "builtin_interfaces/Duration"
STATUSES = "sequence<nav2_msgs/WaypointStatus>"
E = {"error_code": ("uint16", 0), "error_msg": ("string", "")}
NAVIGATION_FEEDBACK = {
    "current_pose": (POSE, None),
    "navigation_time": (DURATION, None),
    "estimated_time_remaining": (DURATION, None),
    "number_of_recoveries": ("int16", 0),
    "distance_remaining": ("float", 0.0),
    "position_tracking_error": ("float", 0.0),
    "heading_tracking_error": ("float", 0.0),
}
DRIVE_GOAL = {
    "target": ("geometry_msgs/Point", None),
    "speed": ("float", 0.0),
    "time_allowance": (DURATION, None),
    "disable_collision_checks": ("boolean", False),
}
ELAPSED_RESULT = {"total_elapsed_time": (DURATION, None), **E}
ROUTE_GOAL = {
    "start_id": ("uint16", 0),
    "start": (POSE, None),
    "goal_id": ("uint16", 0),
    "goal": (POSE, None),
    "use_start": ("boolean", False),
    "use_poses": ("boolean", False),
}

MESSAGES: dict[type[Message], dict[str, tuple[str, Any]]] = {
    action.NavigateToPose.Goal: {"pose": (POSE, None), "behavior_tree": ("string", "")},
    action.NavigateToPose.Result: dict(E),
    action.NavigateToPose.Feedback: dict(NAVIGATION_FEEDBACK),
    action.NavigateThroughPoses.Goal: {
        "poses": ("nav_msgs/Goals", None),
        "behavior_tree": ("string", ""),
    },
    action.NavigateThroughPoses.Result: {**E, "waypoint_statuses": (STATUSES, [])},
    action.NavigateThroughPoses.Feedback: {
        **NAVIGATION_FEEDBACK,
        "number_of_poses_remaining": ("int16", 0),
        "waypoint_statuses": (STATUSES, []),
    },
    action.FollowWaypoints.Goal: {
        "number_of_loops": ("uint32", 0),
        "goal_index": ("uint32", 0),
        "poses": (f"sequence<{POSE}>", []),
    },
    action.FollowWaypoints.Result: {"missed_waypoints": (STATUSES, []), **E},
    action.FollowWaypoints.Feedback: {"current_waypoint": ("uint32", 0)},
    action.FollowGPSWaypoints.Goal: {
        "number_of_loops": ("uint32", 0),
        "goal_index": ("uint32", 0),
        "gps_poses": ("sequence<geographic_msgs/GeoPose>", []),
    },
    action.FollowGPSWaypoints.Result: {
        "missed_waypoints": (STATUSES, []),
        "error_code": ("int16", 0),
        "error_msg": ("string", ""),
    },
    action.FollowGPSWaypoints.Feedback: {"current_waypoint": ("uint32", 0)},
    action.FollowPath.Goal: {
        "path": ("nav_msgs/Path", None),
        "controller_id": ("string", ""),
        "goal_checker_id": ("string", ""),
        "progress_checker_id": ("string", ""),
        "path_handler_id": ("string", ""),
    },
    action.FollowPath.Result: {"result": ("std_msgs/Empty", None), **E},
    action.FollowPath.Feedback: {
        "tracking_feedback": ("nav2_msgs/TrackingFeedback", None),
        "distance_to_goal": ("float", 0.0),  # Humble to Kilted
        "speed": ("float", 0.0),  # Humble to Kilted
    },
    action.ComputePathToPose.Goal: {
        "goal": (POSE, None),
        "start": (POSE, None),
        "viapoints": (f"sequence<{POSE}>", []),
        "planner_id": ("string", ""),
        "use_start": ("boolean", False),
    },
    action.ComputePathToPose.Result: {
        "path": ("nav_msgs/Path", None),
        "planning_time": (DURATION, None),
        **E,
    },
    action.ComputePathThroughPoses.Goal: {
        "goals": ("nav_msgs/Goals", None),
        "start": (POSE, None),
        "planner_id": ("string", ""),
        "use_start": ("boolean", False),
    },
    action.ComputePathThroughPoses.Result: {
        "path": ("nav_msgs/Path", None),
        "last_reached_index": ("int16", 0),
        "planning_time": (DURATION, None),
        **E,
    },
    action.SmoothPath.Goal: {
        "path": ("nav_msgs/Path", None),
        "smoother_id": ("string", ""),
        "max_smoothing_duration": (DURATION, None),
        "check_for_collisions": ("boolean", False),
    },
    action.SmoothPath.Result: {
        "path": ("nav_msgs/Path", None),
        "smoothing_duration": (DURATION, None),
        "was_completed": ("boolean", False),
        **E,
    },
    action.Spin.Goal: {
        "target_yaw": ("float", 0.0),
        "time_allowance": (DURATION, None),
        "disable_collision_checks": ("boolean", False),
    },
    action.Spin.Result: dict(ELAPSED_RESULT),
    action.Spin.Feedback: {"angular_distance_traveled": ("float", 0.0)},
    action.BackUp.Goal: dict(DRIVE_GOAL),
    action.BackUp.Result: dict(ELAPSED_RESULT),
    action.BackUp.Feedback: {"distance_traveled": ("float", 0.0)},
    action.DriveOnHeading.Goal: dict(DRIVE_GOAL),
    action.DriveOnHeading.Result: dict(ELAPSED_RESULT),
    action.DriveOnHeading.Feedback: {"distance_traveled": ("float", 0.0)},
    action.Wait.Goal: {"time": (DURATION, None)},
    action.Wait.Result: dict(ELAPSED_RESULT),
    action.Wait.Feedback: {"time_left": (DURATION, None)},
    action.AssistedTeleop.Goal: {"time_allowance": (DURATION, None)},
    action.AssistedTeleop.Result: dict(ELAPSED_RESULT),
    action.AssistedTeleop.Feedback: {"current_teleop_duration": (DURATION, None)},
    action.DockRobot.Goal: {
        "use_dock_id": ("boolean", True),
        "dock_id": ("string", ""),
        "dock_pose": (POSE, None),
        "dock_type": ("string", ""),
        "max_staging_time": ("float", 1000.0),
        "navigate_to_staging_pose": ("boolean", True),
    },
    action.DockRobot.Result: {
        "success": ("boolean", True),
        "error_code": ("uint16", 0),
        "num_retries": ("uint16", 0),
        "error_msg": ("string", ""),
    },
    action.DockRobot.Feedback: {
        "state": ("uint16", 0),
        "docking_time": (DURATION, None),
        "num_retries": ("uint16", 0),
    },
    action.UndockRobot.Goal: {"dock_type": ("string", ""), "max_undocking_time": ("float", 30.0)},
    action.UndockRobot.Result: {"success": ("boolean", True), **E},
    action.FollowObject.Goal: {
        "pose_topic": ("string", ""),
        "tracked_frame": ("string", ""),
        "max_duration": (DURATION, None),
    },
    action.FollowObject.Result: {
        "total_elapsed_time": (DURATION, None),
        "error_code": ("uint16", 0),
        "num_retries": ("uint16", 0),
        "error_msg": ("string", ""),
    },
    action.FollowObject.Feedback: {
        "state": ("uint16", 0),
        "following_time": (DURATION, None),
        "num_retries": ("uint16", 0),
    },
    action.ComputeRoute.Goal: dict(ROUTE_GOAL),
    action.ComputeRoute.Result: {
        "planning_time": (DURATION, None),
        "path": ("nav_msgs/Path", None),
        "route": ("nav2_msgs/Route", None),
        **E,
    },
    action.ComputeAndTrackRoute.Goal: dict(ROUTE_GOAL),
    action.ComputeAndTrackRoute.Result: {"execution_duration": (DURATION, None), **E},
    action.ComputeAndTrackRoute.Feedback: {
        "last_node_id": ("uint16", 0),
        "next_node_id": ("uint16", 0),
        "current_edge_id": ("uint16", 0),
        "route": ("nav2_msgs/Route", None),
        "path": ("nav_msgs/Path", None),
        "operations_triggered": ("sequence<string>", []),
        "rerouted": ("boolean", False),
    },
    WaypointStatus: {
        "waypoint_status": ("uint8", 0),
        "waypoint_index": ("uint32", 0),
        "waypoint_pose": (POSE, None),
        "error_code": ("uint16", 0),
        "error_msg": ("string", ""),
    },
    MissedWaypoint: {"index": ("uint32", 0), "goal": (POSE, None), "error_code": ("uint16", 0)},
    TrackingFeedback: {
        "header": ("std_msgs/Header", None),
        "position_tracking_error": ("float", 0.0),
        "heading_tracking_error": ("float", 0.0),
        "current_path_index": ("uint32", 0),
        "robot_pose": (POSE, None),
        "distance_to_goal": ("float", 0.0),
        "speed": ("float", 0.0),
        "remaining_path_length": ("float", 0.0),
    },
    Route: {
        "header": ("std_msgs/Header", None),
        "route_cost": ("float", 0.0),
        "nodes": ("sequence<nav2_msgs/RouteNode>", []),
        "edges": ("sequence<nav2_msgs/RouteEdge>", []),
    },
    RouteNode: {"nodeid": ("uint16", 0), "position": ("geometry_msgs/Point", None)},
    RouteEdge: {
        "edgeid": ("uint16", 0),
        "start": ("geometry_msgs/Point", None),
        "end": ("geometry_msgs/Point", None),
    },
    GeoPoint: {
        "latitude": ("double", 0.0),
        "longitude": ("double", 0.0),
        "altitude": ("double", 0.0),
    },
    GeoPose: {
        "position": ("geographic_msgs/GeoPoint", None),
        "orientation": ("geometry_msgs/Quaternion", None),
    },
    GoalStatus: {"goal_info": ("action_msgs/GoalInfo", None), "status": ("int8", 0)},
}
"""Field types and defaults (None: a nested message, checked by type) of each message."""

EMPTY_FEEDBACK = (
    action.ComputePathToPose.Feedback,
    action.ComputePathThroughPoses.Feedback,
    action.SmoothPath.Feedback,
    action.UndockRobot.Feedback,
    action.ComputeRoute.Feedback,
)
BAOBAB_FIELDS = {action.FollowWaypoints.Feedback: {"missed_waypoints"}}
"""Fields baobab adds: the waypoints missed so far (Nav2 reports them in the result only)."""

FIELD_CASES = [
    pytest.param(cls, field, id=f"{cls.__name__}.{field}")
    for cls, fields in MESSAGES.items()
    for field in fields
]


@pytest.mark.parametrize(("cls", "field"), FIELD_CASES)
def test_message_field_has_nav2s_type_and_default(cls: type[Message], field: str) -> None:
    kind, default = MESSAGES[cls][field]
    assert cls.get_fields_and_field_types()[field] == kind
    value = getattr(cls(), field)
    if default is None:
        package, _, name = kind.partition("/")
        assert type(value)._type_name == f"{package}/msg/{name}"
    elif isinstance(value, np.ndarray):
        assert value.tolist() == default
    else:
        assert value == default and type(value) is type(default)


@pytest.mark.parametrize("cls", [*MESSAGES, *EMPTY_FEEDBACK], ids=lambda cls: cls.__name__)
def test_message_has_no_fields_beyond_nav2s(cls: type[Message]) -> None:
    expected = set(MESSAGES.get(cls, {})) | BAOBAB_FIELDS.get(cls, set())
    assert set(cls.get_fields_and_field_types()) == expected


RESULT_CODES: dict[type[Any], dict[str, int]] = {
    action.NavigateToPose: {
        "UNKNOWN": 9000,
        "FAILED_TO_LOAD_BEHAVIOR_TREE": 9001,
        "TF_ERROR": 9002,
        "TIMEOUT": 9003,
    },
    action.NavigateThroughPoses: {
        "UNKNOWN": 9100,
        "FAILED_TO_LOAD_BEHAVIOR_TREE": 9101,
        "TF_ERROR": 9102,
        "TIMEOUT": 9103,
    },
    action.FollowWaypoints: {
        "UNKNOWN": 600,
        "TASK_EXECUTOR_FAILED": 601,
        "NO_VALID_WAYPOINTS": 602,
        "STOP_ON_MISSED_WAYPOINT": 603,
    },
    action.FollowGPSWaypoints: {
        "UNKNOWN": 600,
        "TASK_EXECUTOR_FAILED": 601,
        "NO_WAYPOINTS_GIVEN": 602,
        "STOP_ON_MISSED_WAYPOINT": 603,
    },
    action.FollowPath: {
        "UNKNOWN": 100,
        "INVALID_CONTROLLER": 101,
        "TF_ERROR": 102,
        "INVALID_PATH": 103,
        "PATIENCE_EXCEEDED": 104,
        "FAILED_TO_MAKE_PROGRESS": 105,
        "NO_VALID_CONTROL": 106,
        "CONTROLLER_TIMED_OUT": 107,
        "TIMEOUT": 108,
    },
    action.ComputePathToPose: {
        "UNKNOWN": 200,
        "INVALID_PLANNER": 201,
        "TF_ERROR": 202,
        "START_OUTSIDE_MAP": 203,
        "GOAL_OUTSIDE_MAP": 204,
        "START_OCCUPIED": 205,
        "GOAL_OCCUPIED": 206,
        "TIMEOUT": 207,
        "NO_VALID_PATH": 208,
    },
    action.ComputePathThroughPoses: {
        "UNKNOWN": 300,
        "INVALID_PLANNER": 301,
        "NO_VALID_PATH": 308,
        "NO_VIAPOINTS_GIVEN": 309,
        "ALL_GOALS": -1,
    },
    action.SmoothPath: {
        "UNKNOWN": 500,
        "INVALID_SMOOTHER": 501,
        "TIMEOUT": 502,
        "SMOOTHED_PATH_IN_COLLISION": 503,
        "FAILED_TO_SMOOTH_PATH": 504,
        "INVALID_PATH": 505,
    },
    action.Spin: {"UNKNOWN": 700, "TIMEOUT": 701, "TF_ERROR": 702, "COLLISION_AHEAD": 703},
    action.BackUp: {
        "UNKNOWN": 710,
        "TIMEOUT": 711,
        "TF_ERROR": 712,
        "INVALID_INPUT": 713,
        "COLLISION_AHEAD": 714,
    },
    action.DriveOnHeading: {
        "UNKNOWN": 720,
        "TIMEOUT": 721,
        "TF_ERROR": 722,
        "COLLISION_AHEAD": 723,
        "INVALID_INPUT": 724,
    },
    action.AssistedTeleop: {"UNKNOWN": 730, "TIMEOUT": 731, "TF_ERROR": 732},
    action.Wait: {"UNKNOWN": 740, "TIMEOUT": 741},
    action.DockRobot: {
        "DOCK_NOT_IN_DB": 901,
        "DOCK_NOT_VALID": 902,
        "FAILED_TO_STAGE": 903,
        "FAILED_TO_DETECT_DOCK": 904,
        "FAILED_TO_CONTROL": 905,
        "FAILED_TO_CHARGE": 906,
        "TIMEOUT": 907,
        "UNKNOWN": 999,
    },
    action.UndockRobot: {
        "DOCK_NOT_VALID": 902,
        "FAILED_TO_CONTROL": 905,
        "TIMEOUT": 907,
        "UNKNOWN": 999,
    },
    action.FollowObject: {
        "TF_ERROR": 901,
        "FAILED_TO_DETECT_OBJECT": 902,
        "FAILED_TO_CONTROL": 903,
        "TIMEOUT": 904,
        "UNKNOWN": 999,
    },
    action.ComputeRoute: {
        "UNKNOWN": 400,
        "TF_ERROR": 401,
        "NO_VALID_GRAPH": 402,
        "INDETERMINANT_NODES_ON_GRAPH": 403,
        "TIMEOUT": 404,
        "NO_VALID_ROUTE": 405,
        "INVALID_EDGE_SCORER_USE": 407,
    },
    action.ComputeAndTrackRoute: {"UNKNOWN": 400, "OPERATION_FAILED": 406, "TIMEOUT": 404},
}
"""Result codes (every result also defines NONE = 0)."""

WITHOUT_COMMON_CODES = (action.FollowWaypoints, action.FollowGPSWaypoints)
"""The only results without GOAL_REJECTED = 1 and SEND_GOAL_FAILURE = 2."""


@pytest.mark.parametrize("kind", RESULT_CODES, ids=lambda kind: kind.__name__)
def test_result_codes_are_nav2s(kind: type[Any]) -> None:
    result = kind.Result
    assert result.NONE == 0
    for name, code in RESULT_CODES[kind].items():
        assert getattr(result, name) == code, name
    common = kind not in WITHOUT_COMMON_CODES
    assert (getattr(result, "GOAL_REJECTED", None) == 1) is common
    assert (getattr(result, "SEND_GOAL_FAILURE", None) == 2) is common


def test_message_constants_and_action_classes() -> None:
    assert (WaypointStatus.PENDING, WaypointStatus.COMPLETED) == (0, 1)
    assert (WaypointStatus.SKIPPED, WaypointStatus.FAILED) == (2, 3)
    assert [GoalStatus.STATUS_SUCCEEDED, GoalStatus.STATUS_CANCELED, GoalStatus.STATUS_ABORTED] == [
        4,
        5,
        6,
    ]
    feedback = action.DockRobot.Feedback
    assert (feedback.NAV_TO_STAGING_POSE, feedback.WAIT_FOR_CHARGE, feedback.RETRY) == (1, 4, 5)
    assert (action.FollowObject.Feedback.CONTROLLING, action.FollowObject.Feedback.RETRY) == (2, 4)
    assert action.NavigateToPose.Feedback.__name__ == "NavigateToPose_Feedback"
    assert repr(action.Spin.Feedback()) == (
        "nav2_msgs.action.Spin_Feedback(angular_distance_traveled=0.0)"
    )
    with pytest.raises(NotImplementedError):
        action.NavigateToPose()
    with pytest.raises(AssertionError, match="position_tracking_error"):
        action.NavigateToPose.Feedback().position_tracking_error = 1  # an int, as rclpy refuses
