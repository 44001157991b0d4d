"""``rclpy.publisher``: publishing messages on a topic of the in-process graph."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from baobab.nav.ros.qos import QoSProfile

if TYPE_CHECKING:
    from baobab.nav.ros.graph import Graph

__all__ = ["Publisher"]


class Publisher:
    """A publisher (``rclpy.publisher.Publisher``); made by ``Node.create_publisher``."""

    def __init__(self, graph: Graph, msg_type: type, topic_name: str, qos_profile: QoSProfile):
        self._graph = graph
        self.msg_type = msg_type
        self.topic_name = topic_name
        self.qos_profile = qos_profile
        self._destroyed = False
        graph.add_publisher(self)

    @property
    def topic(self) -> str:
        """The fully qualified topic name."""
        return self.topic_name

    def publish(self, msg: Any) -> None:
        """Send ``msg`` to every matching subscription (each gets its own copy).

        Raises:
            TypeError: ``msg`` is not of the publisher's message type (rclpy's check).
            RuntimeError: the publisher was destroyed.
        """
        if not isinstance(msg, self.msg_type):
            raise TypeError(f"Expected {self.msg_type}, got {type(msg)}")
        if self._destroyed:
            raise RuntimeError("publisher is invalid: it was destroyed")
        self._graph.publish(self, msg)

    def get_subscription_count(self) -> int:
        """How many subscriptions the topic has."""
        return self._graph.count(self.topic_name, publishers=False)

    def destroy(self) -> None:
        """Stop publishing (idempotent)."""
        self._destroyed = True
        self._graph.remove(self)
