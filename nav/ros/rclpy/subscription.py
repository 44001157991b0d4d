"""``rclpy.subscription``: a topic's messages queued for a node's callback."""

from __future__ import annotations

import inspect
from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from baobab.nav.ros.qos import QoSProfile

if TYPE_CHECKING:
    from baobab.nav.ros.graph import Graph
    from baobab.nav.ros.rclpy.logging import RcutilsLogger

__all__ = ["MessageInfo", "Subscription"]


class MessageInfo(dict[str, Any]):
    """What rclpy passes as a callback's second argument: publication timestamps (ns)."""


class Subscription:
    """A subscription (``rclpy.subscription.Subscription``); made by ``Node.create_subscription``.

    Delivered messages wait in a queue of the QoS depth (the oldest is dropped when it is
    full, as KEEP_LAST does) until an executor spinning the node takes one and calls the
    callback. An internal subscription (a ``TransformListener``'s) is called at once instead.
    """

    def __init__(
        self,
        graph: Graph,
        msg_type: type,
        topic_name: str,
        callback: Callable[..., Any],
        qos_profile: QoSProfile,
        *,
        logger: RcutilsLogger,
        now_ns: Callable[[], int],
        callback_group: object = None,
        raw: bool = False,
        internal: bool = False,
    ) -> None:
        self._graph = graph
        self.msg_type = msg_type
        self.topic_name = topic_name
        self.callback = callback
        self.callback_group = callback_group
        self.qos_profile = qos_profile
        self.raw = raw
        self._internal = internal
        self._logger = logger
        self._now_ns = now_ns
        self._warned: set[str] = set()
        self._queue: deque[tuple[Any, int]] = deque(maxlen=qos_profile.keeps)
        self._wants_info = _takes_two_arguments(callback)
        graph.add_subscription(self)

    @property
    def topic(self) -> str:
        """The fully qualified topic name."""
        return self.topic_name

    def receive(self, message: Any) -> None:
        """Take a delivered message: queue it (or handle it at once when internal)."""
        if self._internal:
            self.callback(message)
        else:
            self._queue.append((message, self._now_ns()))

    def warn_incompatible(self, policy: str) -> None:
        """Warn once per policy that a publisher's QoS does not match (rclcpp's wording)."""
        if policy not in self._warned:
            self._warned.add(policy)
            self._logger.warning(
                f"New publisher discovered on topic '{self.topic_name}', offering incompatible "
                f"QoS. No messages will be received from it. Last incompatible policy: {policy}"
            )

    def has_message(self) -> bool:
        """True when a message waits."""
        return bool(self._queue)

    def take_and_call(self) -> None:
        """Pass the oldest waiting message to the callback."""
        message, stamp = self._queue.popleft()
        if self._wants_info:
            info = MessageInfo(source_timestamp=stamp, received_timestamp=stamp)
            self.callback(message, info)
        else:
            self.callback(message)

    def destroy(self) -> None:
        """Stop receiving (idempotent)."""
        self._queue.clear()
        self._graph.remove(self)


def _takes_two_arguments(callback: Callable[..., Any]) -> bool:
    """True when ``callback`` cannot take the message alone but takes it with its info (how
    rclpy decides whether to pass a ``MessageInfo``)."""
    try:
        signature = inspect.signature(callback)
    except (TypeError, ValueError):
        return False
    try:
        signature.bind(object())
    except TypeError:
        try:
            signature.bind(object(), object())
        except TypeError:
            return False
        return True
    return False
