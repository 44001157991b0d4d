"""``baobab ros run NODE.py ...`` and ``baobab ros launch FILE.launch.py ...``: rclpy node files
run unmodified against the simulation, on sim time, in one process.

    baobab ros run NODE.py [NODE.py ...] --world W --robot R [--duration S] [--seed N]
        [--start X,Y,YAW] [--pub TOPIC TYPE YAML --at T] [--press KEY --at T]
        [--release KEY --at T] [--echo TOPIC] [--record F.mcap] [-- --ros-args ...]
    baobab ros launch FILE.launch.py [name:=value ...] [--show-args] [same options]

``--pub`` sends one message (``ros2 topic pub --once``: the type as ``pkg/msg/Type``, the
fields as YAML) when sim time reaches the ``--at`` after it (0 without one); ``--press`` and
``--release`` work the keys a ``pynput`` listener hears. ``--echo`` prints each message of a
topic as ``ros2 topic echo`` does; ``--record`` writes every message to an MCAP file (JSON).
The ``--ros-args`` after a lone ``--`` go to every node file, as ``ros2 run pkg exe --ros-args``.

Exit status: 0 when the run lasted ``--duration`` (or every node ended by itself); 1 when node
code raised: its traceback, from the node file's first frame, and a line naming the file and
its nodes; 2 for a mistake in the command (one line, located where it can be).
"""

from __future__ import annotations

import argparse
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from baobab.robots.catalog import DEFAULT_MOBILE_ROBOT, MOBILE_ROBOTS, ROBOTS
from baobab.sim.errors import BaobabError, clip

ARM_NAMES = tuple(name for name, robot in ROBOTS.items() if robot.runtime)
"""The registry's arms, which run in their own scenes."""
EXIT_OK, EXIT_FAILED, EXIT_INVALID = 0, 1, 2
DEFAULT_DURATION = 60.0
"""Seconds of sim time a run lasts without ``--duration``."""


_LAUNCH_ARGUMENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_.]*:=")


def split_arguments(arguments: list[str]) -> tuple[list[str], dict[str, list[str]]]:
    """Take what argparse must not see out of a ``baobab ros`` command line: the words after a
    lone ``--`` (the nodes' ``--ros-args``) and ``name:=value`` launch arguments, which
    ``ros2 launch`` takes anywhere.

    Returns:
        The words for argparse, and ``passthrough`` and ``launch_arguments`` for the handler.
    """
    passthrough: list[str] = []
    if "--" in arguments:
        at = arguments.index("--")
        arguments, passthrough = arguments[:at], arguments[at + 1 :]
    launch = [word for word in arguments if _LAUNCH_ARGUMENT.match(word)]
    rest = [word for word in arguments if not _LAUNCH_ARGUMENT.match(word)]
    return rest, {"passthrough": passthrough, "launch_arguments": launch}


class RosCommandError(BaobabError):
    """A ``baobab ros`` argument that cannot be used."""


@dataclass
class NodeSpec:
    """One node file to run and its command line after its own path."""

    path: Path
    argv: list[str] = field(default_factory=list)


_ARM = ARM_NAMES[0] if ARM_NAMES else "ARM"
"""An arm of the registry, for the help's examples."""

RUN_HELP = """\
Run rclpy node files unmodified against the simulation, on sim time, in one process: each
file's main() (or its __main__ block). The robot is on ROS's topics (/cmd_vel, /odom, /tf,
/scan, ...; an arm's /cartesian_impedance/*).

examples:
  baobab ros run pub_node.py sub_node.py -- --ros-args -p timer_period:=0.5
  baobab ros run point2point_nav.py --world walls --pub /goal geometry_msgs/msg/PoseStamped \\
      "{header: {frame_id: odom}, pose: {position: {x: 2.0, y: 2.0}}}" --at 1 --echo /cmd_vel
  baobab ros run keyboard_teleop.py --press w --at 1 --release w --at 3

exit status: 0 when the run lasted --duration, 1 when node code raised (its traceback), 2
for a mistake in the command."""

LAUNCH_HELP = f"""\
Run a Python launch file (LaunchDescription, DeclareLaunchArgument, LaunchConfiguration,
IncludeLaunchDescription of a local file, LogInfo, launch_ros Node) against the simulation.

example:
  baobab ros launch exercise_pose_publisher.launch.py --robot {_ARM} \\
      goal:="[3.0, 0.6, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0]"
"""


class _Timed(argparse.Action):
    """``--pub``, ``--press`` and ``--release``: kept in order, each with the ``--at`` after it."""

    def __call__(self, parser: Any, namespace: Any, values: Any, option: str | None = None) -> None:
        events = getattr(namespace, "events", None) or []
        events.append({"kind": self.dest, "values": values, "at": 0.0})
        namespace.events = events


class _At(argparse.Action):
    def __call__(self, parser: Any, namespace: Any, values: Any, option: str | None = None) -> None:
        events: list[dict[str, Any]] = getattr(namespace, "events", None) or []
        if not events:
            parser.error("--at must follow a --pub, --press or --release")
        try:
            time = float(values)
        except ValueError:
            time = -1.0
        if not time >= 0.0:
            parser.error(f"--at: expected a non-negative time in seconds, got '{clip(values)}'")
        events[-1]["at"] = time


def _common(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--world", default=None, help="bundled world or world file (default walls)")
    parser.add_argument(
        "--robot",
        default=None,
        metavar="NAME_OR_PATH",
        help=f"a mobile robot ({', '.join(MOBILE_ROBOTS)}; default {DEFAULT_MOBILE_ROBOT}) or "
        f"a robot file, or an arm in its own scene ({', '.join(ARM_NAMES)})",
    )
    parser.add_argument(
        "--duration",
        type=float,
        default=DEFAULT_DURATION,
        help=f"seconds of sim time to run (default {DEFAULT_DURATION:g})",
    )
    parser.add_argument("--seed", metavar="N", default="0", help="simulation seed (default 0)")
    parser.add_argument("--start", metavar="X,Y,YAW", help="the mobile robot's start pose")
    parser.add_argument(
        "--pub", nargs=3, metavar=("TOPIC", "TYPE", "YAML"), action=_Timed, help="send a message"
    )
    parser.add_argument("--press", metavar="KEY", action=_Timed, help="press a key (pynput)")
    parser.add_argument("--release", metavar="KEY", action=_Timed, help="release a key")
    parser.add_argument("--at", metavar="T", action=_At, help="when the event before falls (s)")
    parser.add_argument("--echo", metavar="TOPIC", action="append", default=[], help="print")
    parser.add_argument("--record", metavar="F.mcap", type=Path, help="record every message")
    parser.set_defaults(events=[])


def configure_ros(parser: argparse.ArgumentParser) -> None:
    """Declare ``baobab ros run`` and ``baobab ros launch``."""
    commands = parser.add_subparsers(dest="ros_command", required=True, metavar="{run,launch}")
    run = commands.add_parser(
        "run",
        help="run node files",
        description=RUN_HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    run.add_argument("nodes", nargs="+", metavar="NODE.py", help="node files, then -- --ros-args")
    _common(run)
    launch = commands.add_parser(
        "launch",
        help="run a Python launch file",
        usage="%(prog)s FILE.launch.py [name:=value ...] [options]",
        description=LAUNCH_HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    launch.add_argument("launch_file", metavar="FILE.launch.py")
    launch.add_argument("--show-args", action="store_true", help="list the launch arguments")
    _common(launch)


def ros_command(args: argparse.Namespace) -> int:
    """Run ``baobab ros run`` or ``baobab ros launch`` (module docstring)."""
    if args.ros_command == "launch":
        from baobab.nav.ros.launch_files import describe_arguments, nodes_of_launch_file

        path = Path(args.launch_file)
        if args.show_args:
            print(describe_arguments(path), end="")
            return EXIT_OK
        specs = [
            NodeSpec(node.path, [*node.argv, *getattr(args, "passthrough", [])])
            for node in nodes_of_launch_file(path, _launch_arguments(args.launch_arguments))
        ]
        return run_nodes(args, specs)
    passthrough = list(getattr(args, "passthrough", []))
    return run_nodes(args, [NodeSpec(Path(name), list(passthrough)) for name in args.nodes])


def _launch_arguments(words: list[str]) -> dict[str, str]:
    values = {}
    for word in words:
        name, separator, value = word.partition(":=")
        if not separator or not name:
            raise RosCommandError(f"launch argument '{clip(word)}': expected name:=value")
        values[name] = value
    return values


def run_nodes(args: argparse.Namespace, specs: list[NodeSpec]) -> int:
    """Bring the robot up, run ``specs`` for ``--duration`` and report (module docstring)."""
    from baobab.missions.cli.arguments import robot_footprint, start_pose
    from baobab.missions.cli.nav2_command import parse_seed
    from baobab.nav.ros.arguments import parse_ros_arguments
    from baobab.nav.ros.bringup import bring_up
    from baobab.nav.ros.node_files import (
        check_script,
        failure_report,
        node_file_main,
        node_file_paths,
    )

    for spec in specs:
        check_script(spec.path)  # a ScriptError is located: main() prints it, exits 2
        parse_ros_arguments(spec.argv)  # a RosArgumentError: one line, exit 2
    if not args.duration > 0:
        raise RosCommandError(f"--duration: expected a positive time, got {args.duration:g} s")
    seed = parse_seed(args.seed)
    start = None
    robot = args.robot or DEFAULT_MOBILE_ROBOT
    if robot not in ARM_NAMES and args.start is not None:
        from baobab.sim.world import load_world

        start = start_pose(args.start, load_world(args.world or "walls"), robot_footprint(robot))
    bringup = bring_up(robot, args.world, seed=seed, start=start)
    runtime = bringup.runtime
    recorder = _recorder(args.record, runtime) if args.record is not None else None
    try:
        with runtime.active(), node_file_paths([spec.path for spec in specs]):
            _schedule(args.events, runtime)
            for topic in args.echo:
                runtime.graph.tap(_topic(topic), _echo)
            for spec in specs:
                runtime.start(
                    node_file_main(spec.path),
                    name=spec.path.stem,
                    argv=[str(spec.path), *spec.argv],
                    origin=str(spec.path),
                )
            end = runtime.run(args.duration)
    finally:
        if recorder is not None:
            recorder.close()
    sys.stdout.flush()
    for failure in end.failures:
        report = failure_report(failure.actor.origin, list(failure.node_names), failure.error)
        print(report, file=sys.stderr)
    if end.failures:
        return EXIT_FAILED
    print(
        f"baobab ros {args.ros_command}: {end.sim_time:.3f} s of sim time, "
        f"trace digest {runtime.trace_digest[:16]}",
        file=sys.stderr,
    )
    return EXIT_OK


def _topic(name: str) -> str:
    return name if name.startswith("/") else f"/{name}"


def _schedule(events: list[dict[str, Any]], runtime: Any) -> None:
    """Turn ``--pub``/``--press``/``--release`` into timed events of ``runtime``."""
    import yaml

    from baobab.nav.rosmsg import MessageFieldError, fill_message, message_class

    for number, event in enumerate(events, start=1):
        kind, values, at = event["kind"], event["values"], event["at"]
        if kind != "pub":
            from baobab.nav.ros.pynput.keyboard import key_named

            try:
                key_named(values)
            except ValueError as exc:
                raise RosCommandError(f"--{kind} {clip(values)}: {exc}") from None
            runtime.at(at, lambda kind=kind, key=values: getattr(runtime.keyboard, kind)(key))
            continue
        topic, type_name, text = values
        try:
            message = message_class(type_name)()
        except KeyError:
            raise RosCommandError(
                f"--pub #{number}: unknown message type '{clip(type_name)}' "
                "(expected pkg/msg/Type, e.g. geometry_msgs/msg/Twist)"
            ) from None
        try:
            fill_message(message, yaml.safe_load(text) if text.strip() else None)
        except yaml.YAMLError as exc:
            raise RosCommandError(f"--pub #{number}: the fields are not YAML: {exc}") from None
        except MessageFieldError as exc:
            raise RosCommandError(f"--pub #{number} ({type_name}): {exc}") from None
        runtime.publish_at(at, _topic(topic), message)


def _echo(topic: str, message: Any) -> None:
    """Print ``message`` as ``ros2 topic echo`` does: its fields as YAML, then ``---``."""
    import yaml

    from baobab.nav.rosmsg import to_plain

    text = yaml.safe_dump(to_plain(message), sort_keys=False, default_flow_style=False)
    print(f"{text}---", flush=False)


def _recorder(path: Path, runtime: Any) -> Any:
    """A recorder writing every message of the run to ``path``: ``/tf`` and ``/tf_static`` as
    Foxglove frame transforms (for its 3D panel), every other topic as JSON, one channel each."""
    from baobab.missions.run.output_checks import check_output_file
    from baobab.nav.ros.tf2_msgs.msg import TFMessage
    from baobab.nav.rosmsg import to_plain
    from baobab.sim.recording import JsonSchema, McapSink, Recorder, Transform

    check_output_file("--record", path)
    recorder = Recorder([McapSink(path)])

    def record(topic: str, message: Any) -> None:
        t = runtime.now_ns() / 1e9
        if isinstance(message, TFMessage):
            transforms = [
                Transform(
                    item.header.frame_id,
                    item.child_frame_id,
                    (
                        item.transform.translation.x,
                        item.transform.translation.y,
                        item.transform.translation.z,
                    ),
                    (
                        item.transform.rotation.x,
                        item.transform.rotation.y,
                        item.transform.rotation.z,
                        item.transform.rotation.w,
                    ),
                )
                for item in message.transforms
            ]
            log = (
                recorder.log_static_transforms if topic == "/tf_static" else recorder.log_transforms
            )
            log(topic, t, transforms)
            return
        schema = JsonSchema(type(message)._type_name, {"type": "object"})
        recorder.log_json(topic, t, to_plain(message), schema=schema)

    for topic in runtime.graph.topic_names():
        for message in runtime.graph.latched(topic):  # published before the recording began
            record(topic, message)
    runtime.graph.tap(None, record)
    return recorder
