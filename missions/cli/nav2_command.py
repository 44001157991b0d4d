"""``baobab nav2 SCRIPT.py --world NAME [--robot NAME_OR_PATH] [--start X,Y,YAW] [--seed N]
[--realtime]``.

Runs a Nav2 Simple Commander script as it is (:func:`baobab.nav.script_runner.run_nav2_script`):
its ``BasicNavigator()`` builds the given world (a bundled name, a world file or a map_server
map YAML) with ``--robot`` (a bundled mobile robot or a robot file; default: the registry's
default mobile robot) at ``--start`` (default: the world's spawn; on a map without one, the map
origin), seeded with ``--seed``, paced to the wall clock with ``--realtime``. The script's output
and exit status pass through unchanged. A mistake in the arguments (an unknown world or robot,
a robot file that cannot be used, a malformed or blocked start pose, a negative seed) exits 2
with one line on standard error before the script runs.
"""

from __future__ import annotations

import argparse
import sys

from baobab.missions.cli.arguments import add_start, robot_footprint, start_pose
from baobab.missions.run.exit_codes import EXIT_INVALID
from baobab.sim.errors import BaobabError, clip, one_line
from baobab.sim.world import load_world


class Nav2ArgumentError(BaobabError):
    """A ``baobab nav2`` argument that cannot be used."""


def configure_nav2(parser: argparse.ArgumentParser) -> None:
    """Declare the arguments of ``baobab nav2``."""
    parser.add_argument("script", metavar="SCRIPT.py", help="a Nav2 Simple Commander script")
    parser.add_argument(
        "--world",
        required=True,
        help="a bundled world name, a world YAML file or a map_server map YAML",
    )
    parser.add_argument(
        "--robot",
        metavar="NAME_OR_PATH",
        help="a bundled mobile robot (see baobab list) or a robot YAML file",
    )
    add_start(parser)
    parser.add_argument("--seed", metavar="N", default="0", help="simulation seed (default 0)")
    parser.add_argument(
        "--realtime", action="store_true", help="pace the simulation to the wall clock"
    )


def nav2_command(args: argparse.Namespace) -> int:
    """Check the arguments, then run the script; its exit status, or 2 for bad arguments."""
    from pathlib import Path

    from baobab.nav.script_runner import check_script, run_nav2_script

    check_script(Path(args.script))  # a ScriptError is located: main() prints it, exits 2
    world = load_world(args.world)  # a WorldError is located: main() prints it, exits 2
    footprint = robot_footprint(args.robot)  # a RobotFileError is located too
    start = start_pose(args.start, world, footprint)  # the default one is checked too (exit 2)
    try:
        seed = parse_seed(args.seed)
    except Nav2ArgumentError as exc:
        print(one_line(f"baobab nav2: {exc}"), file=sys.stderr)
        return EXIT_INVALID
    given = start if args.start is not None else None  # else the navigator's own default
    defaults = {
        "world": args.world,
        "robot": args.robot,
        "start": given,
        "seed": seed,
        "realtime": args.realtime,
    }
    return run_nav2_script(args.script, navigator_defaults=defaults)


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
