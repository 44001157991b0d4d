"""Keyboard teleop in a terminal: raw key input and the rules that turn key presses into motion.

A terminal reports key presses, never releases, so the seed's held-key model (§5) needs a rule
for when a key counts as released. The rules, with ``t`` the time of the press (s):

- a motion key (the layout's four, or an arrow key) counts as held until ``t + hold_time``
  (0.4 s by default). Holding a key down makes the terminal repeat it (after its repeat
  delay, usually 0.25-0.6 s, then about 30 times a second), and each repeat renews the hold,
  so the robot moves while the key is down and stops within ``hold_time`` after it is let
  go. A single tap moves it for ``hold_time``.
- the command is the seed's mapping of the held set (:func:`~.teleop.twist_from_keys`):
  forward/backward combine with left/right, and opposite keys held together cancel. Only the
  last key pressed repeats in a terminal, so to drive an arc tap the other key again and
  again, or use two keys in turn.
- space releases every key at once: stop now.
- ``q`` quits; in the ZQSD layout, where ``q`` turns left, Escape quits (Escape and Ctrl-D
  quit in both). Ctrl-C interrupts (SIGINT).

:class:`RawTerminal` switches the terminal to character-at-a-time input without echo
(``tty.setcbreak``: no line buffering, signals still work) and puts it back however the
program leaves: a normal exit, an exception, SIGINT, SIGTERM or SIGHUP. It reads with
``select`` and a timeout, so a loop can wait for keys and for the wall clock at once.
"""

from __future__ import annotations

import codecs
import contextlib
import enum
import os
import select
import signal
import termios
import threading
import tty
from collections.abc import Iterator
from types import FrameType, TracebackType
from typing import Any

from baobab.robots.diff_drive.teleop import (
    DEFAULT_ANGULAR_SPEED,
    DEFAULT_LINEAR_SPEED,
    KeyLayout,
    Twist2D,
    twist_from_keys,
)

DEFAULT_HOLD_TIME = 0.4
"""How long (s) a motion key press counts as held without a repeat."""
SPACE = " "
ESCAPE = "escape"
"""The name :func:`split_keys` gives a lone Escape key."""
CTRL_D = "\x04"
ARROWS = {"A": "up", "B": "down", "C": "right", "D": "left"}
"""Final byte of an arrow key's escape sequence -> the key's name."""


class KeyAction(enum.Enum):
    """What a key press asks of the program beyond the motion."""

    NONE = "none"
    STOP = "stop"
    QUIT = "quit"


def split_keys(text: str) -> list[str]:
    """The keys in ``text`` as read from a terminal, in order.

    Printable characters stand for themselves; an escape sequence (``ESC [ ... X`` or
    ``ESC O X``) becomes ``up``/``down``/``left``/``right`` for the arrows and ``unknown``
    otherwise; a lone ESC becomes ``escape``.
    """
    keys: list[str] = []
    i = 0
    while i < len(text):
        char = text[i]
        if char != "\x1b":
            keys.append(char)
            i += 1
            continue
        if i + 1 < len(text) and text[i + 1] in "[O":
            j = i + 2
            while j < len(text) and not "\x40" <= text[j] <= "\x7e":
                j += 1
            final = text[j] if j < len(text) else ""
            keys.append(ARROWS.get(final, "unknown"))
            i = j + 1
            continue
        keys.append(ESCAPE)
        i += 1
    return keys


class TerminalKeys:
    """Key presses with their times -> the keys held and the command (see the module rules).

    Args:
        layout: the layout's four motion keys.
        hold_time: how long (s) a press counts as held (must be positive).
        linear_speed: forward speed while a forward/backward key is held (m/s).
        angular_speed: turn rate while a left/right key is held (rad/s).

    Raises:
        ValueError: if ``hold_time`` is not positive.
    """

    def __init__(
        self,
        layout: KeyLayout,
        *,
        hold_time: float = DEFAULT_HOLD_TIME,
        linear_speed: float = DEFAULT_LINEAR_SPEED,
        angular_speed: float = DEFAULT_ANGULAR_SPEED,
    ) -> None:
        if not hold_time > 0:
            raise ValueError(f"hold time must be positive, got {hold_time}")
        self.layout = layout
        self.hold_time = hold_time
        self.linear_speed = linear_speed
        self.angular_speed = angular_speed
        self.quit_keys = frozenset({ESCAPE, CTRL_D} | ({"q"} - layout.allowed))
        self._aliases = {
            "up": layout.forward,
            "down": layout.backward,
            "left": layout.left,
            "right": layout.right,
        }
        self._until: dict[str, float] = {}

    @property
    def quit_label(self) -> str:
        """How to quit, for a help line: ``q`` or ``Esc``."""
        return "q" if "q" in self.quit_keys else "Esc"

    def press(self, key: str, now: float) -> KeyAction:
        """A key was pressed at ``now`` (s); what it asks beyond the motion."""
        if key in self.quit_keys:
            return KeyAction.QUIT
        if key == SPACE:
            self.release_all()
            return KeyAction.STOP
        motion = self._aliases.get(key, key.lower())
        if motion in self.layout.allowed:
            self._until[motion] = now + self.hold_time
        return KeyAction.NONE

    def release_all(self) -> None:
        """Forget every held key."""
        self._until.clear()

    def held(self, now: float) -> frozenset[str]:
        """The motion keys held at ``now`` (s)."""
        return frozenset(key for key, until in self._until.items() if now < until - 1e-9)

    def twist(self, now: float) -> Twist2D:
        """The command for the keys held at ``now`` (s)."""
        return twist_from_keys(
            self.held(now),
            self.layout,
            linear_speed=self.linear_speed,
            angular_speed=self.angular_speed,
        )


class _Hangup(SystemExit):
    """Raised from SIGTERM/SIGHUP so that every ``finally`` runs (exit 128 + signal)."""


class RawTerminal:
    """A terminal in character-at-a-time mode while the ``with`` block runs.

    Args:
        fd: the terminal's file descriptor (stdin's).

    Raises:
        termios.error: if ``fd`` is not a terminal (check ``os.isatty`` first).
    """

    def __init__(self, fd: int) -> None:
        self.fd = fd
        self._saved: list[Any] | None = None
        self._handlers: dict[int, Any] = {}
        self._decoder = codecs.getincrementaldecoder("utf-8")(errors="replace")

    def __enter__(self) -> RawTerminal:
        self._saved = termios.tcgetattr(self.fd)
        if threading.current_thread() is threading.main_thread():  # only it may set handlers
            for signum in (signal.SIGTERM, signal.SIGHUP):
                self._handlers[signum] = signal.signal(signum, _raise_exit)
        tty.setcbreak(self.fd, termios.TCSANOW)
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.restore()

    def restore(self) -> None:
        """Put the terminal settings and signal handlers back (idempotent)."""
        if self._saved is not None:
            with contextlib.suppress(termios.error):  # a hung-up terminal needs nothing back
                termios.tcsetattr(self.fd, termios.TCSADRAIN, self._saved)
            self._saved = None
        for signum, handler in self._handlers.items():
            signal.signal(signum, handler)
        self._handlers.clear()

    def read(self, timeout: float) -> str:
        """What was typed, waiting at most ``timeout`` s for the first key ("" if none).

        Raises:
            EOFError: when the terminal is closed.
        """
        ready, _, _ = select.select([self.fd], [], [], max(timeout, 0.0))
        if not ready:
            return ""
        try:
            data = os.read(self.fd, 1024)
        except OSError as exc:  # EIO: the other side of a pseudo-terminal hung up
            raise EOFError("the terminal was closed") from exc
        if not data:
            raise EOFError("the terminal was closed")
        return self._decoder.decode(data)

    def keys(self, timeout: float) -> Iterator[str]:
        """The keys typed within ``timeout`` s (see :func:`split_keys`)."""
        yield from split_keys(self.read(timeout))


def _raise_exit(signum: int, _frame: FrameType | None) -> None:
    raise _Hangup(128 + signum)
