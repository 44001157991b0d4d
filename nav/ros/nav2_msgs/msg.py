"""``nav2_msgs.msg``: costmaps, waypoint statuses, path tracking feedback and routes.

Fields, types and defaults are those of Nav2's current release (reference/nav2_ros_facts.md
§5); ``MissedWaypoint`` is Jazzy's, kept for scripts written against it.
"""

from __future__ import annotations

from baobab.nav.msgs import Costmap, CostmapMetaData, Header, Point, PoseStamped
from baobab.nav.rosmsg import Message

__all__ = [
    "Costmap",
    "CostmapMetaData",
    "MissedWaypoint",
    "Route",
    "RouteEdge",
    "RouteNode",
    "TrackingFeedback",
    "WaypointStatus",
]


class WaypointStatus(Message):
    """``nav2_msgs/WaypointStatus``: how one waypoint of a goal list went."""

    PENDING = 0
    COMPLETED = 1
    SKIPPED = 2
    FAILED = 3

    _type_name = "nav2_msgs/msg/WaypointStatus"
    _fields_and_field_types = {
        "waypoint_status": "uint8",
        "waypoint_index": "uint32",
        "waypoint_pose": "geometry_msgs/PoseStamped",
        "error_code": "uint16",
        "error_msg": "string",
    }
    waypoint_status: int
    waypoint_index: int
    waypoint_pose: PoseStamped
    error_code: int
    error_msg: str


class MissedWaypoint(Message):
    """``nav2_msgs/MissedWaypoint`` (Jazzy): a waypoint the follower could not reach."""

    _type_name = "nav2_msgs/msg/MissedWaypoint"
    _fields_and_field_types = {
        "index": "uint32",
        "goal": "geometry_msgs/PoseStamped",
        "error_code": "uint16",
    }
    index: int
    goal: PoseStamped
    error_code: int


class TrackingFeedback(Message):
    """``nav2_msgs/TrackingFeedback``: how closely the controller follows its path.

    ``position_tracking_error`` (m) is positive with the robot left of the path;
    ``heading_tracking_error`` (rad) is positive with the robot's heading rotated right of the
    path's direction. ``distance_to_goal`` is the straight distance (m) to the path's end,
    ``remaining_path_length`` the length (m) of path left, ``speed`` the odometry speed (m/s).
    """

    _type_name = "nav2_msgs/msg/TrackingFeedback"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "position_tracking_error": "float",
        "heading_tracking_error": "float",
        "current_path_index": "uint32",
        "robot_pose": "geometry_msgs/PoseStamped",
        "distance_to_goal": "float",
        "speed": "float",
        "remaining_path_length": "float",
    }
    header: Header
    position_tracking_error: float
    heading_tracking_error: float
    current_path_index: int
    robot_pose: PoseStamped
    distance_to_goal: float
    speed: float
    remaining_path_length: float


class RouteNode(Message):
    """``nav2_msgs/RouteNode``: a node of a route graph."""

    _type_name = "nav2_msgs/msg/RouteNode"
    _fields_and_field_types = {"nodeid": "uint16", "position": "geometry_msgs/Point"}
    nodeid: int
    position: Point


class RouteEdge(Message):
    """``nav2_msgs/RouteEdge``: an edge of a route graph, from ``start`` to ``end``."""

    _type_name = "nav2_msgs/msg/RouteEdge"
    _fields_and_field_types = {
        "edgeid": "uint16",
        "start": "geometry_msgs/Point",
        "end": "geometry_msgs/Point",
    }
    edgeid: int
    start: Point
    end: Point


class Route(Message):
    """``nav2_msgs/Route``: the nodes and edges of a planned route and its cost."""

    _type_name = "nav2_msgs/msg/Route"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "route_cost": "float",
        "nodes": "sequence<nav2_msgs/RouteNode>",
        "edges": "sequence<nav2_msgs/RouteEdge>",
    }
    header: Header
    route_cost: float
    nodes: list[RouteNode]
    edges: list[RouteEdge]
