"""``baobab nav2 SCRIPT.py --world NAME [--robot NAME_OR_PATH] [--start X,Y,YAW] [--seed N]
[--realtime]``.

Runs a Nav2 Simple Commander script as it is (:func:`baobab.nav.script_runner.run_nav2_script`):
its ``BasicNavigator()`` builds the given world with ``--robot`` (a bundled mobile robot or a
robot file; default: the registry's default mobile robot) at ``--start`` (default: the world's
spawn), seeded with ``--seed``, paced to the wall clock with ``--realtime``. The script's output
and exit status pass through unchanged. A mistake in the arguments (an unknown world or robot,
a robot file that cannot be used, a malformed or blocked start pose, a negative seed) exits 2
with one line on standard error before the script runs.
"""

from __future__ import annotations

import argparse
import math
import sys

from baobab.missions.run.exit_codes import EXIT_INVALID
from baobab.robots.footprint import Footprint
from baobab.sim.errors import BaobabError, clip, one_line
from baobab.sim.world import Pose2D, World, load_world


class Nav2ArgumentError(BaobabError):
    """A ``baobab nav2`` argument that cannot be used."""


def configure_nav2(parser: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``baobab nav2``."""
    parser.add_argument("script", metavar="SCRIPT.py", help="a Nav2 Simple Commander script")
    parser.add_argument("--world", required=True, help="a bundled world name or a world YAML file")
    parser.add_argument(
        "--robot",
        metavar="NAME_OR_PATH",
        help="a bundled mobile robot (see baobab list) or a robot YAML file",
    )
    parser.add_argument(
        "--start",
        metavar="X,Y,YAW",
        help="start pose (m, m, rad; default: the world's spawn); --start=-1,2,0 for negatives",
    )
    parser.add_argument("--seed", metavar="N", default="0", help="simulation seed (default 0)")
    parser.add_argument(
        "--realtime", action="store_true", help="pace the simulation to the wall clock"
    )


def nav2_command(args: argparse.Namespace) -> int:
    """Check the arguments, then run the script; its exit status, or 2 for bad arguments."""
    from pathlib import Path

    from baobab.nav.script_runner import check_script, run_nav2_script

    check_script(Path(args.script))  # a ScriptError is located: main() prints it, exits 2
    try:
        world = load_world(args.world)  # a WorldError is located: main() prints it, exits 2
        footprint = robot_footprint(args.robot)  # a RobotFileError too
        start = parse_start(args.start, world, footprint)
        seed = parse_seed(args.seed)
    except Nav2ArgumentError as exc:
        print(one_line(f"baobab nav2: {exc}"), file=sys.stderr)
        return EXIT_INVALID
    defaults = {
        "world": args.world,
        "robot": args.robot,
        "start": start,
        "seed": seed,
        "realtime": args.realtime,
    }
    return run_nav2_script(args.script, navigator_defaults=defaults)


def robot_footprint(robot: str | None) -> Footprint:
    """The footprint of the robot ``--robot`` names (the default mobile robot's without it).

    Raises:
        Nav2ArgumentError: an unknown or fixed robot.
        RobotFileError: a robot file that cannot be used (located).
    """
    from baobab.nav.navigator_robot import NavigatorSetupError, navigator_robot

    try:
        return navigator_robot(robot).mobile_facts.footprint
    except NavigatorSetupError as exc:
        raise Nav2ArgumentError(f"--robot: {exc}") from None


def parse_start(text: str | None, world: World, footprint: Footprint) -> Pose2D | None:
    """The pose of ``--start X,Y[,YAW]`` (m, m, rad), checked to be free for ``footprint`` in
    ``world``.

    Without ``--start`` (None), the world's default spawn is checked instead.

    Raises:
        Nav2ArgumentError: not two or three finite numbers, or a pose the robot cannot stand on.
    """
    if text is None:
        _check_free(world, world.spawn, footprint, "the default spawn")
        return None
    parts = text.split(",")
    try:
        values = [float(part) for part in parts]
    except ValueError:
        values = []
    if len(values) not in (2, 3) or not all(math.isfinite(value) for value in values):
        raise Nav2ArgumentError(f"--start: expected X,Y,YAW (m, m, rad), got '{clip(text)}'")
    pose = Pose2D(x=values[0], y=values[1], yaw=values[2] if len(values) == 3 else 0.0)
    _check_free(world, pose, footprint, "--start")
    return pose


def _check_free(world: World, pose: Pose2D, footprint: Footprint, what: str) -> None:
    from baobab.nav.navigator_robot import NavigatorSetupError, check_free

    try:
        check_free(world, pose, footprint, what=what)
    except NavigatorSetupError as exc:
        raise Nav2ArgumentError(str(exc)) from None


def parse_seed(text: str) -> int:
    """The seed of ``--seed N``.

    Raises:
        Nav2ArgumentError: not a non-negative whole number.
    """
    try:
        seed = int(text)
    except ValueError:
        seed = -1
    if seed < 0:
        raise Nav2ArgumentError(f"--seed: expected a non-negative whole number, got '{clip(text)}'")
    return seed
