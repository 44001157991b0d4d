"""``rclpy.timer``: timers and rates on the node's clock (simulation time).

A timer created at time t0 with period p is due at t0 + p, t0 + 2p, ... as rcl schedules it:
each call moves the due time by exactly one period, and a timer that fell behind skips the
periods it missed. Its callback runs when an executor spinning its node finds it due; under
``baobab ros run`` the simulation stops at every due time, so callbacks run at exactly the sim
times ROS would schedule them (rounded up to the physics step).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from baobab.nav.rostime import Clock

if TYPE_CHECKING:
    from baobab.nav.ros.graph import Graph

__all__ = ["Rate", "Timer"]


class Timer:
    """A periodic callback (``rclpy.timer.Timer``); made by ``Node.create_timer``."""

    def __init__(
        self,
        callback: Callable[[], Any] | None,
        callback_group: object,
        timer_period_ns: int,
        clock: Clock,
        *,
        graph: Graph,
        autostart: bool = True,
    ) -> None:
        if timer_period_ns < 0:
            raise ValueError("timer period must not be negative")
        self.callback = callback
        self.callback_group = callback_group
        self._clock = clock
        self._graph = graph
        self._period_ns = int(timer_period_ns)
        self._last_call_ns = clock.now().nanoseconds
        self._next_ns = self._last_call_ns + self._period_ns
        self._canceled = not autostart
        self._destroyed = False
        graph.timers.append(self)

    @property
    def clock(self) -> Clock:
        """The clock the timer runs on."""
        return self._clock

    @property
    def timer_period_ns(self) -> int:
        """The period (ns)."""
        return self._period_ns

    @timer_period_ns.setter
    def timer_period_ns(self, value: int) -> None:
        self._period_ns = int(value)
        self.reset()

    @property
    def next_call_ns(self) -> int | None:
        """The sim time (ns) the timer is next due, or None while canceled."""
        return None if self._canceled or self._destroyed else self._next_ns

    def is_ready(self) -> bool:
        """True when due now."""
        due = self.next_call_ns
        return due is not None and self._clock.now().nanoseconds >= due

    def call(self) -> None:
        """Advance the schedule by one call (what rcl does before the callback runs)."""
        now = self._clock.now().nanoseconds
        self._last_call_ns = now
        period = self._period_ns
        self._next_ns += period
        if self._next_ns < now:
            if period == 0:
                self._next_ns = now
            else:
                self._next_ns += (1 + (now - self._next_ns - 1) // period) * period

    def cancel(self) -> None:
        """Stop calling back until :meth:`reset`."""
        self._canceled = True

    def is_canceled(self) -> bool:
        """True after :meth:`cancel`."""
        return self._canceled

    def reset(self) -> None:
        """Restart: next due one period from now."""
        self._canceled = False
        self._next_ns = self._clock.now().nanoseconds + self._period_ns

    def time_since_last_call(self) -> int:
        """Nanoseconds since the last call (or since creation)."""
        return self._clock.now().nanoseconds - self._last_call_ns

    def time_until_next_call(self) -> int | None:
        """Nanoseconds until due (negative when overdue); None while canceled."""
        due = self.next_call_ns
        return None if due is None else due - self._clock.now().nanoseconds

    def destroy(self) -> None:
        """Remove the timer for good."""
        if not self._destroyed:
            self._destroyed = True
            self._graph.timers[:] = [timer for timer in self._graph.timers if timer is not self]

    def __enter__(self) -> Timer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.destroy()


class Rate:
    """``Node.create_rate(hz)``: :meth:`sleep` waits until the next tick, on sim time.

    Ticks fall at creation + k / hz; a loop slower than the rate skips missed ticks.
    """

    def __init__(self, timer: Timer, *, wait: Callable[[int | None, Callable[[], bool]], None]):
        self._timer = timer
        self._wait = wait

    def sleep(self) -> None:
        """Block until the next tick (sim time advances meanwhile).

        Raises:
            ROSInterruptException: the rate was destroyed.
        """
        from baobab.nav.ros.rclpy.exceptions import ROSInterruptException

        due = self._timer.next_call_ns
        if due is None:
            raise ROSInterruptException()
        self._wait(due, self._timer.is_ready)
        self._timer.call()

    def destroy(self) -> None:
        """Stop the rate."""
        self._timer.destroy()
