"""Keyboard teleop (seed §5): pressed keys -> (linear, angular), both layouts, as a table."""

from __future__ import annotations

import pytest

from baobab.robots.turtlebot3 import LAYOUTS, KeyboardTeleop, Twist2D, layout_named, twist_from_keys

V, W = 0.25, 1.2

TABLE = [
    # (WASD keys, ZQSD keys, expected command)
    ("", "", (0.0, 0.0)),
    ("w", "z", (V, 0.0)),
    ("s", "s", (-V, 0.0)),
    ("a", "q", (0.0, W)),
    ("d", "d", (0.0, -W)),
    ("wa", "zq", (V, W)),
    ("wd", "zd", (V, -W)),
    ("sa", "sq", (-V, W)),
    ("sd", "sd", (-V, -W)),
    ("ws", "zs", (0.0, 0.0)),  # opposite keys cancel
    ("ad", "qd", (0.0, 0.0)),
    ("wsa", "zsq", (0.0, W)),
    ("wad", "zqd", (V, 0.0)),
    ("wasd", "zqsd", (0.0, 0.0)),
]


@pytest.mark.parametrize(("wasd", "zqsd", "expected"), TABLE)
def test_both_layouts(wasd: str, zqsd: str, expected: tuple[float, float]) -> None:
    assert twist_from_keys(set(wasd), LAYOUTS["wasd"]) == expected
    assert twist_from_keys(set(zqsd), LAYOUTS["zqsd"]) == expected


def test_keys_of_the_other_layout_and_strangers_are_ignored() -> None:
    assert twist_from_keys({"z", "q", "x", "1"}, LAYOUTS["wasd"]) == (0.0, 0.0)
    assert twist_from_keys({"w", "a"}, LAYOUTS["zqsd"]) == (0.0, 0.0)
    assert twist_from_keys({"W", "A"}) == (V, W)  # caps lock does not matter


def test_speeds_are_parameters() -> None:
    command = twist_from_keys({"w", "d"}, linear_speed=0.1, angular_speed=0.5)
    assert command == Twist2D(linear=0.1, angular=-0.5)


def test_press_and_release_track_the_held_keys() -> None:
    teleop = KeyboardTeleop("zqsd")
    assert teleop.allowed == frozenset("zqsd")
    assert teleop.on_press("z") == (V, 0.0)
    assert teleop.on_press("q") == (V, W)
    assert teleop.on_press("d") == (V, 0.0)  # left and right held: they cancel
    assert teleop.on_press("p") == (V, 0.0)  # not a layout key
    assert teleop.pressed == {"z", "q", "d"}
    assert teleop.on_release("q") == (V, -W)
    assert teleop.on_release("z") == (0.0, -W)
    assert teleop.on_release("z") == (0.0, -W)  # releasing twice is harmless
    assert teleop.release_all() == (0.0, 0.0)
    assert teleop.pressed == set()


def test_unknown_layout_is_named_in_the_error() -> None:
    assert layout_named("WASD") == LAYOUTS["wasd"]
    with pytest.raises(ValueError, match="unknown keyboard layout 'dvorak'; known layouts: wasd"):
        KeyboardTeleop("dvorak")
