"""``rclpy.executors``: executors that run nodes' timers, subscriptions and tasks.

As rclpy's: ``spin_once`` runs at most one callback. When nothing is ready it waits (on sim
time) for something to be; the ready work found by one wait is handed out over the following
calls, in rclpy's order: tasks first, then per node (in the order the nodes were added) its
timers, then its subscriptions. ``MultiThreadedExecutor`` is accepted and runs callbacks one
at a time in the same order, so a run stays deterministic.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from baobab.nav.ros import waiting
from baobab.nav.ros.rclpy.context import Context, get_default_context
from baobab.nav.ros.rclpy.task import Future

if TYPE_CHECKING:
    from baobab.nav.ros.rclpy.node import Node

__all__ = [
    "Executor",
    "ExternalShutdownException",
    "MultiThreadedExecutor",
    "ShutdownException",
    "SingleThreadedExecutor",
    "TimeoutException",
]


class ExternalShutdownException(Exception):
    """The context was shut down while the executor waited."""


class ShutdownException(Exception):
    """The executor was shut down."""


class TimeoutException(Exception):
    """A wait ran out of time."""


Work = Callable[[], None]


class Executor:
    """Runs the callbacks of the nodes added to it (module docstring)."""

    def __init__(self, *, context: Context | None = None) -> None:
        self._context = get_default_context() if context is None else context
        self._nodes: list[Node] = []
        self._tasks: list[tuple[Future, Callable[..., Any], tuple[Any, ...]]] = []
        self._pending: deque[tuple[object, Work]] = deque()
        self._shut_down = False

    @property
    def context(self) -> Context:
        """The context the executor follows."""
        return self._context

    def add_node(self, node: Node) -> bool:
        """Spin ``node`` too; False when it was added already."""
        if node in self._nodes:
            return False
        self._nodes.append(node)
        node.executor = self
        return True

    def remove_node(self, node: Node) -> None:
        """Stop spinning ``node``."""
        self._nodes = [item for item in self._nodes if item is not node]

    def get_nodes(self) -> list[Node]:
        """The nodes added."""
        return list(self._nodes)

    def create_task(self, callback: Callable[..., Any], *args: Any) -> Future:
        """Run ``callback(*args)`` at the next spin; its result completes the returned future."""
        future = Future()
        self._tasks.append((future, callback, args))
        return future

    def shutdown(self, timeout_sec: float | None = None) -> bool:
        """Stop spinning and forget the nodes."""
        self._shut_down = True
        for node in self._nodes:
            if node.executor is self:
                node.executor = None
        self._nodes = []
        return True

    def wake(self) -> None:
        """Accepted: a waiting executor notices new work by itself."""

    # -- finding work -----------------------------------------------------------------------

    def _ready_work(self) -> list[tuple[object, Work]]:
        work: list[tuple[object, Work]] = []
        tasks, self._tasks = self._tasks, []
        work.extend(
            (future, _task_runner(future, callback, args)) for future, callback, args in tasks
        )
        for node in self._nodes:
            for timer in node.timers:
                if timer.callback is not None and timer.is_ready():
                    work.append((timer, _timer_runner(timer)))
            for subscription in node.subscriptions:
                if subscription.has_message():
                    work.append((subscription, subscription.take_and_call))
        return work

    def _has_work(self) -> bool:
        if self._tasks or not self._context.ok() or self._shut_down:
            return True
        for node in self._nodes:
            if any(timer.callback is not None and timer.is_ready() for timer in node.timers):
                return True
            if any(subscription.has_message() for subscription in node.subscriptions):
                return True
        return False

    def _next_work(self) -> Work | None:
        while self._pending:
            entity, work = self._pending.popleft()
            if _still_ready(entity):
                return work
        self._pending.extend(self._ready_work())
        while self._pending:
            entity, work = self._pending.popleft()
            if _still_ready(entity):
                return work
        return None

    # -- spinning ---------------------------------------------------------------------------

    def spin_once(self, timeout_sec: float | None = None) -> None:
        """Run one ready callback, waiting up to ``timeout_sec`` (None or < 0: no limit) for
        one; return without one when the time runs out or the context shuts down.
        """
        work = self._next_work()
        if work is None and timeout_sec != 0:
            deadline = None
            if timeout_sec is not None and timeout_sec >= 0:
                deadline = self._now_ns() + round(timeout_sec * 1e9)
            waiting.wait(deadline, self._has_work, what="Executor.spin_once()")
            work = self._next_work()
        if work is not None and self._context.ok():
            work()

    def spin(self) -> None:
        """Run callbacks until the context shuts down."""
        while self._context.ok() and not self._shut_down:
            self.spin_once()

    def spin_until_future_complete(self, future: Future, timeout_sec: float | None = None) -> None:
        """Run callbacks until ``future`` is done, the time is up or the context shuts down."""
        if timeout_sec is None or timeout_sec < 0:
            while self._context.ok() and not future.done() and not self._shut_down:
                self._spin_once_until(future, None)
            return
        end = self._now_ns() + round(timeout_sec * 1e9)
        while self._context.ok() and not future.done() and self._now_ns() < end:
            self._spin_once_until(future, end)

    def spin_once_until_future_complete(
        self, future: Future, timeout_sec: float | None = None
    ) -> None:
        """One ``spin_once`` that also returns when ``future`` completes."""
        deadline = None
        if timeout_sec is not None and timeout_sec >= 0:
            deadline = self._now_ns() + round(timeout_sec * 1e9)
        self._spin_once_until(future, deadline)

    def _spin_once_until(self, future: Future, deadline: int | None) -> None:
        work = self._next_work()
        if work is None:
            waiting.wait(
                deadline,
                lambda: future.done() or self._has_work(),
                what="Executor.spin_until_future_complete()",
            )
            work = self._next_work()
        if work is not None:
            work()

    def _now_ns(self) -> int:
        from baobab.nav.rostime import sim_time_ns

        return sim_time_ns()

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.shutdown()


class SingleThreadedExecutor(Executor):
    """Runs callbacks in the thread that spins it."""


class MultiThreadedExecutor(Executor):
    """Accepted for compatibility; runs callbacks one at a time, deterministically.

    Args:
        num_threads: accepted and ignored.
    """

    def __init__(self, num_threads: int | None = None, *, context: Context | None = None) -> None:
        super().__init__(context=context)
        self.num_threads = num_threads


def _still_ready(entity: object) -> bool:
    if isinstance(entity, Future):
        return True
    has_message = getattr(entity, "has_message", None)
    if has_message is not None:
        return bool(has_message())
    return bool(getattr(entity, "is_ready")())  # noqa: B009  (a timer)


def _timer_runner(timer: Any) -> Work:
    def run() -> None:
        timer.call()
        timer.callback()

    return run


def _task_runner(future: Future, callback: Callable[..., Any], args: tuple[Any, ...]) -> Work:
    def run() -> None:
        if future.cancelled():
            return
        try:
            future.set_result(callback(*args))
        except Exception as exc:  # rclpy stores a task's exception in its future
            future.set_exception(exc)

    return run
