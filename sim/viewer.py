"""MuJoCo's interactive viewer, opened only where a display exists, and real-time pacing.

``mujoco.viewer.launch_passive`` terminates the whole process when GLFW finds no display (no
Python exception), so :func:`open_viewer` checks ``DISPLAY`` / ``WAYLAND_DISPLAY`` first and
returns None with a clear message instead.
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable, Mapping
from typing import Any

import mujoco

from baobab.sim.builder import ROBOT_GROUP

NO_DISPLAY_MESSAGE = (
    "no display (neither DISPLAY nor WAYLAND_DISPLAY is set): the MuJoCo viewer cannot open; "
    "the run goes on headless (record it with --record FILE.mcap or --video FILE.mp4)"
)


def display_available(environ: Mapping[str, str] | None = None) -> bool:
    """True if an X11 or Wayland display is set in ``environ`` (default: the process's)."""
    env = os.environ if environ is None else environ
    return bool(env.get("DISPLAY") or env.get("WAYLAND_DISPLAY"))


def _print_to_stderr(message: str) -> None:
    print(message, file=sys.stderr)


def open_viewer(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    *,
    report: Callable[[str], None] = _print_to_stderr,
    environ: Mapping[str, str] | None = None,
) -> Any | None:
    """Open MuJoCo's passive viewer on ``model``/``data``, robot geoms (group 3) shown.

    The caller steps the physics and calls ``handle.sync()`` after each step it wants drawn
    (pace it with :class:`RealTimePacer`), and ``handle.close()`` at the end.

    Args:
        model: the compiled model.
        data: the data the simulation steps.
        report: receives the message when no display exists (default: print to stderr).
        environ: the environment to check (default: the process's).

    Returns:
        The viewer handle (``mujoco.viewer.Handle``), or None when there is no display.
    """
    if not display_available(environ):
        report(NO_DISPLAY_MESSAGE)
        return None
    import mujoco.viewer

    handle = mujoco.viewer.launch_passive(model, data, show_left_ui=False, show_right_ui=False)
    with handle.lock():
        handle.opt.geomgroup[ROBOT_GROUP] = 1
    return handle


class RealTimePacer:
    """Hold a loop back so sim time advances no faster than the wall clock times ``speed``.

    Args:
        speed: sim seconds per wall second (1.0 is real time).
        clock: wall clock in seconds (monotonic).
        sleep: waits a number of seconds.
    """

    def __init__(
        self,
        speed: float = 1.0,
        *,
        clock: Callable[[], float] = time.monotonic,
        sleep: Callable[[float], None] = time.sleep,
    ) -> None:
        if not speed > 0:
            raise ValueError(f"real-time speed must be positive, got {speed}")
        self.speed = speed
        self._clock = clock
        self._sleep = sleep
        self._origin: tuple[float, float] | None = None

    def wait(self, sim_time: float) -> float:
        """Sleep until the wall clock catches up with ``sim_time`` (s); returns the sleep (s).

        The first call sets the origin. A loop that falls behind does not sleep and does not
        try to catch up later faster than ``speed``.
        """
        now = self._clock()
        if self._origin is None:
            self._origin = (now, sim_time)
            return 0.0
        wall0, sim0 = self._origin
        delay = wall0 + (sim_time - sim0) / self.speed - now
        if delay <= 0:
            if delay < -0.25:  # more than a quarter second behind: re-anchor instead of rushing
                self._origin = (now, sim_time)
            return 0.0
        self._sleep(delay)
        return delay
