"""``action_msgs.msg``: goal identity and status, the codes Nav2 scripts compare with."""

from __future__ import annotations

from baobab.nav.ros.unique_identifier_msgs.msg import UUID
from baobab.nav.rosmsg import Message
from baobab.nav.rostime import TimeMsg

__all__ = ["GoalInfo", "GoalStatus", "GoalStatusArray"]


class GoalInfo(Message):
    """``action_msgs/GoalInfo``: a goal's id and when it was accepted."""

    _type_name = "action_msgs/msg/GoalInfo"
    _fields_and_field_types = {
        "goal_id": "unique_identifier_msgs/UUID",
        "stamp": "builtin_interfaces/Time",
    }
    goal_id: UUID
    stamp: TimeMsg


class GoalStatus(Message):
    """``action_msgs/GoalStatus``: a goal and where it is in its life (``status``)."""

    STATUS_UNKNOWN = 0
    STATUS_ACCEPTED = 1
    STATUS_EXECUTING = 2
    STATUS_CANCELING = 3
    STATUS_SUCCEEDED = 4
    STATUS_CANCELED = 5
    STATUS_ABORTED = 6

    _type_name = "action_msgs/msg/GoalStatus"
    _fields_and_field_types = {"goal_info": "action_msgs/GoalInfo", "status": "int8"}
    goal_info: GoalInfo
    status: int


class GoalStatusArray(Message):
    """``action_msgs/GoalStatusArray``: the status of every goal of one action server."""

    _type_name = "action_msgs/msg/GoalStatusArray"
    _fields_and_field_types = {"status_list": "sequence<action_msgs/GoalStatus>"}
    status_list: list[GoalStatus]
