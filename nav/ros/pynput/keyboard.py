"""``pynput.keyboard``: key listeners fed by the run's virtual keyboard.

A teleop node starts a ``keyboard.Listener(on_press=..., on_release=...)``; under ``baobab ros
run`` there is no physical keyboard, so the run presses and releases keys at given sim times
(:class:`VirtualKeyboard`), and every started listener calls its callbacks with them, in its own
thread, as pynput does. A callback that returns ``False`` stops its listener; one that raises
stops it too, and the error fails the run with its traceback.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable
from contextvars import ContextVar
from enum import Enum
from typing import Any

from baobab.nav.ros import waiting

__all__ = ["Key", "KeyCode", "Listener", "VirtualKeyboard"]


class KeyCode:
    """A key that types a character (``key.char``)."""

    def __init__(self, vk: int | None = None, char: str | None = None, is_dead: bool = False):
        self.vk = vk
        self.char = char
        self.is_dead = is_dead

    @classmethod
    def from_char(cls, char: str, **kwargs: Any) -> KeyCode:
        """The key typing ``char``."""
        return cls(char=char, **kwargs)

    @classmethod
    def from_vk(cls, vk: int, **kwargs: Any) -> KeyCode:
        """The key with virtual key code ``vk``."""
        return cls(vk=vk, **kwargs)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, KeyCode):
            return NotImplemented
        return (self.char, self.vk) == (other.char, other.vk)

    def __hash__(self) -> int:
        return hash((self.char, self.vk))

    def __repr__(self) -> str:
        return repr(self.char) if self.char is not None else f"<{self.vk}>"


class Key(Enum):
    """Special keys (``Key.space``, ``Key.esc``, the arrows, ...)."""

    alt = KeyCode(vk=0xFFE9)
    backspace = KeyCode(vk=0xFF08)
    ctrl = KeyCode(vk=0xFFE3)
    delete = KeyCode(vk=0xFFFF)
    down = KeyCode(vk=0xFF54)
    end = KeyCode(vk=0xFF57)
    enter = KeyCode(vk=0xFF0D)
    esc = KeyCode(vk=0xFF1B)
    home = KeyCode(vk=0xFF50)
    left = KeyCode(vk=0xFF51)
    right = KeyCode(vk=0xFF53)
    shift = KeyCode(vk=0xFFE1)
    space = KeyCode(vk=0x20, char=" ")
    tab = KeyCode(vk=0xFF09)
    up = KeyCode(vk=0xFF52)


def key_named(name: str) -> Key | KeyCode:
    """``"w"`` -> ``KeyCode(char="w")``; ``"space"``, ``"esc"``, ``"up"`` -> the special key.

    Raises:
        ValueError: a name that is neither one character nor a special key's name.
    """
    if len(name) == 1:
        return KeyCode.from_char(name)
    if name in Key.__members__:
        return Key[name]
    raise ValueError(
        f"unknown key {name!r}: expected one character or one of {', '.join(Key.__members__)}"
    )


Callback = Callable[[Any], Any]


class VirtualKeyboard:
    """The run's keyboard: :meth:`press` and :meth:`release` reach every started listener."""

    def __init__(self) -> None:
        self.listeners: list[Listener] = []

    def press(self, name: str) -> None:
        """Press the key ``name`` (see :func:`key_named`)."""
        key = key_named(name)
        for listener in self.listeners:
            listener._events.append(("press", key))

    def release(self, name: str) -> None:
        """Release the key ``name``."""
        key = key_named(name)
        for listener in self.listeners:
            listener._events.append(("release", key))


_keyboard: ContextVar[VirtualKeyboard | None] = ContextVar("virtual_keyboard", default=None)


def use_keyboard(keyboard: VirtualKeyboard | None) -> None:
    """Make ``keyboard`` the one listeners started in this context hear (None: none)."""
    _keyboard.set(keyboard)


class Listener(threading.Thread):
    """``pynput.keyboard.Listener``: calls ``on_press(key)`` / ``on_release(key)`` for each key
    event of the run's keyboard, in its own thread, until stopped."""

    def __init__(
        self,
        on_press: Callback | None = None,
        on_release: Callback | None = None,
        suppress: bool = False,
        **kwargs: Any,
    ) -> None:
        super().__init__(daemon=True)
        self.on_press = on_press
        self.on_release = on_release
        self._events: deque[tuple[str, Any]] = deque()
        self._stopped = False
        self._keyboard = _keyboard.get()

    @property
    def running(self) -> bool:
        """True between ``start()`` and ``stop()``."""
        return self.is_alive() and not self._stopped

    def start(self) -> None:
        """Start listening to the run's keyboard."""
        if self._keyboard is not None:
            self._keyboard.listeners.append(self)
        super().start()

    def stop(self) -> None:
        """Stop listening (callable from a callback or another thread)."""
        self._stopped = True
        if self._keyboard is not None and self in self._keyboard.listeners:
            self._keyboard.listeners.remove(self)

    def run(self) -> None:
        """Deliver key events until stopped."""
        if self._keyboard is None or not waiting.can_wait():
            return
        while not self._stopped:
            if not self._events:
                waiting.wait(None, lambda: bool(self._events) or self._stopped, what="Listener")
                continue
            kind, key = self._events.popleft()
            callback = self.on_press if kind == "press" else self.on_release
            if callback is not None and callback(key) is False:
                self.stop()

    def wait(self) -> None:
        """Return once the listener is ready (at once)."""

    def __enter__(self) -> Listener:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()
