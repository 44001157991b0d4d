"""``rosgraph_msgs.msg``: the ``/clock`` message."""

from __future__ import annotations

from baobab.nav.rosmsg import Message
from baobab.nav.rostime import TimeMsg

__all__ = ["Clock"]


class Clock(Message):
    """``rosgraph_msgs/Clock``: the simulation time nodes with ``use_sim_time`` follow."""

    _type_name = "rosgraph_msgs/msg/Clock"
    _fields_and_field_types = {"clock": "builtin_interfaces/Time"}
    clock: TimeMsg
