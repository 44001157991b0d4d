"""Keyboard teleoperation (seed §5): the set of pressed keys -> a (linear, angular) command.

Two layouts are known: WASD (QWERTY keyboards) and ZQSD (AZERTY keyboards). Several keys may
be held at once: forward/backward combine with left/right, and opposite keys cancel. The
mapping is a pure function, :func:`twist_from_keys`; :class:`KeyboardTeleop` holds the
pressed set with ``on_press``/``on_release`` semantics, as the seed's pynput listener does.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import NamedTuple

DEFAULT_LINEAR_SPEED = 0.25
"""Teleop forward speed (m/s), the seed's ``linear_speed`` default."""
DEFAULT_ANGULAR_SPEED = 1.2
"""Teleop turn rate (rad/s), the seed's ``angular_speed`` default."""


class Twist2D(NamedTuple):
    """A planar velocity command: ``linear`` (m/s, forward) and ``angular`` (rad/s, CCW)."""

    linear: float
    angular: float


class KeyLayout(NamedTuple):
    """The four keys of a layout: forward, backward, rotate left, rotate right."""

    forward: str
    backward: str
    left: str
    right: str

    @property
    def allowed(self) -> frozenset[str]:
        """The keys this layout reacts to."""
        return frozenset(self)


LAYOUTS: dict[str, KeyLayout] = {
    "wasd": KeyLayout(forward="w", backward="s", left="a", right="d"),
    "zqsd": KeyLayout(forward="z", backward="s", left="q", right="d"),
}
"""Known layouts by name: ``wasd`` (QWERTY) and ``zqsd`` (AZERTY)."""


def layout_named(name: str) -> KeyLayout:
    """The layout called ``name`` (case-insensitive).

    Raises:
        ValueError: for an unknown name; the message lists the known ones.
    """
    try:
        return LAYOUTS[name.lower()]
    except KeyError:
        known = ", ".join(sorted(LAYOUTS))
        raise ValueError(f"unknown keyboard layout '{name}'; known layouts: {known}") from None


def twist_from_keys(
    pressed: Iterable[str],
    layout: KeyLayout = LAYOUTS["wasd"],
    *,
    linear_speed: float = DEFAULT_LINEAR_SPEED,
    angular_speed: float = DEFAULT_ANGULAR_SPEED,
) -> Twist2D:
    """The command for the keys held down: each axis is +speed, -speed or 0 (opposites cancel).

    Keys are matched case-insensitively; keys outside the layout are ignored.
    """
    keys = {key.lower() for key in pressed}
    forward = (layout.forward in keys) - (layout.backward in keys)
    turn = (layout.left in keys) - (layout.right in keys)
    return Twist2D(linear=forward * linear_speed, angular=turn * angular_speed)


class KeyboardTeleop:
    """The pressed-key set of a keyboard listener and the command it gives.

    Args:
        layout: the layout, or its name (``"wasd"`` or ``"zqsd"``).
        linear_speed: forward speed while a forward/backward key is held (m/s).
        angular_speed: turn rate while a left/right key is held (rad/s).

    Raises:
        ValueError: for an unknown layout name.
    """

    def __init__(
        self,
        layout: KeyLayout | str = "wasd",
        *,
        linear_speed: float = DEFAULT_LINEAR_SPEED,
        angular_speed: float = DEFAULT_ANGULAR_SPEED,
    ) -> None:
        self.layout = layout_named(layout) if isinstance(layout, str) else layout
        self.allowed = self.layout.allowed
        self.linear_speed = linear_speed
        self.angular_speed = angular_speed
        self.pressed: set[str] = set()

    def on_press(self, key: str) -> Twist2D:
        """Note ``key`` as held (if it belongs to the layout) and return the new command."""
        char = key.lower()
        if char in self.allowed:
            self.pressed.add(char)
        return self.twist()

    def on_release(self, key: str) -> Twist2D:
        """Note ``key`` as released and return the new command."""
        self.pressed.discard(key.lower())
        return self.twist()

    def release_all(self) -> Twist2D:
        """Forget every held key (focus lost, listener stopped): the command becomes zero."""
        self.pressed.clear()
        return self.twist()

    def twist(self) -> Twist2D:
        """The command for the keys held now."""
        return twist_from_keys(
            self.pressed,
            self.layout,
            linear_speed=self.linear_speed,
            angular_speed=self.angular_speed,
        )
