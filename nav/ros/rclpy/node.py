"""``rclpy.node``: a node with a name, a logger and a simulation-time clock.

baobab runs no ROS graph: a node has no topics, services, timers or parameters, and asking
for one raises :class:`~baobab.nav.ros.UnsupportedRosFeatureError` naming what was asked. Its
clock is a ROS-time clock reading the simulation time, as nodes with ``use_sim_time`` do.
``BasicNavigator`` is a node too, as in Nav2.
"""

from __future__ import annotations

from typing import NoReturn

from baobab.nav.ros import UnsupportedRosFeatureError
from baobab.nav.ros.rclpy.context import Context, get_default_context
from baobab.nav.ros.rclpy.logging import RcutilsLogger
from baobab.nav.rostime import Clock, ClockType


class Node:
    """A named ROS node without communication.

    Args:
        node_name: the node's name, also its logger's name.
        context: the lifecycle the node belongs to; the default context when ``None``.
        namespace: the node's namespace (``"/"`` when ``None`` or empty).
        **options: rclpy's other node options (parameter overrides, QoS settings, ...);
            accepted and ignored, as there is no ROS graph to apply them to.
    """

    def __init__(
        self,
        node_name: str,
        *,
        context: Context | None = None,
        namespace: str | None = None,
        **options: object,
    ) -> None:
        self._name = node_name
        self._namespace = "/" + (namespace or "").strip("/")
        self._context = get_default_context() if context is None else context
        self._logger = RcutilsLogger(node_name)
        self._clock = Clock(clock_type=ClockType.ROS_TIME)
        self._destroyed = False
        self._context.track_node(self)

    @property
    def context(self) -> Context:
        """The lifecycle this node belongs to."""
        return self._context

    def get_name(self) -> str:
        """The node's name."""
        return self._name

    def get_namespace(self) -> str:
        """The node's namespace, ``"/"`` at the root."""
        return self._namespace

    def get_fully_qualified_name(self) -> str:
        """Namespace and name, such as ``/basic_navigator``."""
        return f"{self._namespace.rstrip('/')}/{self._name}"

    def get_logger(self) -> RcutilsLogger:
        """The node's logger."""
        return self._logger

    def get_clock(self) -> Clock:
        """The node's ROS-time clock (simulation time)."""
        return self._clock

    def destroy_node(self) -> None:
        """Release the node; a second call does nothing."""
        if not self._destroyed:
            self._destroyed = True
            self._context.untrack_node(self)

    def _spin_once(self, timeout_sec: float | None) -> None:
        """What ``rclpy.spin_once(node)`` does: nothing, as a plain node has no callbacks.

        Subclasses with work to do per spin (a navigator advancing its simulation) override it.
        """

    def _unsupported(self, what: str) -> NoReturn:
        raise UnsupportedRosFeatureError(
            f"Node.{what}() is not supported: baobab runs no ROS graph (no topics, services, "
            "timers or parameters); use the navigator's methods instead"
        )

    def create_publisher(self, *args: object, **kwargs: object) -> NoReturn:
        """Not supported (no ROS topics)."""
        self._unsupported("create_publisher")

    def create_subscription(self, *args: object, **kwargs: object) -> NoReturn:
        """Not supported (no ROS topics)."""
        self._unsupported("create_subscription")

    def create_client(self, *args: object, **kwargs: object) -> NoReturn:
        """Not supported (no ROS services)."""
        self._unsupported("create_client")

    def create_service(self, *args: object, **kwargs: object) -> NoReturn:
        """Not supported (no ROS services)."""
        self._unsupported("create_service")

    def create_timer(self, *args: object, **kwargs: object) -> NoReturn:
        """Not supported (nothing spins timers)."""
        self._unsupported("create_timer")

    def declare_parameter(self, *args: object, **kwargs: object) -> NoReturn:
        """Not supported (no ROS parameters)."""
        self._unsupported("declare_parameter")

    def get_parameter(self, *args: object, **kwargs: object) -> NoReturn:
        """Not supported (no ROS parameters)."""
        self._unsupported("get_parameter")
