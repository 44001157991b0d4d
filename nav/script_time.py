"""Python's own clock in a Nav2 script under ``baobab nav2``: sim time once a navigator runs.

Nav2 scripts pace their polls with ``time.sleep(0.2)`` and time their goals with
``time.time()``. Under ROS those read the wall clock while the robot drives on its own; here
the simulation moves only when the script lets it, so :func:`script_time` makes these calls,
made by the script's thread while a navigator exists, read and advance sim time:

* ``time.sleep(d)`` advances the navigator's simulation by ``d`` (the same wait as
  ``Clock.sleep_for``, :mod:`baobab.nav.navigator_time`);
* ``time.time()``, ``time.time_ns()``, ``time.monotonic()``, ``time.monotonic_ns()`` read the
  wall time at which the script started plus the time that passed since: wall time until a
  navigator exists, sim time while one does (so they never go back).

Other threads, ``time.perf_counter``, ``time.process_time`` and ``datetime`` keep the wall
clock. With ``baobab nav2 --realtime`` the simulation is paced to the wall clock, so the clock
readings stay the wall's (``wall_clock=True``); ``time.sleep`` still advances the simulation,
paced, so it takes as long as it says and the robot drives on meanwhile.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from baobab.nav.ros import waiting
from baobab.nav.rostime import S_TO_NS, SimTimeSource, sim_time_ns, sim_time_source


class ScriptClock:
    """Seconds since the script started: wall time while no sim-time source is registered,
    sim time while one is; continuous across sources coming and going.

    Args:
        real_monotonic: the wall clock (s).
    """

    def __init__(self, real_monotonic: Callable[[], float]) -> None:
        self._real = real_monotonic
        self._source: SimTimeSource | None = None
        self._base = 0.0
        self._source_start = 0.0
        self._real_start = real_monotonic()

    def elapsed(self) -> float:
        """Seconds since the script started, on the clock in force (class docstring)."""
        source = sim_time_source()
        real_now = self._real()
        if source is not self._source:
            self._base = self._value(real_now)
            self._source = source
            self._source_start = 0.0 if source is None else source()
            self._real_start = real_now
        return self._value(real_now)

    def _value(self, real_now: float) -> float:
        if self._source is None:
            return self._base + (real_now - self._real_start)
        return self._base + (self._source() - self._source_start)


@contextmanager
def script_time(*, wall_clock: bool = False) -> Iterator[ScriptClock]:
    """Inside the block, the calling thread's ``time.sleep``, ``time.time`` and
    ``time.monotonic`` (and their ``_ns`` forms) follow sim time (module docstring); with
    ``wall_clock`` only ``time.sleep`` does."""
    thread = threading.get_ident()
    real_sleep, real_time, real_time_ns = time.sleep, time.time, time.time_ns
    real_monotonic, real_monotonic_ns = time.monotonic, time.monotonic_ns
    clock = ScriptClock(real_monotonic)
    wall_origin, monotonic_origin = real_time(), real_monotonic()

    def ours() -> bool:
        return threading.get_ident() == thread

    waiting_now = False  # a sleep during a wait is baobab's own (real-time pacing): real

    def sleep(seconds: float) -> None:
        nonlocal waiting_now
        seconds = float(seconds)
        if waiting_now or not (ours() and waiting.can_wait()):
            real_sleep(seconds)
            return
        if seconds < 0:
            raise ValueError("sleep length must be non-negative")
        waiting_now = True
        try:
            waiting.wait(sim_time_ns() + round(seconds * S_TO_NS), None, what="time.sleep()")
        finally:
            waiting_now = False

    def wall() -> float:
        return wall_origin + clock.elapsed() if ours() else real_time()

    def monotonic() -> float:
        return monotonic_origin + clock.elapsed() if ours() else real_monotonic()

    patches = {
        "sleep": sleep,
        "time": wall,
        "time_ns": lambda: round(wall() * S_TO_NS) if ours() else real_time_ns(),
        "monotonic": monotonic,
        "monotonic_ns": lambda: round(monotonic() * S_TO_NS) if ours() else real_monotonic_ns(),
    }
    if wall_clock:
        patches = {"sleep": sleep}
    saved = {name: getattr(time, name) for name in patches}
    for name, function in patches.items():
        setattr(time, name, function)
    try:
        yield clock
    finally:
        for name, function in saved.items():
            setattr(time, name, function)
