"""The in-process ROS graph: topics, who publishes and subscribes, and message delivery.

A publish hands each matching subscription its own copy of the message at once (as a
deserialised message is its own object in ROS), into the subscription's queue, which keeps
the newest ``depth`` messages under KEEP_LAST. Matching follows ROS's QoS rules: the types must
be the same, and a best-effort publisher does not reach a reliable subscription (the
subscriber's node warns once, in rclcpp's words). Messages from transient-local publishers are
kept (their ``depth`` newest) and handed to transient-local subscriptions that come later, which
is how ``/tf_static`` reaches late listeners.

Taps see every message published on a topic whether or not anyone subscribes: they are how
``--echo``, recordings and the run's trace observe the graph.
"""

from __future__ import annotations

import copy
from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Protocol

from baobab.nav.ros.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

if TYPE_CHECKING:
    pass

Tap = Callable[[str, Any], None]
"""Called with (topic name, message) for each message published on a topic."""


class Endpoint(Protocol):
    """What the graph needs of a publisher or a subscription."""

    topic_name: str
    msg_type: type
    qos_profile: QoSProfile


class Receiver(Endpoint, Protocol):
    """A subscription as the graph sees it."""

    def receive(self, message: Any) -> None:
        """Take a delivered message (queue it, or handle it at once)."""
        ...

    def warn_incompatible(self, policy: str) -> None:
        """Say once that a publisher's QoS does not match."""
        ...


class Topic:
    """One topic: its endpoints in creation order, and what transient-local publishers kept."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.publishers: list[Endpoint] = []
        self.subscriptions: list[Receiver] = []
        self.kept: dict[int, deque[Any]] = {}
        self.taps: list[Tap] = []


def _incompatible(publisher: QoSProfile, subscription: QoSProfile) -> str | None:
    if (
        publisher.reliability is ReliabilityPolicy.BEST_EFFORT
        and subscription.reliability is ReliabilityPolicy.RELIABLE
    ):
        return "RELIABILITY"
    if (
        publisher.durability is DurabilityPolicy.VOLATILE
        and subscription.durability is DurabilityPolicy.TRANSIENT_LOCAL
    ):
        return "DURABILITY"
    return None


class Graph:
    """Every topic of one run (or of one script outside a run)."""

    def __init__(self) -> None:
        self._topics: dict[str, Topic] = {}
        self._all_taps: list[Tap] = []
        self.timers: list[Any] = []
        """Every live timer and rate of the graph's nodes: the simulation loop stops at their
        due times (:class:`~baobab.nav.ros.rclpy.timer.Timer`)."""

    def topic(self, name: str) -> Topic:
        """The topic called ``name`` (fully qualified), created on first use."""
        topic = self._topics.get(name)
        if topic is None:
            topic = self._topics[name] = Topic(name)
        return topic

    def add_publisher(self, publisher: Endpoint) -> None:
        """Advertise ``publisher`` on its topic."""
        topic = self.topic(publisher.topic_name)
        topic.publishers.append(publisher)
        for subscription in topic.subscriptions:
            self._check_match(publisher, subscription)

    def add_subscription(self, subscription: Receiver) -> None:
        """Subscribe; a transient-local subscription gets what transient-local publishers kept."""
        topic = self.topic(subscription.topic_name)
        topic.subscriptions.append(subscription)
        for publisher in topic.publishers:
            if not self._check_match(publisher, subscription):
                continue
            if subscription.qos_profile.durability is DurabilityPolicy.TRANSIENT_LOCAL:
                for message in topic.kept.get(id(publisher), ()):
                    subscription.receive(copy.deepcopy(message))

    def remove(self, endpoint: Endpoint) -> None:
        """Take a publisher or subscription off its topic (idempotent)."""
        topic = self._topics.get(endpoint.topic_name)
        if topic is None:
            return
        topic.publishers = [item for item in topic.publishers if item is not endpoint]
        topic.subscriptions = [item for item in topic.subscriptions if item is not endpoint]
        topic.kept.pop(id(endpoint), None)

    def _check_match(self, publisher: Endpoint, subscription: Receiver) -> bool:
        if publisher.msg_type is not subscription.msg_type:
            return False
        policy = _incompatible(publisher.qos_profile, subscription.qos_profile)
        if policy is not None:
            subscription.warn_incompatible(policy)
            return False
        return True

    def publish(self, publisher: Endpoint, message: Any, *, fresh: bool = False) -> None:
        """Deliver ``message`` to the subscriptions that match ``publisher``.

        Args:
            publisher: an advertised publisher.
            message: the message; copied for each receiver unless ``fresh`` (built for this
                publish and never touched again), when the first receiver takes it as it is.
        """
        topic = self.topic(publisher.topic_name)
        for tap in topic.taps:
            tap(topic.name, message)
        for tap in self._all_taps:
            tap(topic.name, message)
        if publisher.qos_profile.durability is DurabilityPolicy.TRANSIENT_LOCAL:
            kept = topic.kept.setdefault(
                id(publisher), deque(maxlen=max(publisher.qos_profile.depth, 1))
            )
            kept.append(copy.deepcopy(message))
        for subscription in list(topic.subscriptions):
            if subscription.msg_type is not publisher.msg_type:
                continue
            if _incompatible(publisher.qos_profile, subscription.qos_profile) is not None:
                continue
            subscription.receive(message if fresh else copy.deepcopy(message))
            fresh = False

    def topic_names(self) -> list[str]:
        """Every topic named so far, sorted."""
        return sorted(self._topics)

    def latched(self, name: str) -> list[Any]:
        """What transient-local publishers of ``name`` kept (what a late subscriber gets)."""
        topic = self._topics.get(name)
        if topic is None:
            return []
        return [message for kept in topic.kept.values() for message in kept]

    def has_receivers(self, name: str) -> bool:
        """True when a subscription or a tap of ``name`` would see a message published on it.

        The simulation builds a message only when this holds; taps on every topic do not
        count, so a trace records the robot's topics only when something reads them.
        """
        topic = self._topics.get(name)
        return topic is not None and bool(topic.subscriptions or topic.taps)

    def tap(self, name: str | None, tap: Tap) -> None:
        """Call ``tap`` with each message published on ``name`` (every topic when None)."""
        if name is None:
            self._all_taps.append(tap)
        else:
            self.topic(name).taps.append(tap)

    def names_and_types(self) -> list[tuple[str, list[str]]]:
        """``Node.get_topic_names_and_types()``: advertised or subscribed topics, sorted."""
        rows = []
        for name in sorted(self._topics):
            topic = self._topics[name]
            types = {
                getattr(endpoint.msg_type, "_type_name", endpoint.msg_type.__name__)
                for endpoint in (*topic.publishers, *topic.subscriptions)
            }
            if types:
                rows.append((name, sorted(types)))
        return rows

    def count(self, name: str, *, publishers: bool) -> int:
        """How many publishers (or subscriptions) ``name`` has."""
        topic = self._topics.get(name)
        if topic is None:
            return 0
        return len(topic.publishers if publishers else topic.subscriptions)
