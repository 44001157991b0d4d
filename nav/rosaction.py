"""ROS 2 action types as rclpy's generated ones: one class holding Goal, Result and Feedback.

An action type such as ``nav2_msgs.action.NavigateToPose`` is a class that cannot be
instantiated; its ``Goal``, ``Result`` and ``Feedback`` attributes are message classes
(:class:`~baobab.nav.rosmsg.Message`) named ``NavigateToPose_Goal`` and so on, as rosidl names
them. The error codes an action's result defines (``NavigateToPose.Result.UNKNOWN``) come from
baobab's code enums (:mod:`baobab.nav.errors`) through :func:`result_codes`, so the numbers
the navigation stack reports and the ones a script compares with are the same.
"""

from __future__ import annotations

from collections.abc import Callable
from enum import IntEnum
from typing import ClassVar, TypeVar

from baobab.nav.rosmsg import Message

GOAL_REJECTED = 1
"""The code Nav2's BT action nodes report when a server rejects their goal."""
SEND_GOAL_FAILURE = 2
"""The code Nav2's BT action nodes report when a goal cannot be sent."""

MessageClass = TypeVar("MessageClass", bound=type[Message])


class Action:
    """Base of every action type: ``Goal``, ``Result``, ``Feedback`` and the ROS type name."""

    _type_name: ClassVar[str]
    """The ROS type name, ``"nav2_msgs/action/NavigateToPose"``."""
    Goal: ClassVar[type[Message]]
    Result: ClassVar[type[Message]]
    Feedback: ClassVar[type[Message]]

    def __init__(self) -> None:
        raise NotImplementedError("Action classes can not be instantiated")


def result_codes(
    codes: type[IntEnum], *, common: bool = True
) -> Callable[[MessageClass], MessageClass]:
    """A class decorator that puts the members of ``codes`` on a Result class as constants.

    Args:
        codes: the action's code enum (``NONE``, ``UNKNOWN``, ...).
        common: also define ``GOAL_REJECTED`` (1) and ``SEND_GOAL_FAILURE`` (2), which every
            Nav2 result with codes defines except the waypoint followers'.
    """

    def decorate(cls: MessageClass) -> MessageClass:
        if common:
            cls.GOAL_REJECTED = GOAL_REJECTED  # type: ignore[attr-defined]
            cls.SEND_GOAL_FAILURE = SEND_GOAL_FAILURE  # type: ignore[attr-defined]
        for member in codes:
            setattr(cls, member.name, int(member))
        return cls

    return decorate
