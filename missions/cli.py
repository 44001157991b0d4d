"""The ``baobab`` command line.

Exit codes (DESIGN §2): 0 as intended, 1 ran but not as intended, 2 invalid input (located
messages on stderr, never a traceback), 3 ran but could not be saved (``run``), 128 + signal
when SIGINT (130), SIGTERM (143) or SIGHUP (129) ended it (:mod:`.interrupts`).

Commands here: ``validate``, ``tree``, ``schema``, ``list`` and ``run`` (its work lives in
:mod:`baobab.missions.run_command`, imported when used so the other commands start fast).
``teleop``, ``campaign`` and ``nav2`` have their arguments declared (DESIGN §4) and are marked
EXTENSION POINT: their handlers report "not available yet".
"""

from __future__ import annotations

import os

# MuJoCo picks its OpenGL backend when first imported; headless, only EGL can render video.
if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    os.environ.setdefault("MUJOCO_GL", "egl")
# baobab's models need no pydantic plugins, and looking for them reads the metadata of every
# installed package at start-up; a user who sets the variable keeps their choice.
os.environ.setdefault("PYDANTIC_DISABLE_PLUGINS", "__all__")

import argparse
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

from baobab.missions.interrupts import signals_for
from baobab.missions.startup import loading_modules, skip_pydantic_plugin_discovery
from baobab.sim.errors import BaobabError, SourceError, one_line

if TYPE_CHECKING:
    from baobab.behaviours.ports import Capabilities
    from baobab.missions.loader import Mission

# Start-up time is a product figure (``baobab validate`` of every bundled mission in well under
# half a second): the mission loader (pydantic) is imported once main() has prepared the
# process, and what only one command needs (py_trees for a compiled tree, json, the behaviour
# catalogue) inside that command's handler.

EXIT_OK, EXIT_NOT_INTENDED, EXIT_INVALID, EXIT_INTERRUPTED = 0, 1, 2, 130
Handler = Callable[[argparse.Namespace], int]


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``baobab`` console script; returns the exit code."""
    skip_pydantic_plugin_discovery()
    arguments = list(sys.argv[1:] if argv is None else argv)
    command = next((argument for argument in arguments if not argument.startswith("-")), None)
    parser = build_parser(command)
    for argument in arguments:
        if not _is_utf8(argument):
            # A run writes its arguments (--set values, paths) into UTF-8 files (result.json,
            # the trace): refuse them now rather than after the simulation.
            print(
                f"baobab: argument '{one_line(argument)}' is not valid UTF-8 text; "
                "write it (and name files) in UTF-8",
                file=sys.stderr,
            )
            return EXIT_INVALID
    extras: dict[str, list[str]] = {}
    if command == "ros":  # `-- --ros-args ...` and `name:=value` words are not argparse's
        from baobab.missions.ros_command import split_arguments

        arguments, extras = split_arguments(arguments)
    try:
        args = parser.parse_args(arguments)
    except SystemExit as exit_:  # argparse: --help (0) or a usage error (2)
        return int(exit_.code or 0)
    vars(args).update(extras)
    handler: Handler = args.handler
    signals_for(args.command)
    try:
        return handler(args)
    except SourceError as exc:
        print(exc, file=sys.stderr)
        return EXIT_INVALID
    except BaobabError as exc:
        print(one_line(f"baobab {args.command}: {exc}"), file=sys.stderr)
        return EXIT_INVALID
    except KeyboardInterrupt:
        return EXIT_INTERRUPTED


def _is_utf8(argument: str) -> bool:
    """False for an argument with bytes that are not UTF-8 (``os.fsdecode`` keeps them as
    lone surrogates)."""
    try:
        argument.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


class _Parser(argparse.ArgumentParser):
    """argparse with its usage errors on one line (exit 2); ``--help`` is unchanged."""

    def error(self, message: str) -> NoReturn:
        """Print ``baobab run: <what is wrong> (see baobab run --help)`` and exit 2."""
        self.exit(EXIT_INVALID, f"{one_line(f'{self.prog}: {message}')} (see {self.prog} --help)\n")


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The argument parser with every subcommand.

    Args:
        command: when it names a subcommand, only that one's arguments are set up (setting up
            the others imports what only they need, e.g. the teleop terminal for ``teleop``).
    """
    parser = _Parser(
        prog="baobab",
        description="Robot missions in YAML, compiled to behaviour trees, run over MuJoCo.",
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, (configure, handler, summary) in COMMANDS.items():
        sub = commands.add_parser(name, help=summary, description=summary)
        if command not in COMMANDS or name == command:
            configure(sub)
        sub.set_defaults(handler=handler)
    return parser


def _assignment(text: str) -> tuple[str, str]:
    from baobab.missions.params import parse_assignment

    try:
        return parse_assignment(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _add_set(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--set",
        dest="sets",
        action="append",
        default=[],
        type=_assignment,
        metavar="KEY=VALUE",
        help="override a mission parameter (repeatable)",
    )


def _overrides(args: argparse.Namespace) -> dict[str, str]:
    overrides: dict[str, str] = {}
    for key, value in args.sets:
        if key in overrides:
            raise BaobabError(f"--set {key} is given twice")
        overrides[key] = value
    return overrides


def _offline_capabilities() -> Capabilities:
    """Ports for displaying a tree without running it: the clock stands at 0."""
    from baobab.behaviours.ports import Capabilities

    return Capabilities(clock=lambda: 0.0)


# --- validate -------------------------------------------------------------------------------


def _configure_validate(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("files", nargs="+", metavar="FILE", help="mission files")
    _add_set(parser)


def _validate(args: argparse.Namespace) -> int:
    # load_mission checks everything a file can get wrong (node types, capabilities, parameters,
    # subtrees, poses); building the py_trees tree from a loaded mission cannot fail, so validate
    # does not build it (and does not import py_trees).
    with loading_modules():
        from baobab.missions.loader import load_mission
        from baobab.missions.registry import default_registry

        default_registry()
    overrides = _overrides(args)
    failed = 0
    for file in args.files:
        try:
            mission = load_mission(file, overrides)
        except SourceError as exc:
            print(exc, file=sys.stderr)
            failed += 1
            continue
        nodes = len(mission.tree.walk())
        summary = f"{mission.name}: {mission.robot.name} in {_world(mission)}, {nodes} nodes"
        print(f"{one_line(file, None)}: ok ({summary})")
    return EXIT_INVALID if failed else EXIT_OK


def _world(mission: Mission) -> str:
    return Path(mission.world_name).name if "/" in mission.world_name else mission.world_name


# --- tree -----------------------------------------------------------------------------------


def _configure_tree(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("mission", metavar="MISSION", help="a mission file")
    parser.add_argument(
        "--format",
        choices=("unicode", "dot", "btcpp"),
        default="unicode",
        help="unicode text, Graphviz dot, or BehaviorTree.CPP v4 XML for Groot2",
    )
    _add_set(parser)


def _tree(args: argparse.Namespace) -> int:
    from baobab.missions.compiler import compile_mission
    from baobab.missions.export import to_btcpp, to_dot, to_unicode
    from baobab.missions.loader import load_mission

    mission = load_mission(args.mission, _overrides(args))
    if args.format == "btcpp":
        sys.stdout.write(to_btcpp(mission))
        return EXIT_OK
    compiled = compile_mission(mission, _offline_capabilities(), require_ports=False)
    text = to_dot(compiled) if args.format == "dot" else to_unicode(compiled)
    sys.stdout.write(text if text.endswith("\n") else text + "\n")
    return EXIT_OK


# --- schema ---------------------------------------------------------------------------------


def _configure_schema(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-o", "--output", type=Path, help="write to this file instead of stdout")


def _schema(args: argparse.Namespace) -> int:
    import json

    from baobab.missions.json_schema import mission_json_schema

    text = json.dumps(mission_json_schema(), indent=2) + "\n"
    if args.output is None:
        sys.stdout.write(text)
    else:
        args.output.write_text(text, encoding="utf-8")
    return EXIT_OK


# --- list -----------------------------------------------------------------------------------


def _configure_list(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="one JSON object on stdout")


def bundled_missions() -> dict[str, str]:
    """Bundled mission files (``missions/*.yaml``): name -> description."""
    from importlib import resources

    from baobab.sim.yaml_source import load_located_yaml

    folder = resources.files("baobab.missions")
    missions: dict[str, str] = {}
    for entry in sorted(folder.iterdir(), key=lambda e: e.name):
        if not entry.name.endswith(".yaml"):
            continue
        try:
            data = load_located_yaml(Path(str(entry))).data
            description = str(data.get("description", "")) if isinstance(data, dict) else ""
        except SourceError as exc:
            description = f"(unreadable: {exc.message})"
        missions[entry.name.removesuffix(".yaml")] = " ".join(description.split())
    return missions


def _catalogue() -> dict[str, Any]:
    from baobab.missions.registry import default_registry
    from baobab.robots.catalog import ROBOTS
    from baobab.sim.world import bundled_world_names

    registry = default_registry()
    return {
        "missions": bundled_missions(),
        "worlds": bundled_world_names(),
        "scenes": sorted({scene for robot in ROBOTS.values() for scene in robot.scenes}),
        "robots": {
            name: {"description": robot.description, "capabilities": sorted(robot.capabilities)}
            for name, robot in ROBOTS.items()
        },
        "behaviours": {
            behaviour.name: {
                "kind": behaviour.kind.value,
                "capability": behaviour.capability,
                "description": behaviour.description,
                "parameters": list(behaviour.ports()),
            }
            for behaviour in registry
        },
    }


def _list(args: argparse.Namespace) -> int:
    import json

    from baobab.missions.registry import NodeKind

    catalogue = _catalogue()
    if args.json:
        print(json.dumps(catalogue, indent=2))
        return EXIT_OK
    lines = ["missions:"]
    lines += [f"  {n:<24} {d}" for n, d in catalogue["missions"].items()] or ["  (none bundled)"]
    lines += ["worlds:"] + [f"  {name}" for name in catalogue["worlds"]]
    lines += [f"  {name} (scene)" for name in catalogue["scenes"]]
    lines.append("robots:")
    for name, robot in catalogue["robots"].items():
        lines.append(f"  {name:<24} {', '.join(robot['capabilities'])}: {robot['description']}")
    lines.append("behaviours:")
    for kind in NodeKind:
        for name, info in catalogue["behaviours"].items():
            if info["kind"] == kind.value:
                need = f"[{info['capability']}]" if info["capability"] else ""
                lines.append(f"  {name:<24} {kind.value:<10} {need:<19} {info['description']}")
    print("\n".join(lines))
    return EXIT_OK


# --- run ----------------------------------------------------------------------------------


def _configure_run(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.recording_hook import (
        DEFAULT_FPS,
        DEFAULT_HOST,
        DEFAULT_PORT,
        DEFAULT_VIDEO_SIZE,
    )

    parser.add_argument(
        "mission", metavar="MISSION", help="a mission file, or the name of a bundled mission"
    )
    _add_set(parser)
    parser.add_argument("--seed", type=int, help="override the mission's seed")
    parser.add_argument("--out", type=Path, help="run folder (default: runs/<mission>-<time>)")
    parser.add_argument("--json", action="store_true", help="one JSON result object on stdout")
    parser.add_argument("--realtime", action="store_true", help="pace the sim to the wall clock")
    parser.add_argument(
        "--baseline",
        type=Path,
        metavar="FILE",
        help="compare sim time, path length and recoveries with FILE (created if missing)",
    )
    seeing = parser.add_argument_group("seeing what happened")
    seeing.add_argument(
        "--record",
        type=Path,
        metavar="FILE.mcap",
        help="record the run as MCAP (open it in Foxglove or PlotJuggler)",
    )
    seeing.add_argument(
        "--live",
        action="store_true",
        help="serve the run to Foxglove over WebSocket, paced to the wall clock",
    )
    seeing.add_argument(
        "--host", metavar="HOST", help=f"live server address (default {DEFAULT_HOST})"
    )
    seeing.add_argument(
        "--port",
        type=_port,
        metavar="PORT",
        help=f"live server port (default {DEFAULT_PORT}; 0 picks a free one)",
    )
    seeing.add_argument(
        "--video",
        type=Path,
        metavar="FILE.mp4",
        help='film the run as H.264 MP4 (needs pip install "baobab[video]")',
    )
    seeing.add_argument(
        "--fps",
        type=_positive_int,
        metavar="N",
        help=f"video frames per second of sim time (default {DEFAULT_FPS})",
    )
    seeing.add_argument(
        "--video-size",
        type=_video_size,
        metavar="WxH",
        help="video size in pixels, both even (default {}x{})".format(*DEFAULT_VIDEO_SIZE),
    )
    seeing.add_argument(
        "--viewer", action="store_true", help="show the MuJoCo viewer (needs a display)"
    )
    seeing.add_argument(
        "--btlog",
        type=Path,
        metavar="FILE.btlog",
        help="log the tree's status changes for Groot2's log viewer",
    )


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: '{text}'") from None
    if value <= 0:
        raise argparse.ArgumentTypeError(f"must be positive, got {value}")
    return value


def _port(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a port number: '{text}'") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError(f"a port is 0..65535, got {value}")
    return value


def _video_size(text: str) -> tuple[int, int]:
    width, _, height = text.lower().partition("x")
    if not (width.isdigit() and height.isdigit()):
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT in pixels, e.g. 640x480: '{text}'")
    size = int(width), int(height)
    if min(size) <= 0 or size[0] % 2 or size[1] % 2:
        raise argparse.ArgumentTypeError(f"width and height must be positive and even: '{text}'")
    return size


def _run(args: argparse.Namespace) -> int:
    from baobab.missions.run_command import run_command

    return run_command(args, _overrides(args))


# --- EXTENSION POINTS: teleop, campaign, nav2 -----------------------------------------------
# The lead replaces each `_not_yet(...)` handler below with the real one; the arguments are
# already those of DESIGN §4, so scripts and docs can rely on them now.


def _configure_teleop(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.teleop_command import configure_teleop

    configure_teleop(parser)


def _teleop(args: argparse.Namespace) -> int:
    from baobab.missions.teleop_command import teleop_command

    return teleop_command(args)


def _configure_campaign(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "mission", metavar="MISSION", help="a mission file, or the name of a bundled mission"
    )
    parser.add_argument(
        "--runs",
        type=_positive_int,
        help="seeded runs; with grid axes, runs per grid cell (default 1)",
    )
    parser.add_argument(
        "--vary",
        action="append",
        default=[],
        metavar="KEY=DIST",
        help="vary a parameter (table), start.x/y/yaw (offsets), noise.lidar_std or "
        "events.N.KIND.FIELD: uniform(a,b), normal(mu,sigma), randint(a,b), choice(v1,v2,...), "
        "grid(a,b,n) (repeatable)",
    )
    parser.add_argument(
        "--grid",
        action="append",
        default=[],
        metavar="KEY=V1,V2,...",
        help="a grid axis of listed values; grid axes combine as a cartesian product (repeatable)",
    )
    _add_set(parser)
    parser.add_argument(
        "--seed",
        type=int,
        help="campaign seed; each run's seed derives from it (default: mission's)",
    )
    parser.add_argument(
        "--workers", type=_positive_int, help="local worker processes (default: one per core)"
    )
    parser.add_argument(
        "--scheduler",
        metavar="tcp://HOST:PORT",
        help='run on a Dask cluster (needs pip install "baobab[campaign]")',
    )
    parser.add_argument(
        "--out", type=Path, help="campaign folder (default: campaigns/<mission>-<time>)"
    )
    parser.add_argument("--json", action="store_true", help="one JSON summary on stdout")


def _campaign(args: argparse.Namespace) -> int:
    from baobab.missions.campaign_command import campaign_command

    return campaign_command(args, _overrides(args))


def _configure_nav2(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.nav2_command import configure_nav2

    configure_nav2(parser)


def _nav2(args: argparse.Namespace) -> int:
    from baobab.missions.nav2_command import nav2_command

    return nav2_command(args)


def _configure_ros(parser: argparse.ArgumentParser) -> None:
    from baobab.missions.ros_command import configure_ros

    configure_ros(parser)


def _ros(args: argparse.Namespace) -> int:
    from baobab.missions.ros_command import ros_command

    return ros_command(args)


def _not_yet(args: argparse.Namespace) -> int:
    print(f"baobab {args.command}: not available yet", file=sys.stderr)
    return EXIT_INVALID


COMMANDS: dict[str, tuple[Callable[[argparse.ArgumentParser], None], Handler, str]] = {
    "run": (_configure_run, _run, "run a mission and write its run folder"),
    "validate": (_configure_validate, _validate, "check mission files without running them"),
    "tree": (_configure_tree, _tree, "print a mission's compiled behaviour tree"),
    "schema": (_configure_schema, _schema, "print the JSON Schema of the mission format"),
    "list": (_configure_list, _list, "list bundled missions, worlds, robots and behaviours"),
    "teleop": (_configure_teleop, _teleop, "drive with the keyboard, assisted teleop on"),
    "campaign": (_configure_campaign, _campaign, "seeded sweeps of a mission, in parallel"),
    "nav2": (_configure_nav2, _nav2, "run a Nav2 Simple Commander script"),
    "ros": (_configure_ros, _ros, "run rclpy node files or a launch file on sim time"),
}
"""Subcommand name -> (argument setup, handler, one-line help)."""
