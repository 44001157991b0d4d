"""``tf2_ros.transform_listener``: fills a buffer from ``/tf`` and ``/tf_static``."""

from __future__ import annotations

from typing import Any

from baobab.nav.ros.qos import DurabilityPolicy, QoSProfile
from baobab.nav.ros.tf2_msgs.msg import TFMessage
from baobab.nav.ros.tf2_ros.buffer import Buffer

__all__ = ["TransformListener"]


class TransformListener:
    """Subscribes ``/tf`` (depth 100) and ``/tf_static`` (depth 100, transient local) and
    stores what arrives in ``buffer``.

    The buffer is filled as transforms are published, whether or not the node is spinning,
    as rclpy's listener does with ``spin_thread=True`` (so ``spin_thread`` changes nothing).
    """

    def __init__(
        self,
        buffer: Buffer,
        node: Any,
        *,
        spin_thread: bool = False,
        qos: QoSProfile | int | None = None,
        static_qos: QoSProfile | int | None = None,
    ) -> None:
        self.buffer = buffer
        self.node = node
        dynamic = QoSProfile(depth=100) if qos is None else qos
        static = (
            QoSProfile(depth=100, durability=DurabilityPolicy.TRANSIENT_LOCAL)
            if static_qos is None
            else static_qos
        )
        self.tf_sub = node.create_subscription(
            TFMessage, "/tf", self.callback, dynamic, _internal=True
        )
        self.tf_static_sub = node.create_subscription(
            TFMessage, "/tf_static", self.static_callback, static, _internal=True
        )

    def callback(self, data: TFMessage) -> None:
        """Store dynamic transforms."""
        for transform in data.transforms:
            self.buffer.set_transform(transform, "default_authority")

    def static_callback(self, data: TFMessage) -> None:
        """Store static transforms."""
        for transform in data.transforms:
            self.buffer.set_transform_static(transform, "default_authority")

    def unregister(self) -> None:
        """Stop listening."""
        self.node.destroy_subscription(self.tf_sub)
        self.node.destroy_subscription(self.tf_static_sub)

    def __del__(self) -> None:
        pass
