"""The ROS run in progress: what node code's waits go to and the topic graph it publishes on.

Waits themselves are :mod:`baobab.nav.time_waiting`'s (re-exported here); this module adds the
run's :class:`~baobab.nav.ros.graph.Graph`. The ROS runtime (:mod:`baobab.nav.ros.runtime`)
registers both for the length of a run; a Nav2 script's navigator registers itself as the
waiter (:mod:`baobab.nav.navigator_time`).
"""

from __future__ import annotations

from contextvars import ContextVar
from typing import TYPE_CHECKING

from baobab.nav.time_waiting import Waiter, can_wait, set_waiter, wait, waiter

if TYPE_CHECKING:
    from baobab.nav.ros.graph import Graph

__all__ = ["Waiter", "can_wait", "run_graph", "set_run", "wait", "waiter"]

_graph: ContextVar[Graph | None] = ContextVar("ros_graph", default=None)


def set_run(scheduler: Waiter | None, graph: Graph | None) -> None:
    """Register (or clear, with None) the running scheduler and graph in this context."""
    set_waiter(scheduler)
    _graph.set(graph)


def run_graph() -> Graph | None:
    """The graph of the run in progress, or None outside a run."""
    return _graph.get()
