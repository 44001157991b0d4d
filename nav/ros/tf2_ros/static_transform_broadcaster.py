"""``tf2_ros.static_transform_broadcaster``: latched transforms on ``/tf_static``."""

from __future__ import annotations

from typing import Any

from baobab.nav.ros.geometry_msgs.msg import TransformStamped
from baobab.nav.ros.qos import DurabilityPolicy, HistoryPolicy, QoSProfile
from baobab.nav.ros.tf2_msgs.msg import TFMessage

__all__ = ["StaticTransformBroadcaster"]


class StaticTransformBroadcaster:
    """``sendTransform`` publishes every static transform sent so far, one per child frame
    (the newest wins), on ``/tf_static`` (depth 1, transient local)."""

    def __init__(self, node: Any, qos: QoSProfile | int | None = None) -> None:
        profile = (
            QoSProfile(
                depth=1,
                history=HistoryPolicy.KEEP_LAST,
                durability=DurabilityPolicy.TRANSIENT_LOCAL,
            )
            if qos is None
            else qos
        )
        self.pub_tf = node.create_publisher(TFMessage, "/tf_static", profile)
        self._sent: dict[str, TransformStamped] = {}

    def sendTransform(self, transform: TransformStamped | list[TransformStamped]) -> None:
        """Add ``transform`` (one or a list) and publish them all."""
        for item in transform if isinstance(transform, list) else [transform]:
            self._sent[item.child_frame_id] = item
        self.pub_tf.publish(TFMessage(transforms=list(self._sent.values())))
