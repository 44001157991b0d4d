"""Result codes of the Nav2 servers baobab does not run yet: docking and following.

The action messages define them (``DockRobot.Result.DOCK_NOT_IN_DB``) and the navigator
reports their UNKNOWN when a call finds no server. They are kept apart from
:mod:`baobab.nav.errors` because mission validation takes every code there as one a run can
end with; each enum moves there with its server.
"""

from __future__ import annotations

from enum import IntEnum


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
