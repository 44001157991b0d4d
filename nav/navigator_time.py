"""A navigator as the sim-time waiter of its script: what ``rclpy.spin_once``, ``Rate.sleep``
and ``Clock.sleep_for`` wait on in a Nav2 script.

In a ``baobab ros run`` the ROS runtime's scheduler advances sim time for node code that
blocks (:mod:`baobab.nav.ros.waiting`). A Nav2 script has no runtime: its simulation is the
one its ``BasicNavigator`` built. The navigator registers a :class:`NavigatorWaits` in its
place, so the same waits step the navigator's simulation (paced to the wall clock with
``realtime``), from the thread that built the navigator. The newest navigator is the waiter,
as it is the sim-time source; destroying it unregisters it.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

from baobab.nav.ros import waiting
from baobab.nav.rostime import S_TO_NS

SPIN_HORIZON = 0.1
"""Sim seconds a wait without a deadline (``rclpy.spin_once(node)``) advances at most: Nav2's
poll, and about when a running task's next action feedback would wake a real executor."""

Advance = Callable[[float, Callable[[], bool] | None], None]
"""Steps the simulation up to a horizon (s), stopping early once the condition holds."""


class NavigatorWaits:
    """Blocks by stepping a navigator's simulation (the waiter protocol of ``waiting``).

    Args:
        advance: the navigator's stepping (at least the horizon, in whole physics steps).
        now_ns: the navigator's sim time (ns).
    """

    def __init__(self, advance: Advance, now_ns: Callable[[], int]) -> None:
        self._advance = advance
        self._now_ns = now_ns
        self._thread = threading.get_ident()

    def current(self) -> NavigatorWaits | None:
        """This waiter for the thread that built the navigator, None for any other."""
        return self if threading.get_ident() == self._thread else None

    def block(self, deadline_ns: int | None, ready: Callable[[], bool] | None) -> None:
        """Step the simulation until sim time ``deadline_ns`` or until ``ready()`` holds; with
        no deadline, for at most :data:`SPIN_HORIZON`."""
        if deadline_ns is None:
            deadline_ns = self._now_ns() + round(SPIN_HORIZON * S_TO_NS)
        while ready is None or not ready():
            remaining = deadline_ns - self._now_ns()
            if remaining <= 0:
                return
            self._advance(remaining / S_TO_NS, ready)

    def register(self) -> None:
        """Become the waiter of the caller's context (replacing an older navigator's)."""
        current = waiting.waiter()
        if current is None or isinstance(current, NavigatorWaits):
            waiting.set_run(self, waiting.run_graph())

    def unregister(self) -> None:
        """Stop being the waiter, if it still is."""
        if waiting.waiter() is self:
            waiting.set_run(None, waiting.run_graph())
