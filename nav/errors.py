"""Navigation error codes, with Nav2's names and numbers, and the exception that carries them.

Each Nav2 action has its own range of codes (reference/nav2.md §2): controller 1xx, planner 2xx,
through-poses planner 3xx, smoother 5xx, waypoint follower 6xx, behaviours 7xx, navigators
9000/9100, the route server 4xx, the GPS waypoint follower 6xx, docking and following servers
9xx. ``NONE = 0`` means success everywhere.
When several actions failed during one navigation, Nav2 reports the numerically lowest non-zero
code (:func:`reported_error_code`).
"""

from __future__ import annotations

from collections.abc import Iterable
from enum import IntEnum

from baobab.sim.errors import BaobabError


class FollowPathError(IntEnum):
    """``nav2_msgs/action/FollowPath`` result codes (controller server)."""

    NONE = 0
    UNKNOWN = 100
    INVALID_CONTROLLER = 101
    TF_ERROR = 102
    INVALID_PATH = 103
    PATIENCE_EXCEEDED = 104
    FAILED_TO_MAKE_PROGRESS = 105
    NO_VALID_CONTROL = 106
    CONTROLLER_TIMED_OUT = 107
    TIMEOUT = 108


class ComputePathToPoseError(IntEnum):
    """``nav2_msgs/action/ComputePathToPose`` result codes (planner server)."""

    NONE = 0
    UNKNOWN = 200
    INVALID_PLANNER = 201
    TF_ERROR = 202
    START_OUTSIDE_MAP = 203
    GOAL_OUTSIDE_MAP = 204
    START_OCCUPIED = 205
    GOAL_OCCUPIED = 206
    TIMEOUT = 207
    NO_VALID_PATH = 208


class ComputePathThroughPosesError(IntEnum):
    """``nav2_msgs/action/ComputePathThroughPoses`` result codes (planner server)."""

    NONE = 0
    UNKNOWN = 300
    INVALID_PLANNER = 301
    TF_ERROR = 302
    START_OUTSIDE_MAP = 303
    GOAL_OUTSIDE_MAP = 304
    START_OCCUPIED = 305
    GOAL_OCCUPIED = 306
    TIMEOUT = 307
    NO_VALID_PATH = 308
    NO_VIAPOINTS_GIVEN = 309


class SmoothPathError(IntEnum):
    """``nav2_msgs/action/SmoothPath`` result codes (smoother server)."""

    NONE = 0
    UNKNOWN = 500
    INVALID_SMOOTHER = 501
    TIMEOUT = 502
    SMOOTHED_PATH_IN_COLLISION = 503
    FAILED_TO_SMOOTH_PATH = 504
    INVALID_PATH = 505


class FollowWaypointsError(IntEnum):
    """``nav2_msgs/action/FollowWaypoints`` result codes (waypoint follower)."""

    NONE = 0
    UNKNOWN = 600
    TASK_EXECUTOR_FAILED = 601
    NO_VALID_WAYPOINTS = 602
    STOP_ON_MISSED_WAYPOINT = 603


class FollowGPSWaypointsError(IntEnum):
    """``nav2_msgs/action/FollowGPSWaypoints`` result codes (waypoint follower)."""

    NONE = 0
    UNKNOWN = 600
    TASK_EXECUTOR_FAILED = 601
    NO_WAYPOINTS_GIVEN = 602
    STOP_ON_MISSED_WAYPOINT = 603


class SpinError(IntEnum):
    """``nav2_msgs/action/Spin`` result codes (behaviour server)."""

    NONE = 0
    UNKNOWN = 700
    TIMEOUT = 701
    TF_ERROR = 702
    COLLISION_AHEAD = 703


class BackUpError(IntEnum):
    """``nav2_msgs/action/BackUp`` result codes (behaviour server)."""

    NONE = 0
    UNKNOWN = 710
    TIMEOUT = 711
    TF_ERROR = 712
    INVALID_INPUT = 713
    COLLISION_AHEAD = 714


class DriveOnHeadingError(IntEnum):
    """``nav2_msgs/action/DriveOnHeading`` result codes (behaviour server)."""

    NONE = 0
    UNKNOWN = 720
    TIMEOUT = 721
    TF_ERROR = 722
    COLLISION_AHEAD = 723
    INVALID_INPUT = 724


class AssistedTeleopError(IntEnum):
    """``nav2_msgs/action/AssistedTeleop`` result codes (behaviour server)."""

    NONE = 0
    UNKNOWN = 730
    TIMEOUT = 731
    TF_ERROR = 732


class WaitError(IntEnum):
    """``nav2_msgs/action/Wait`` result codes (behaviour server)."""

    NONE = 0
    UNKNOWN = 740
    TIMEOUT = 741


class NavigateToPoseError(IntEnum):
    """``nav2_msgs/action/NavigateToPose`` result codes (BT navigator's own errors)."""

    NONE = 0
    UNKNOWN = 9000
    FAILED_TO_LOAD_BEHAVIOR_TREE = 9001
    TF_ERROR = 9002
    TIMEOUT = 9003


class NavigateThroughPosesError(IntEnum):
    """``nav2_msgs/action/NavigateThroughPoses`` result codes (BT navigator's own errors)."""

    NONE = 0
    UNKNOWN = 9100
    FAILED_TO_LOAD_BEHAVIOR_TREE = 9101
    TF_ERROR = 9102
    TIMEOUT = 9103


class DockRobotError(IntEnum):
    """``nav2_msgs/action/DockRobot`` result codes (docking server)."""

    NONE = 0
    DOCK_NOT_IN_DB = 901
    DOCK_NOT_VALID = 902
    FAILED_TO_STAGE = 903
    FAILED_TO_DETECT_DOCK = 904
    FAILED_TO_CONTROL = 905
    FAILED_TO_CHARGE = 906
    TIMEOUT = 907
    UNKNOWN = 999


class UndockRobotError(IntEnum):
    """``nav2_msgs/action/UndockRobot`` result codes (docking server)."""

    NONE = 0
    DOCK_NOT_VALID = 902
    FAILED_TO_CONTROL = 905
    TIMEOUT = 907
    UNKNOWN = 999


class FollowObjectError(IntEnum):
    """``nav2_msgs/action/FollowObject`` result codes (following server, Rolling)."""

    NONE = 0
    TF_ERROR = 901
    FAILED_TO_DETECT_OBJECT = 902
    FAILED_TO_CONTROL = 903
    TIMEOUT = 904
    UNKNOWN = 999


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


class NavigationError(BaobabError):
    """A navigation step failed with a Nav2 error code.

    Attributes:
        code: the Nav2 code, an ``IntEnum`` member of one of the enums above (or a plain int).
        message: one line saying what went wrong, for ``error_msg``.
    """

    def __init__(self, code: IntEnum | int, message: str) -> None:
        self.code = code
        self.message = message
        super().__init__(f"{self.code_name} ({int(code)}): {message}")

    @property
    def code_name(self) -> str:
        """The code's Nav2 name (``NO_VALID_PATH``), or its number when it has no name."""
        return self.code.name if isinstance(self.code, IntEnum) else str(int(self.code))


class GoalRejectedError(BaobabError):
    """A goal refused before any server works on it (the navigator's send returns None).

    Attributes:
        code: the action's error code for it; None means the action's UNKNOWN, which is what
            Nav2's client reports for a rejected goal.
    """

    def __init__(self, message: str, code: IntEnum | None = None) -> None:
        super().__init__(message)
        self.code = code


class CollisionAheadError(NavigationError):
    """The controller's projected motion up to the carrot runs into lethal space.

    Nav2's Regulated Pure Pursuit reports this as ``NO_VALID_CONTROL`` ("detected collision
    ahead"); the distinct type lets a caller tell it from other control failures.
    """

    def __init__(self, message: str = "collision ahead") -> None:
        super().__init__(FollowPathError.NO_VALID_CONTROL, message)


def reported_error_code(codes: Iterable[int]) -> int:
    """The code a navigator reports after several actions ran: the lowest non-zero, else 0.

    This is Nav2's rule (reference/nav2.md §2.7): a controller failure (1xx) outranks a planner
    failure (2xx), which outranks behaviour codes (7xx).
    """
    failures = [int(code) for code in codes if int(code) != 0]
    return min(failures) if failures else 0


class UnsupportedRosFeatureError(BaobabError):
    """A script used a part of ROS that baobab does not model (services, actions), or waited
    on sim time where nothing advances it."""
