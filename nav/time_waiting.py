"""Waiting on sim time from user code: what ``spin``, ``rate.sleep``, clock sleeps and TF
timeouts call.

Whatever advances sim time for a blocked caller registers here as the :class:`Waiter` of the
current context: the ROS runtime's scheduler for the length of a run (node code inherits it),
or a Nav2 script's navigator (:mod:`baobab.nav.navigator_time`), whose waits step its own
simulation. Outside those, and from threads that are not actors, nothing can advance sim time,
so a wait that would block raises instead. This module sits below :mod:`baobab.nav.ros` so
that :mod:`baobab.nav.rostime`'s clock can wait too.
"""

from __future__ import annotations

from collections.abc import Callable
from contextvars import ContextVar
from typing import Protocol

from baobab.nav.errors import UnsupportedRosFeatureError


class Waiter(Protocol):
    """What advances sim time for a blocked caller: the runtime's scheduler, or a navigator."""

    def current(self) -> object | None:
        """Who is calling, or None for a thread that cannot wait on sim time."""
        ...

    def block(self, deadline_ns: int | None, ready: Callable[[], bool] | None) -> None:
        """Return at sim time ``deadline_ns`` or once ``ready()`` holds."""
        ...


_waiter: ContextVar[Waiter | None] = ContextVar("sim_time_waiter", default=None)


def waiter() -> Waiter | None:
    """What waits are handed to in this context (None: nothing can wait)."""
    return _waiter.get()


def set_waiter(waiter: Waiter | None) -> None:
    """Register (or clear, with None) what advances sim time in this context."""
    _waiter.set(waiter)


def can_wait() -> bool:
    """True when the caller is node code of a run, so waiting advances sim time."""
    current = _waiter.get()
    return current is not None and current.current() is not None


def wait(deadline_ns: int | None, ready: Callable[[], bool] | None, *, what: str) -> None:
    """Block until sim time ``deadline_ns`` (None: no limit) or until ``ready()`` holds.

    Raises:
        UnsupportedRosFeatureError: not node code of a run (``what`` names the call).
    """
    scheduler = _waiter.get()
    if scheduler is None or scheduler.current() is None:
        raise UnsupportedRosFeatureError(
            f"{what} waits on simulation time, which only node code run by the ROS runtime "
            "can do (run the file with `baobab ros run NODE.py --world W --robot R`), or the "
            "thread of a Nav2 script that built a BasicNavigator"
        )
    scheduler.block(deadline_ns, ready)
