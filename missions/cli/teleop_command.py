"""``baobab teleop --world NAME [--robot NAME_OR_PATH] [--start X,Y,YAW]``: drive a mobile robot
with the keyboard, assisted teleop on.

The robot (``--robot``: a bundled mobile robot or a robot file; the registry's default mobile
robot without it) starts at ``--start`` or the world's spawn (on a map without one, its origin)
with its navigation server running one assisted teleop session without a time limit, so the
collision projection slows it down near obstacles and stops it before them
(:class:`~baobab.nav.behaviors.AssistedTeleop`). Keys follow the keyboard teleop's mapping
(:mod:`baobab.robots.diff_drive.teleop`: WASD or ZQSD, the seed's 0.25 m/s and 1.2 rad/s within
the robot's limits) with the terminal rules of :mod:`baobab.robots.diff_drive.teleop_terminal`
(a press holds for 0.4 s, space stops, ``q`` quits). The simulation is paced to the wall clock,
the one place where that is right, and a
status line shows the pose, the nearest obstacle and the scaling assisted teleop applies.

:class:`TeleopSession` is the terminal-free part (keys in, sim advanced, status out);
:func:`drive` is the real-time loop over a :class:`RawTerminal`.
"""

from __future__ import annotations

import argparse
import math
import shutil
import sys
import textwrap
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, TextIO

from baobab.missions.cli.arguments import add_start, start_pose
from baobab.missions.run.exit_codes import EXIT_INVALID, EXIT_OK
from baobab.robots.catalog import RobotInfo, default_mobile_robot
from baobab.robots.diff_drive.teleop import LAYOUTS, layout_named
from baobab.robots.diff_drive.teleop_terminal import (
    DEFAULT_HOLD_TIME,
    KeyAction,
    RawTerminal,
    TerminalKeys,
)
from baobab.sim.tasks import TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D, World, load_world

if TYPE_CHECKING:
    from baobab.nav.server import NavigationServer

TICK = 0.05
"""Sim time (s) advanced per loop turn; also the resolution of key holds."""
STATUS_PERIOD = 0.1
"""How often (s) the status line is redrawn."""
MAX_LAG = 0.25
"""A loop further behind the wall clock than this (s) starts counting afresh."""
PREEMPT_WAIT = 1.0
"""How long (s of sim time) ending the session may take (one 10 Hz cycle does it)."""


@dataclass(frozen=True)
class TeleopStatus:
    """What the status line shows: sim time (s), pose (m, rad), body twist (m/s, rad/s), the
    nearest obstacle and its distance from the footprint (m), the scaling assisted teleop
    applies, and the motion keys held."""

    time: float
    x: float
    y: float
    yaw: float
    linear: float
    angular: float
    nearest: str
    clearance: float
    scaling: float
    keys: str

    def line(self, width: int = 80) -> str:
        """One line of at most ``width - 1`` characters."""
        yaw = _signed(math.degrees(self.yaw), 0)
        text = (
            f"{self.time:5.1f}s x{_signed(self.x)} y{_signed(self.y)} yaw{yaw}°"
            f" v{_signed(self.linear)} w{_signed(self.angular)} | scaling {self.scaling:.2f}"
            f" | {self.nearest} {self.clearance:.2f} m | keys {self.keys or '-'}"
        )
        return text[: max(width - 1, 20)]


class TeleopSession:
    """A mobile robot in ``world`` driven by key presses through assisted teleop (no terminal).

    Args:
        world: where to drive.
        keys: the key rules (layout, hold time, speeds).
        robot: the robot (default: the registry's default mobile robot).
        start: where the robot starts (m, rad); default: the world's spawn.
    """

    def __init__(
        self,
        world: World,
        keys: TerminalKeys,
        robot: RobotInfo | None = None,
        start: Pose2D | None = None,
    ) -> None:
        from baobab.nav.robot_params import navigation_params  # the navigation stack loads slowly
        from baobab.nav.server import build_navigation

        self.world = world
        self.keys = keys
        self.info = robot or default_mobile_robot()
        self.sim, self.robot = self.info.build_sim(world, start)
        self.server: NavigationServer = build_navigation(
            self.sim,
            self.robot.base,
            self.robot.lidar,
            world,
            params=navigation_params(self.info),
        )
        self.handle = self.server.assisted_teleop(0.0)

    @property
    def time(self) -> float:
        """Sim time (s)."""
        return self.sim.time

    def press(self, key: str) -> KeyAction:
        """A key was pressed now; space also stops the command at once."""
        action = self.keys.press(key, self.sim.time)
        self._command()
        return action

    def advance(self, duration: float) -> None:
        """Run ``duration`` s of sim time in :data:`TICK` steps, the held keys driving."""
        steps = max(round(duration / TICK), 1)
        for _ in range(steps):
            self._command()
            self.sim.step_for(TICK)

    def status(self) -> TeleopStatus:
        """The robot now."""
        base = self.robot.base
        pose = base.pose()
        linear, angular = base.body_velocity()
        name, clearance = self.robot.facts.footprint.clearance_in(self.world, pose)
        scaling = self.handle.feedback.get("scaling", 1.0)
        return TeleopStatus(
            time=self.sim.time,
            x=pose.x,
            y=pose.y,
            yaw=pose.yaw,
            linear=linear,
            angular=angular,
            nearest=name,
            clearance=clearance,
            scaling=float(scaling),
            keys="".join(sorted(self.keys.held(self.sim.time))),
        )

    def finish(self) -> TaskOutcome | None:
        """End assisted teleop (preempt: SUCCEEDED) and let the robot stop."""
        self.keys.release_all()
        self.server.preempt_teleop()
        end = self.sim.time + PREEMPT_WAIT
        while self.handle.status is TaskStatus.RUNNING and self.sim.time < end - 1e-9:
            self.advance(TICK)
        self.server.close()
        return self.handle.outcome

    def _command(self) -> None:
        self.server.teleop_command(*self.keys.twist(self.sim.time))


def drive(
    session: TeleopSession,
    terminal: RawTerminal,
    out: TextIO,
    *,
    clock: Callable[[], float] = time.monotonic,
    width: int = 80,
) -> None:
    """Run ``session`` at real time, reading keys from ``terminal``, until a quit key.

    Each turn waits for the wall clock to reach the next tick, handling keys as they come,
    then advances the sim one tick; the status line is redrawn every :data:`STATUS_PERIOD`.
    A terminal that hangs up ends the loop like a quit key.
    """
    wall_origin, sim_origin = clock(), session.time
    next_status = session.time
    while True:
        deadline = wall_origin + (session.time + TICK - sim_origin)
        while True:
            try:
                keys = list(terminal.keys(deadline - clock()))
            except EOFError:
                return
            if any(session.press(key) is KeyAction.QUIT for key in keys):
                return
            if clock() >= deadline:
                break
        session.advance(TICK)
        if clock() - (wall_origin + session.time - sim_origin) > MAX_LAG:
            wall_origin, sim_origin = clock(), session.time
        if session.time >= next_status - 1e-9:
            next_status += STATUS_PERIOD
            out.write("\r" + session.status().line(width) + "\x1b[K")
            out.flush()


def help_text(keys: TerminalKeys, world: str, width: int = 80) -> str:
    """The keys, for the first lines on screen, wrapped at spaces to fit ``width`` columns.

    Each line has at most ``width - 1`` characters, as the status line, so that no terminal
    wraps it again (a word longer than that, such as a long world path, is cut).
    """
    layout = keys.layout
    text = (
        f"baobab teleop: {world}, assisted teleop on. {layout.forward}/{layout.backward} "
        f"forward/back, {layout.left}/{layout.right} turn (or arrows; a press holds "
        f"{keys.hold_time:g} s), space stop, {keys.quit_label} quit"
    )
    return "\n".join(textwrap.wrap(text, width=max(width - 1, 20), break_on_hyphens=False))


def configure_teleop(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``baobab teleop``."""
    parser.add_argument(
        "--world",
        required=True,
        help="a bundled world name, a world YAML file or a map_server map YAML",
    )
    add_start(parser)
    parser.add_argument(
        "--robot",
        metavar="NAME_OR_PATH",
        help="a bundled mobile robot (see baobab list) or a robot YAML file",
    )
    parser.add_argument(
        "--layout",
        choices=sorted(LAYOUTS),
        default="wasd",
        help="wasd (QWERTY keyboards) or zqsd (AZERTY; Esc quits)",
    )
    parser.add_argument(
        "--hold",
        type=_positive_seconds,
        default=DEFAULT_HOLD_TIME,
        metavar="SECONDS",
        help=f"how long one key press keeps moving the robot (default {DEFAULT_HOLD_TIME:g})",
    )


def _positive_seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number of seconds: '{text}'") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be positive, got {text}")
    return value


def teleop_command(args: argparse.Namespace) -> int:
    """The ``baobab teleop`` handler: 0 after quitting, 2 without a terminal.

    Raises:
        WorldError: for an unknown world (the CLI prints it and exits 2).
        RobotFileError: a robot file that cannot be used (exit 2).
        NavigatorSetupError: an unknown or fixed robot (exit 2).
        BaobabError: a malformed start, or one not free for the robot (exit 2).
    """
    from baobab.nav.navigator_robot import navigator_robot

    world = load_world(args.world)
    robot = navigator_robot(args.robot)
    start = start_pose(args.start, world, robot.mobile_facts.footprint)
    stdin = sys.stdin
    if stdin is None or not stdin.isatty():
        print("baobab teleop: needs an interactive terminal (stdin is not a TTY)", file=sys.stderr)
        return EXIT_INVALID
    linear, angular = robot.tuning.teleop_speeds
    keys = TerminalKeys(
        layout_named(args.layout), hold_time=args.hold, linear_speed=linear, angular_speed=angular
    )
    session = TeleopSession(world, keys, robot, start)
    out = sys.stdout
    width = _terminal_width()
    out.write(help_text(keys, world.name, width) + "\n\x1b[?25l")
    out.flush()
    try:
        with RawTerminal(stdin.fileno()) as terminal:
            drive(session, terminal, out, width=width)
    finally:
        out.write("\x1b[?25h\n")
        out.flush()
    outcome = session.finish()
    pose = session.robot.base.pose()
    result = "?" if outcome is None else outcome.status.value
    print(
        f"baobab teleop: stopped at x {pose.x:+.2f} m, y {pose.y:+.2f} m after "
        f"{session.time:.1f} s; assisted teleop {result}"
    )
    return EXIT_OK


def _signed(value: float, digits: int = 2) -> str:
    """``value`` with its sign, never ``-0.00``."""
    return f"{round(value, digits) + 0.0:+.{digits}f}"


def _terminal_width() -> int:
    """Columns of the terminal (``COLUMNS`` when set, else the size stdout's terminal says;
    80 when neither says), at least 20."""
    return max(shutil.get_terminal_size((80, 24)).columns, 20)
