"""``rclpy``: init/shutdown, ``ok()``, spinning, nodes, time — over baobab's simulation.

``rclpy.init()`` and ``rclpy.shutdown()`` pair up as in ROS 2 (init twice or shut down twice
raises ``RuntimeError``; after a shutdown, init works again). ``spin_once`` gives a node its
per-spin hook; ``spin`` and ``spin_until_future_complete`` would wait forever for ROS
callbacks that baobab never delivers, so they raise
:class:`~baobab.nav.ros.UnsupportedRosFeatureError`.
"""

from __future__ import annotations

from typing import NoReturn

from baobab.nav.ros import UnsupportedRosFeatureError
from baobab.nav.ros.rclpy import clock, context, duration, logging, node, time
from baobab.nav.ros.rclpy.context import Context, get_default_context
from baobab.nav.ros.rclpy.node import Node

__all__ = [
    "Context",
    "Node",
    "clock",
    "context",
    "create_node",
    "duration",
    "get_default_context",
    "init",
    "logging",
    "node",
    "ok",
    "shutdown",
    "spin",
    "spin_once",
    "spin_until_future_complete",
    "time",
    "try_shutdown",
]


def init(
    *,
    args: list[str] | None = None,
    context: Context | None = None,
    domain_id: int | None = None,
    signal_handler_options: object = None,
) -> Context:
    """Start the ROS lifecycle; the returned context also works as ``with rclpy.init():``.

    Raises:
        RuntimeError: already initialised and not shut down since.
    """
    chosen = get_default_context() if context is None else context
    chosen.init(args, domain_id=domain_id)
    return chosen


def ok(*, context: Context | None = None) -> bool:
    """True between ``init()`` and ``shutdown()``."""
    return (get_default_context() if context is None else context).ok()


def shutdown(*, context: Context | None = None, uninstall_handlers: bool | None = None) -> None:
    """End the ROS lifecycle, destroying the nodes created in it.

    Raises:
        RuntimeError: ``init()`` was not called (since the last shutdown).
    """
    (get_default_context(shutting_down=True) if context is None else context).shutdown()


def try_shutdown(*, context: Context | None = None, uninstall_handlers: bool | None = None) -> None:
    """Like :func:`shutdown`, but does nothing when there is nothing to shut down."""
    (get_default_context(shutting_down=True) if context is None else context).try_shutdown()


def create_node(
    node_name: str,
    *,
    context: Context | None = None,
    namespace: str | None = None,
    **options: object,
) -> Node:
    """A new :class:`~baobab.nav.ros.rclpy.node.Node`, as ``rclpy.create_node`` makes one."""
    return Node(node_name, context=context, namespace=namespace, **options)


def spin_once(node: Node, *, executor: object = None, timeout_sec: float | None = None) -> None:
    """Run the node's per-spin work once (nothing for a plain node)."""
    node._spin_once(timeout_sec)


def spin(node: Node, executor: object = None) -> NoReturn:
    """Not supported: it would wait forever for ROS callbacks."""
    raise UnsupportedRosFeatureError(
        "rclpy.spin() is not supported: it waits for ROS callbacks and baobab runs no ROS "
        "graph; poll navigator.isTaskComplete() in a loop instead"
    )


def spin_until_future_complete(
    node: Node, future: object, executor: object = None, timeout_sec: float | None = None
) -> NoReturn:
    """Not supported: baobab has no ROS futures."""
    raise UnsupportedRosFeatureError(
        "rclpy.spin_until_future_complete() is not supported: baobab has no ROS futures; "
        "the navigator's methods block or poll by themselves"
    )
