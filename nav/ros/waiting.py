"""Waiting on sim time from node code: what ``spin``, ``rate.sleep`` and TF timeouts call.

The ROS runtime (:mod:`baobab.nav.ros.runtime`) registers its scheduler here for the length
of a run; node code inherits it. A Nav2 script's navigator registers itself the same way
(:mod:`baobab.nav.navigator_time`): its waits step the navigator's own simulation. Outside a
run, and from threads that are not actors, nothing can advance sim time, so a wait that would
block raises instead.
"""

from __future__ import annotations

from collections.abc import Callable
from contextvars import ContextVar
from typing import TYPE_CHECKING, Protocol

from baobab.nav.ros import UnsupportedRosFeatureError

if TYPE_CHECKING:
    from baobab.nav.ros.graph import Graph


class Waiter(Protocol):
    """What advances sim time for a blocked caller: the runtime's scheduler, or a navigator."""

    def current(self) -> object | None:
        """Who is calling, or None for a thread that cannot wait on sim time."""
        ...

    def block(self, deadline_ns: int | None, ready: Callable[[], bool] | None) -> None:
        """Return at sim time ``deadline_ns`` or once ``ready()`` holds."""
        ...


_scheduler: ContextVar[Waiter | None] = ContextVar("ros_scheduler", default=None)
_graph: ContextVar[Graph | None] = ContextVar("ros_graph", default=None)


def waiter() -> Waiter | None:
    """What waits are handed to in this context (None: nothing can wait)."""
    return _scheduler.get()


def set_run(scheduler: Waiter | None, graph: Graph | None) -> None:
    """Register (or clear, with None) the running scheduler and graph in this context."""
    _scheduler.set(scheduler)
    _graph.set(graph)


def run_graph() -> Graph | None:
    """The graph of the run in progress, or None outside a run."""
    return _graph.get()


def can_wait() -> bool:
    """True when the caller is node code of a run, so waiting advances sim time."""
    scheduler = _scheduler.get()
    return scheduler is not None and scheduler.current() is not None


def wait(deadline_ns: int | None, ready: Callable[[], bool] | None, *, what: str) -> None:
    """Block until sim time ``deadline_ns`` (None: no limit) or until ``ready()`` holds.

    Raises:
        UnsupportedRosFeatureError: not node code of a run (``what`` names the call).
    """
    scheduler = _scheduler.get()
    if scheduler is None or scheduler.current() is None:
        raise UnsupportedRosFeatureError(
            f"{what} waits on simulation time, which only node code run by the ROS runtime "
            "can do (run the file with `baobab ros run NODE.py --world W --robot R`), or the "
            "thread of a Nav2 script that built a BasicNavigator"
        )
    scheduler.block(deadline_ns, ready)
