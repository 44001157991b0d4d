"""SIGINT, SIGTERM and SIGHUP: every command ends on them with ``128 + signal``, never a traceback.

- Start-up, and the commands that write nothing that needs finishing (``validate``, ``tree``,
  ``schema``, ``list``, ``run`` until its run starts) (:func:`exit_on_signals`): the process
  flushes its streams and exits at once with ``128 + signal`` (130, 143, 129). Nothing is
  raised into the code that was running, which may be a native extension being imported.
- Commands that must tidy up on the way out (a terminal in raw mode, worker processes)
  (:func:`unwind_on_signals`): SIGINT raises ``KeyboardInterrupt`` as usual, SIGTERM and
  SIGHUP raise :class:`SignalExit`, so ``finally`` blocks run; the exit code is the same.
- ``baobab run`` once its run starts (:class:`RunSignals`): the first of them ends the run at
  the next tick as CANCELED (``error_msg`` names the signal), the run folder is written as
  usual, and the exit code is ``128 + signal``. A signal that arrives while the folder is
  written lets the writing finish first. A second SIGINT interrupts at once, as in any
  command-line tool (the run folder is then not written, and no temporary folder stays
  behind); a repeated SIGTERM or SIGHUP only confirms the first.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

HANDLED = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
"""The signals that end a command gracefully."""
EXIT_SIGNAL_BASE = 128
"""A command ended by signal N exits with ``128 + N``, as a shell reports it."""


class SignalExit(SystemExit):
    """The process leaves because of a signal; ``code`` is ``128 + signal``."""


def exit_code_for(signum: int) -> int:
    """``128 + signum``: 130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP."""
    return EXIT_SIGNAL_BASE + int(signum)


def _exit_at_once(signum: int, _frame: FrameType | None) -> None:
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):  # closed, or interrupted inside a write
            stream.flush()
    os._exit(exit_code_for(signum))


def _unwind(signum: int, _frame: FrameType | None) -> None:
    raise SignalExit(exit_code_for(signum))


def exit_on_signals() -> None:
    """Let each of :data:`HANDLED` end the process at once with ``128 + signal``.

    Only in the main thread; elsewhere nothing changes.
    """
    if threading.current_thread() is threading.main_thread():
        for signum in HANDLED:
            signal.signal(signum, _exit_at_once)


def exits_at_once() -> bool:
    """Whether :func:`exit_on_signals` is in force (the ``baobab`` process, not a caller's)."""
    return signal.getsignal(signal.SIGTERM) is _exit_at_once


def unwind_on_signals() -> None:
    """SIGINT raises KeyboardInterrupt, SIGTERM and SIGHUP :class:`SignalExit` (main thread)."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.default_int_handler)
        signal.signal(signal.SIGTERM, _unwind)
        signal.signal(signal.SIGHUP, _unwind)


UNWINDING_COMMANDS = ("teleop", "campaign", "nav2")
"""Commands that tidy up when a signal ends them (a raw terminal, workers, a user's script)."""


def signals_for(command: str) -> None:
    """In the ``baobab`` process, let :data:`UNWINDING_COMMANDS` unwind on signals."""
    if command in UNWINDING_COMMANDS and exits_at_once():
        unwind_on_signals()


class RunSignals:
    """What the signals do while a run runs and its folder is written; see the module text.

    Attributes:
        first: the first signal received, or None.
    """

    def __init__(self) -> None:
        self.first: signal.Signals | None = None
        self._sigints = 0

    def note(self, signum: int) -> None:
        """Count a signal (a forwarded one too): the first one decides the exit code."""
        if self.first is None:
            self.first = signal.Signals(signum)
        if signum == signal.SIGINT:
            self._sigints += 1

    def reason(self) -> str | None:
        """The name of the first signal (the run ends CANCELED), or None; polled every tick."""
        return None if self.first is None else self.first.name

    def exit_code(self, own: int) -> int:
        """``128 + signal`` after a signal, else ``own`` (the run's own exit code)."""
        return own if self.first is None else exit_code_for(self.first)

    def _handle(self, signum: int, _frame: FrameType | None) -> None:
        self.note(signum)
        if signum == signal.SIGINT and self._sigints == 2:
            raise KeyboardInterrupt  # the second Ctrl-C: stop now

    @contextmanager
    def installed(self) -> Iterator[RunSignals]:
        """Handle :data:`HANDLED` while inside (main thread only: elsewhere nothing changes)."""
        if threading.current_thread() is not threading.main_thread():
            yield self
            return
        previous = {signum: signal.signal(signum, self._handle) for signum in HANDLED}
        try:
            yield self
        finally:
            for signum, handler in previous.items():
                signal.signal(signum, handler)
