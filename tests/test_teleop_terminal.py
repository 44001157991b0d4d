"""``baobab teleop``: the session on sim time, the real-time loop, and the real terminal UI.

The session and the loop are driven with scripted keys and a scripted clock (deterministic).
The terminal UI runs as a subprocess in a pseudo-terminal: keys are written to the master side
and the screen is read back; every wait reads with a ``select`` timeout until the screen shows
what is awaited (generous bounds: the UI runs at real time and starts in a few seconds).
"""

from __future__ import annotations

import fcntl
import io
import os
import re
import select
import signal
import struct
import subprocess
import sys
import termios
import threading
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import pytest

from baobab.missions.cli.command_line import main
from baobab.missions.cli.teleop_command import TICK, TeleopSession, TeleopStatus, drive, help_text
from baobab.robots.catalog import ROBOTS
from baobab.robots.diff_drive.teleop import LAYOUTS
from baobab.robots.diff_drive.teleop_terminal import RawTerminal, TerminalKeys
from baobab.sim.tasks import TaskStatus
from baobab.sim.world import load_world

STATUS = re.compile(
    r"\s*(?P<t>\d+\.\d)s x(?P<x>[+-]\d+\.\d\d) y(?P<y>[+-]\d+\.\d\d) yaw(?P<yaw>[+-]\d+)°"
    r" v(?P<v>[+-]\d+\.\d\d) w(?P<w>[+-]\d+\.\d\d) \| scaling (?P<scaling>\d\.\d\d)"
    r" \| (?P<nearest>\S+) (?P<clearance>-?\d+\.\d\d) m \| keys (?P<keys>\S+)"
)
STARTUP = 60.0
"""s: bound on the UI's first status line (imports, model build; numba caches when cold)."""
REACTION = 20.0
"""s: bound on the screen showing the effect of a key (it takes well under a second)."""
COLUMNS = 110
"""The pseudo-terminal's width: the one-line banner (120 characters in walls) does not fit."""


def _session(hold: float = 0.4) -> TeleopSession:
    return TeleopSession(load_world("walls"), TerminalKeys(LAYOUTS["wasd"], hold_time=hold))


def test_a_session_drives_with_held_keys_and_assisted_teleop_stops_it_at_the_wall() -> None:
    session = _session()
    assert session.handle.status is TaskStatus.RUNNING
    for _ in range(20):  # a key repeat every 0.1 s for 2 s
        session.press("w")
        session.advance(0.1)
    status = session.status()
    assert status.linear == pytest.approx(0.22, abs=0.005) and status.keys == "w"
    assert 0.35 < status.x < 0.45 and status.nearest == "wall_east"
    assert status.clearance == pytest.approx(1.15 - 0.105 - status.x, abs=1e-6)
    session.advance(1.0)  # no repeat: the hold ran out, the robot stops by itself
    assert session.status().linear == pytest.approx(0.0, abs=0.005)
    for _ in range(70):  # 7 s of "w" at the wall: assisted teleop stops it before
        session.press("w")
        session.advance(0.1)
    status = session.status()
    assert status.scaling == 0.0 and status.keys == "w"
    assert 0.05 <= status.clearance < 0.08
    assert session.press(" ").value == "stop" and session.status().keys == ""
    outcome = session.finish()
    assert outcome is not None and outcome.status is TaskStatus.SUCCEEDED
    assert session.robot.base.target == (0.0, 0.0)


def test_a_waffle_session_measures_its_polygon_and_stops_it_short_of_the_wall() -> None:
    waffle = ROBOTS["turtlebot3_waffle"]
    speeds = waffle.tuning.teleop_speeds
    keys = TerminalKeys(LAYOUTS["wasd"], linear_speed=speeds[0], angular_speed=speeds[1])
    session = TeleopSession(load_world("walls"), keys, waffle)
    status = session.status()  # the front edge, 0.0765 m ahead of base_link
    assert status.nearest == "wall_east"
    assert status.clearance == pytest.approx(1.15 - 0.0765 - status.x, abs=1e-6)
    for _ in range(100):  # 10 s of "w": assisted teleop stops it before the wall
        session.press("w")
        session.advance(0.1)
    status = session.status()
    assert status.scaling == 0.0 and 0.05 <= status.clearance < 0.1
    outcome = session.finish()
    assert outcome is not None and outcome.status is TaskStatus.SUCCEEDED


def test_the_status_line_fits_the_terminal() -> None:
    status = TeleopStatus(12.34, 0.5, -0.0001, -0.001, -1e-9, 0.25, "wall_east", 0.3123, 0.4, "aw")
    line = status.line(120)
    assert line == (
        " 12.3s x+0.50 y+0.00 yaw+0° v+0.00 w+0.25 | scaling 0.40 | wall_east 0.31 m | keys aw"
    )
    assert STATUS.fullmatch(line)
    assert len(status.line(40)) == 39


@pytest.mark.parametrize("width", [COLUMNS, 80, 40])
def test_the_banner_wraps_at_spaces_to_fit_the_terminal(width: int) -> None:
    keys = TerminalKeys(LAYOUTS["wasd"])
    whole = help_text(keys, "walls", 200)
    assert "\n" not in whole and len(whole) > COLUMNS
    lines = help_text(keys, "walls", width).split("\n")
    assert len(lines) > 1 and max(map(len, lines)) < width
    assert " ".join(lines) == whole  # broken at spaces only


@dataclass
class _ScriptedTerminal:
    """Keys at given wall-clock times; waiting advances the scripted clock."""

    script: list[tuple[float, str]]
    now: float = 100.0

    def clock(self) -> float:
        return self.now

    def keys(self, timeout: float) -> Iterator[str]:
        due = self.now + max(timeout, 0.0)
        if self.script and self.script[0][0] <= due:
            at, key = self.script.pop(0)
            self.now = max(self.now, at)
            yield key
        else:
            self.now = due


def test_the_loop_keeps_sim_time_with_the_wall_clock_and_quits_on_q() -> None:
    session = _session()
    terminal = _ScriptedTerminal([(100.0 + 0.1 * k, "w") for k in range(1, 11)] + [(103.0, "q")])
    out = io.StringIO()
    drive(session, terminal, out, clock=terminal.clock, width=120)  # type: ignore[arg-type]
    assert session.time == pytest.approx(3.0, abs=TICK + 1e-9)
    lines = [line for line in out.getvalue().split("\r") if line]
    assert len(lines) == pytest.approx(30, abs=1)  # 10 Hz
    times = [float(STATUS.match(line.removesuffix("\x1b[K"))["t"]) for line in lines]  # type: ignore[index]
    assert times == sorted(times)
    assert session.status().x > 0.2


# --- the real terminal UI in a pseudo-terminal ------------------------------------------------


class Screen:
    """The master side of a pseudo-terminal running ``baobab teleop``."""

    def __init__(self, *args: str) -> None:
        self.master, self.slave = os.openpty()
        fcntl.ioctl(self.slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, COLUMNS, 0, 0))
        self.settings = termios.tcgetattr(self.slave)
        command = "from baobab.missions.cli.command_line import main; raise SystemExit(main())"
        env = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "LINES")}
        self.process = subprocess.Popen(
            [sys.executable, "-c", command, "teleop", "--world", "walls", *args],
            stdin=self.slave,
            stdout=self.slave,
            stderr=self.slave,
            start_new_session=True,
            env=env,  # the terminal's own size, not one a parent shell exported
        )
        self.text = ""

    def read(self, timeout: float) -> bool:
        """Read what the program wrote within ``timeout`` s; False when nothing came."""
        ready, _, _ = select.select([self.master], [], [], timeout)
        if not ready:
            return False
        self.text += os.read(self.master, 65536).decode("utf-8", errors="replace")
        return True

    def status(self) -> dict[str, str] | None:
        """The last complete status line on screen (each ends by clearing the line's rest)."""
        for line in reversed(self.text.split("\r")):
            found = STATUS.fullmatch(line.partition("\x1b[K")[0]) if "\x1b[K" in line else None
            if found:
                return found.groupdict()
        return None

    def wait_for(self, what: Callable[[dict[str, str]], bool], bound: float) -> dict[str, str]:
        """Read until the status line satisfies ``what``; fails after ``bound`` s of silence."""
        while True:
            status = self.status()
            if status is not None and what(status):
                return status
            assert self.read(bound), f"nothing new on screen for {bound} s:\n{self.text[-500:]}"

    def type(self, keys: str) -> None:
        os.write(self.master, keys.encode())

    def finish(self, bound: float) -> int:
        """Read until the program exits; its exit code."""
        while self.process.poll() is None:
            self.read(0.1)
        code = self.process.wait(bound)
        while self.read(0.0):
            pass
        return code

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        os.close(self.master)
        os.close(self.slave)


def test_the_terminal_ui_drives_stops_and_quits() -> None:
    screen = Screen("--hold", "30")  # only space stops the robot within the test
    try:
        _drive_stop_quit(screen)
    finally:
        screen.close()


def _drive_stop_quit(screen: Screen) -> None:
    first = screen.wait_for(lambda s: True, STARTUP)
    banner = screen.text.partition("\x1b[?25l")[0].split("\r\n")[:-1]
    whole = help_text(TerminalKeys(LAYOUTS["wasd"], hold_time=30.0), "walls", 200)
    assert " ".join(banner) == whole and max(map(len, banner)) < COLUMNS
    assert (first["x"], first["keys"]) == ("+0.00", "-")
    assert termios.tcgetattr(screen.slave)[3] & termios.ECHO == 0  # raw while it runs
    screen.type("w")
    moving = screen.wait_for(lambda s: float(s["x"]) > 0.1, REACTION)
    assert moving["keys"] == "w" and float(moving["v"]) > 0.2 and moving["scaling"] == "1.00"
    screen.type(" ")
    stopped = screen.wait_for(lambda s: s["keys"] == "-" and s["v"] == "+0.00", REACTION)
    assert float(stopped["t"]) - float(moving["t"]) < 5.0  # space, not the 30 s hold
    later = screen.wait_for(lambda s: float(s["t"]) > float(stopped["t"]) + 1.0, REACTION)
    assert later["x"] == stopped["x"]  # it stays stopped
    screen.type("q")
    assert screen.finish(REACTION) == 0
    assert screen.text.rstrip().splitlines()[-1].startswith("baobab teleop: stopped at x +0.")
    assert "assisted teleop SUCCEEDED" in screen.text
    assert "\x1b[?25h" in screen.text  # the cursor is shown again
    assert termios.tcgetattr(screen.slave) == screen.settings  # the terminal is restored


def test_the_raw_terminal_reads_keys_and_is_restored_on_every_way_out() -> None:
    master, slave = os.openpty()
    try:
        settings = termios.tcgetattr(slave)
        with RawTerminal(slave) as terminal:
            assert termios.tcgetattr(slave)[3] & (termios.ECHO | termios.ICANON) == 0
            assert terminal.read(0.0) == ""
            os.write(master, "w\x1b[Aé".encode())
            assert list(terminal.keys(REACTION)) == ["w", "up", "é"]
        assert termios.tcgetattr(slave) == settings
        with pytest.raises(KeyboardInterrupt), RawTerminal(slave):
            raise KeyboardInterrupt  # what SIGINT raises
        assert termios.tcgetattr(slave) == settings
        if threading.current_thread() is threading.main_thread():
            before = signal.getsignal(signal.SIGTERM)
            with pytest.raises(SystemExit) as exit_, RawTerminal(slave):
                handler = signal.getsignal(signal.SIGTERM)
                assert callable(handler)
                handler(signal.SIGTERM, None)  # what SIGTERM runs
            assert exit_.value.code == 128 + signal.SIGTERM
            assert signal.getsignal(signal.SIGTERM) == before
            assert termios.tcgetattr(slave) == settings
        with pytest.raises(EOFError), RawTerminal(slave) as terminal:
            os.close(master)  # hang up: reading ends, leaving needs no terminal
            master = -1
            terminal.read(REACTION)
    finally:
        for fd in (master, slave):
            if fd >= 0:
                os.close(fd)


def test_without_a_terminal_it_says_so_and_exits_2(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(sys, "stdin", io.StringIO("w"))
    assert main(["teleop", "--world", "walls"]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err == "baobab teleop: needs an interactive terminal (stdin is not a TTY)\n"
    assert main(["teleop", "--world", "walls", "--hold", "0"]) == 2  # argparse refuses it
    assert "must be positive" in capsys.readouterr().err
