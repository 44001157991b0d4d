"""``rclpy.context``: the init/shutdown lifecycle, and the default context ``rclpy.init`` uses."""

from __future__ import annotations

import sys
import weakref
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from types import TracebackType
from typing import Any, Protocol

from baobab.nav.ros import waiting
from baobab.nav.ros.arguments import RosArguments, parse_ros_arguments
from baobab.nav.ros.graph import Graph


class TrackedNode(Protocol):
    """What a context needs of the nodes created in it (:class:`~.node.Node` is one)."""

    def destroy_node(self) -> None:
        """Release the node."""
        ...

    def get_name(self) -> str:
        """The node's name."""
        ...


class Context:
    """One init/shutdown lifecycle; nodes created in it are destroyed when it shuts down.

    As in rclpy, a context initialises once and shuts down once; ``rclpy.shutdown()`` then
    replaces the default context, so ``rclpy.init()`` works again afterwards.
    """

    def __init__(self) -> None:
        self._initialized = False
        self._shut_down = False
        self._nodes: list[weakref.ref[TrackedNode]] = []
        self._callbacks: list[Callable[[], None]] = []
        self.arguments = RosArguments()
        """What the ``--ros-args`` sections of ``init(args=...)`` said."""
        self.executor: Any = None
        """The executor ``rclpy.spin`` uses for this context (made on first use)."""
        self._own_graph: Graph | None = None

    @property
    def graph(self) -> Graph:
        """The topics nodes of this context use: the run's graph, or one of the context's own
        outside a run (a Nav2 script's nodes talk among themselves)."""
        shared = waiting.run_graph()
        if shared is not None:
            return shared
        if self._own_graph is None:
            self._own_graph = Graph()
        return self._own_graph

    def init(
        self,
        args: list[str] | None = None,
        *,
        initialize_logging: bool = True,
        domain_id: int | None = None,
    ) -> None:
        """Start the lifecycle, reading the ``--ros-args`` sections of ``args`` (``sys.argv``
        when None); the other options are accepted and ignored.

        Raises:
            RuntimeError: the context was initialised before (rclpy's error).
            RosArgumentError: a ``--ros-args`` rule that cannot be read.
        """
        if domain_id is not None and domain_id < 0:
            raise RuntimeError(f"Domain id ({domain_id}) should not be lower than zero.")
        if self._initialized:
            raise RuntimeError("Context.init() must only be called once")
        self.arguments = parse_ros_arguments(sys.argv[1:] if args is None else list(args))
        self._initialized = True

    def ok(self) -> bool:
        """True between :meth:`init` and shutdown."""
        return self._initialized and not self._shut_down

    def shutdown(self) -> None:
        """End the lifecycle: destroy the context's nodes, run the shutdown callbacks.

        Raises:
            RuntimeError: the context was never initialised, or is already shut down.
        """
        if not self._initialized:
            raise RuntimeError("Context must be initialized before it can be shutdown")
        if self._shut_down:
            raise RuntimeError("rcl_shutdown already called on the given context")
        self._cleanup()

    def try_shutdown(self) -> None:
        """Shut down if initialised and not shut down yet; otherwise do nothing."""
        if self.ok():
            self._cleanup()

    def _cleanup(self) -> None:
        self._shut_down = True
        for reference in list(self._nodes):
            node = reference()
            if node is not None:
                node.destroy_node()
        self._nodes.clear()
        callbacks, self._callbacks = self._callbacks, []
        for callback in callbacks:
            callback()

    def on_shutdown(self, callback: Callable[[], None]) -> None:
        """Call ``callback`` at shutdown (at once if the context is already shut down)."""
        if not callable(callback):
            raise TypeError(f"callback should be a callable, got {type(callback)}")
        if self._shut_down:
            callback()
        else:
            self._callbacks.append(callback)

    def track_node(self, node: TrackedNode) -> None:
        """Destroy ``node`` when this context shuts down (held weakly)."""
        # Nodes dropped without destroy_node() leave dead references; a script that makes
        # navigators in a loop must not pile them up.
        self._nodes = [reference for reference in self._nodes if reference() is not None]
        self._nodes.append(weakref.ref(node))

    def node_names(self) -> list[str]:
        """The names of the context's live nodes, in creation order."""
        return [node.get_name() for ref in self._nodes if (node := ref()) is not None]

    def untrack_node(self, node: TrackedNode) -> None:
        """Forget ``node`` (it was destroyed on its own)."""
        self._nodes = [ref for ref in self._nodes if ref() is not None and ref() is not node]

    def __enter__(self) -> Context:
        if not self._initialized:
            raise RuntimeError(
                "init() must be called on this Context before using it with a context manager"
            )
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.try_shutdown()


_default_context: ContextVar[Context | None] = ContextVar("rclpy_default_context", default=None)


def get_default_context(*, shutting_down: bool = False) -> Context:
    """The context ``rclpy.init()`` and new nodes use when given none.

    With ``shutting_down`` the current default is returned and a fresh one takes its place
    for the next ``init``, which is how ``rclpy.shutdown()`` makes init/shutdown repeatable.
    """
    context = _default_context.get()
    if context is None:
        context = Context()
    _default_context.set(None if shutting_down else context)
    return context


@contextmanager
def fresh_default_context() -> Iterator[Context]:
    """A brand-new default context inside the block; the previous one is restored after."""
    context = Context()
    token = _default_context.set(context)
    try:
        yield context
    finally:
        _default_context.reset(token)


def set_fresh_default_context() -> Context:
    """Give the current ``contextvars`` context a brand-new default context (until it ends):
    each node file of a run gets its own, so each can call ``rclpy.init()``."""
    context = Context()
    _default_context.set(context)
    return context
