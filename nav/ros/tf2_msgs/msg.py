"""``tf2_msgs.msg``: the message ``/tf`` and ``/tf_static`` carry."""

from __future__ import annotations

import baobab.nav.ros.geometry_msgs.msg
from baobab.nav.rosmsg import Message

__all__ = ["TFMessage"]


class TFMessage(Message):
    """``tf2_msgs/TFMessage``: a batch of transforms."""

    _type_name = "tf2_msgs/msg/TFMessage"
    _fields_and_field_types = {"transforms": "sequence<geometry_msgs/TransformStamped>"}
    transforms: list[baobab.nav.ros.geometry_msgs.msg.TransformStamped]
