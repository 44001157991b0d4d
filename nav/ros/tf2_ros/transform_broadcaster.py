"""``tf2_ros.transform_broadcaster``: publishes transforms on ``/tf``."""

from __future__ import annotations

from typing import Any

from baobab.nav.ros.geometry_msgs.msg import TransformStamped
from baobab.nav.ros.qos import QoSProfile
from baobab.nav.ros.tf2_msgs.msg import TFMessage

__all__ = ["TransformBroadcaster"]


class TransformBroadcaster:
    """``sendTransform`` publishes one or several ``TransformStamped`` on ``/tf`` (depth 100)."""

    def __init__(self, node: Any, qos: QoSProfile | int = 100) -> None:
        self.pub_tf = node.create_publisher(TFMessage, "/tf", qos)

    def sendTransform(self, transform: TransformStamped | list[TransformStamped]) -> None:
        """Publish ``transform`` (one or a list)."""
        transforms = transform if isinstance(transform, list) else [transform]
        self.pub_tf.publish(TFMessage(transforms=transforms))
