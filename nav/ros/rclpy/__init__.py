"""``rclpy``: init/shutdown, ``ok()``, spinning, nodes, time — over baobab's simulation.

``rclpy.init()`` and ``rclpy.shutdown()`` pair up as in ROS 2 (init twice or shut down twice
raises ``RuntimeError``; after a shutdown, init works again). ``spin``, ``spin_once`` and
``spin_until_future_complete`` use the context's global executor
(:mod:`~baobab.nav.ros.rclpy.executors`); waiting for callbacks advances sim time, which node
code run by ``baobab ros run`` can do, and so can a Nav2 script once it built a
``BasicNavigator``, whose simulation then serves the waits (:mod:`baobab.nav.navigator_time`).
Elsewhere ``spin_once`` runs the callbacks that are ready, and a call that would wait forever
raises :class:`~baobab.nav.ros.UnsupportedRosFeatureError`.
"""

from __future__ import annotations

from typing import Any

from baobab.nav.ros import waiting
from baobab.nav.ros.rclpy import (
    callback_groups,
    clock,
    context,
    duration,
    exceptions,
    executors,
    logging,
    node,
    parameter,
    qos,
    task,
    time,
    timer,
    utilities,
)
from baobab.nav.ros.rclpy.context import Context, get_default_context
from baobab.nav.ros.rclpy.executors import Executor, SingleThreadedExecutor
from baobab.nav.ros.rclpy.node import Node
from baobab.nav.ros.rclpy.task import Future

__all__ = [
    "Context",
    "Node",
    "callback_groups",
    "clock",
    "context",
    "create_node",
    "duration",
    "exceptions",
    "executors",
    "get_default_context",
    "get_global_executor",
    "init",
    "logging",
    "node",
    "ok",
    "parameter",
    "qos",
    "shutdown",
    "spin",
    "spin_once",
    "spin_until_future_complete",
    "task",
    "time",
    "timer",
    "try_shutdown",
    "utilities",
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
    **options: Any,
) -> Node:
    """A new :class:`~baobab.nav.ros.rclpy.node.Node`, as ``rclpy.create_node`` makes one."""
    return Node(node_name, context=context, namespace=namespace, **options)


def get_global_executor(*, context: Context | None = None) -> Executor:
    """The executor ``rclpy.spin`` and friends use (one per context)."""
    chosen = get_default_context() if context is None else context
    if chosen.executor is None:
        chosen.executor = SingleThreadedExecutor(context=chosen)
    executor: Executor = chosen.executor
    return executor


def _executor_for(node: Node, executor: Executor | None) -> Executor:
    chosen = get_global_executor(context=node.context) if executor is None else executor
    chosen.add_node(node)
    return chosen


def spin_once(
    node: Node, *, executor: Executor | None = None, timeout_sec: float | None = None
) -> None:
    """Run at most one of the node's ready callbacks, waiting up to ``timeout_sec`` for one.

    Outside a run: run one ready callback if there is one, then the node's per-spin step (a
    navigator advances its simulation by up to ``timeout_sec``).
    """
    chosen = _executor_for(node, executor)
    if waiting.can_wait():
        chosen.spin_once(timeout_sec=timeout_sec)
        return
    chosen.spin_once(timeout_sec=0)
    node._spin_once(timeout_sec)


def spin(node: Node, executor: Executor | None = None) -> None:
    """Run the node's callbacks until the context shuts down (or the run ends).

    Raises:
        UnsupportedRosFeatureError: outside a run, where nothing would ever wake it.
    """
    if not waiting.can_wait():
        waiting.wait(None, None, what="rclpy.spin()")
    _executor_for(node, executor).spin()


def spin_until_future_complete(
    node: Node, future: Future, executor: Executor | None = None, timeout_sec: float | None = None
) -> None:
    """Run the node's callbacks until ``future`` is done or ``timeout_sec`` has passed."""
    _executor_for(node, executor).spin_until_future_complete(future, timeout_sec)
