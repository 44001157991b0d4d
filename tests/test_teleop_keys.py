"""Keyboard teleop (seed §5): pressed keys -> (linear, angular), both layouts, as a table; the
terminal rules (a press holds for a while, space stops, q quits) as a tick table."""

from __future__ import annotations

import pytest

from baobab.robots.diff_drive import LAYOUTS, KeyboardTeleop, Twist2D, layout_named, twist_from_keys
from baobab.robots.diff_drive.teleop_terminal import (
    CTRL_D,
    ESCAPE,
    KeyAction,
    TerminalKeys,
    split_keys,
)

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


# --- in a terminal (no key releases): a press holds for a while, space stops, q quits ------

HOLD = 0.4

TERMINAL_TICKS = [
    # (time s, keys pressed then, action expected, command expected just after)
    (0.0, "", "none", (0.0, 0.0)),
    (0.1, "w", "none", (V, 0.0)),  # held until 0.5 s
    (0.3, "", "none", (V, 0.0)),
    (0.5, "", "none", (0.0, 0.0)),  # no repeat came: released
    (1.0, "w", "none", (V, 0.0)),
    (1.3, "w", "none", (V, 0.0)),  # a terminal's key repeat renews the hold
    (1.6, "a", "none", (V, W)),  # w until 1.7 s, a until 2.0 s: an arc
    (1.7, "", "none", (0.0, W)),
    (1.8, "d", "none", (0.0, 0.0)),  # a and d both held: they cancel
    (2.0, "", "none", (0.0, -W)),
    (2.1, "ws", "none", (0.0, -W)),  # opposites cancel
    (2.2, " ", "stop", (0.0, 0.0)),  # space releases everything at once
    (2.3, "W", "none", (V, 0.0)),  # caps lock does not matter
    (2.4, "x", "none", (V, 0.0)),  # strangers are ignored
    (2.5, "q", "quit", (V, 0.0)),
]


def test_terminal_key_rules_as_a_tick_table() -> None:
    keys = TerminalKeys(LAYOUTS["wasd"], hold_time=HOLD)
    for now, pressed, action, expected in TERMINAL_TICKS:
        actions = {keys.press(key, now).value for key in pressed} or {"none"}
        assert actions == {action}, now
        assert keys.twist(now) == pytest.approx(expected), now


def test_terminal_keys_in_the_zqsd_layout_and_arrows() -> None:
    keys = TerminalKeys(LAYOUTS["zqsd"])
    assert keys.press("q", 0.0) is KeyAction.NONE  # q turns left here
    assert keys.twist(0.0) == (0.0, W)
    assert keys.quit_label == "Esc"
    assert keys.press(ESCAPE, 0.1) is KeyAction.QUIT
    assert keys.press(CTRL_D, 0.1) is KeyAction.QUIT
    keys.release_all()
    for arrow, expected in [("up", (V, 0.0)), ("down", (-V, 0.0)), ("right", (0.0, -W))]:
        keys.release_all()
        keys.press(arrow, 1.0)
        assert keys.twist(1.0) == expected
    assert TerminalKeys(LAYOUTS["wasd"]).quit_label == "q"
    with pytest.raises(ValueError, match="hold time must be positive"):
        TerminalKeys(LAYOUTS["wasd"], hold_time=0.0)


def test_terminal_bytes_split_into_keys() -> None:
    assert split_keys("wa d") == ["w", "a", " ", "d"]
    assert split_keys("\x1b[A\x1b[B\x1bOC\x1b[D") == ["up", "down", "right", "left"]
    assert split_keys("\x1b") == [ESCAPE]
    assert split_keys("\x1b[1;5Aw") == ["up", "w"]  # Ctrl+Up: the arrow, modifiers dropped
    assert split_keys("\x1b[15~") == ["unknown"]  # F5
