"""Result codes of the Nav2 servers baobab does not run yet: GPS waypoints and routes.

The action messages define them (``ComputeRoute.Result.NO_VALID_ROUTE``) and the navigator
reports their UNKNOWN when a call finds no server. They are kept apart from
:mod:`baobab.nav.errors` because mission validation takes every code there as one a run can
end with; each enum moves there with its server.
"""

from __future__ import annotations

from enum import IntEnum


class FollowGPSWaypointsError(IntEnum):
    """``nav2_msgs/action/FollowGPSWaypoints`` result codes (waypoint follower)."""

    NONE = 0
    UNKNOWN = 600
    TASK_EXECUTOR_FAILED = 601
    NO_WAYPOINTS_GIVEN = 602
    STOP_ON_MISSED_WAYPOINT = 603


class ComputeRouteError(IntEnum):
    """``nav2_msgs/action/ComputeRoute`` result codes (route server)."""

    NONE = 0
    UNKNOWN = 400
    TF_ERROR = 401
    NO_VALID_GRAPH = 402
    INDETERMINANT_NODES_ON_GRAPH = 403
    TIMEOUT = 404
    NO_VALID_ROUTE = 405
    INVALID_EDGE_SCORER_USE = 407


class ComputeAndTrackRouteError(IntEnum):
    """``nav2_msgs/action/ComputeAndTrackRoute`` result codes (route server)."""

    NONE = 0
    UNKNOWN = 400
    TF_ERROR = 401
    NO_VALID_GRAPH = 402
    INDETERMINANT_NODES_ON_GRAPH = 403
    TIMEOUT = 404
    NO_VALID_ROUTE = 405
    OPERATION_FAILED = 406
    INVALID_EDGE_SCORER_USE = 407
