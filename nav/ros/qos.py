"""Quality-of-service profiles, their policies and rmw's presets (served as ``rclpy.qos``).

The in-process graph honours what changes what a subscriber sees: the history (KEEP_LAST
``depth`` messages queue per subscription, KEEP_ALL queues all), reliability matching (a
best-effort publisher does not reach a reliable subscription) and durability (a late
transient-local subscription receives what transient-local publishers kept). Deadlines,
lifespans and liveliness are accepted and not modelled.
"""

from __future__ import annotations

from enum import IntEnum

from baobab.nav.rostime import Duration

__all__ = [
    "DurabilityPolicy",
    "HistoryPolicy",
    "LivelinessPolicy",
    "QoSDurabilityPolicy",
    "QoSHistoryPolicy",
    "QoSProfile",
    "QoSReliabilityPolicy",
    "ReliabilityPolicy",
    "qos_profile_parameters",
    "qos_profile_sensor_data",
    "qos_profile_services_default",
    "qos_profile_system_default",
]


class HistoryPolicy(IntEnum):
    """How many messages a queue keeps."""

    SYSTEM_DEFAULT = 0
    KEEP_LAST = 1
    KEEP_ALL = 2
    UNKNOWN = 3


class ReliabilityPolicy(IntEnum):
    """Whether delivery is guaranteed."""

    SYSTEM_DEFAULT = 0
    RELIABLE = 1
    BEST_EFFORT = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class DurabilityPolicy(IntEnum):
    """Whether late subscribers get earlier messages."""

    SYSTEM_DEFAULT = 0
    TRANSIENT_LOCAL = 1
    VOLATILE = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class LivelinessPolicy(IntEnum):
    """How liveliness is asserted (accepted, not modelled)."""

    SYSTEM_DEFAULT = 0
    AUTOMATIC = 1
    MANUAL_BY_TOPIC = 3
    UNKNOWN = 4
    BEST_AVAILABLE = 5


QoSHistoryPolicy = HistoryPolicy
QoSReliabilityPolicy = ReliabilityPolicy
QoSDurabilityPolicy = DurabilityPolicy


class QoSProfile:
    """A QoS profile (``rclpy.qos.QoSProfile``).

    Args:
        history: KEEP_LAST (the default when ``depth`` is given) or KEEP_ALL.
        depth: queue length for KEEP_LAST.
        reliability, durability, liveliness: the policies.
        **kwargs: deadline, lifespan, liveliness_lease_duration,
            avoid_ros_namespace_conventions: accepted.

    Raises:
        ValueError: neither ``history`` nor ``depth`` given, or a negative depth.
    """

    def __init__(
        self,
        *,
        history: HistoryPolicy | int | None = None,
        depth: int | None = None,
        reliability: ReliabilityPolicy | int = ReliabilityPolicy.RELIABLE,
        durability: DurabilityPolicy | int = DurabilityPolicy.VOLATILE,
        liveliness: LivelinessPolicy | int = LivelinessPolicy.SYSTEM_DEFAULT,
        **kwargs: object,
    ) -> None:
        if history is None and depth is None:
            raise ValueError("History and/or depth settings are required.")
        if depth is not None and (isinstance(depth, bool) or not isinstance(depth, int)):
            raise TypeError(f"depth must be an int, got {depth!r}")
        if depth is not None and depth < 0:
            raise ValueError(f"depth must not be negative, got {depth}")
        self.history = HistoryPolicy(HistoryPolicy.KEEP_LAST if history is None else history)
        self.depth = 0 if depth is None else depth
        self.reliability = ReliabilityPolicy(reliability)
        self.durability = DurabilityPolicy(durability)
        self.liveliness = LivelinessPolicy(liveliness)
        self.deadline = kwargs.get("deadline", Duration())
        self.lifespan = kwargs.get("lifespan", Duration())

    @property
    def keeps(self) -> int | None:
        """The queue length this profile asks for; None for KEEP_ALL."""
        if self.history is HistoryPolicy.KEEP_ALL:
            return None
        return max(self.depth, 1)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, QoSProfile):
            return NotImplemented
        return (self.history, self.depth, self.reliability, self.durability) == (
            other.history,
            other.depth,
            other.reliability,
            other.durability,
        )

    def __repr__(self) -> str:
        return (
            f"QoSProfile(history={self.history.name}, depth={self.depth}, "
            f"reliability={self.reliability.name}, durability={self.durability.name})"
        )


def as_profile(qos: QoSProfile | int) -> QoSProfile:
    """A profile from what ``create_publisher``/``create_subscription`` take (a depth is
    KEEP_LAST of that depth).

    Raises:
        TypeError: neither a profile nor an int.
    """
    if isinstance(qos, QoSProfile):
        return qos
    if isinstance(qos, int) and not isinstance(qos, bool):
        return QoSProfile(depth=qos)
    raise TypeError(
        "Expected QoSProfile or int, but received " + repr(type(qos)).replace("class ", "")
    )


qos_profile_system_default = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10)
qos_profile_sensor_data = QoSProfile(
    history=HistoryPolicy.KEEP_LAST, depth=5, reliability=ReliabilityPolicy.BEST_EFFORT
)
qos_profile_services_default = QoSProfile(depth=10)
qos_profile_parameters = QoSProfile(depth=1000)
