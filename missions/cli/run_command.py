"""``baobab run``: load, run, judge, write the run folder, report, and choose the exit code.

Order of work, so that invalid input exits 2 with nothing written: the options (each of
``--record``/``--video``/``--btlog`` names a regular file in a writable folder, PyAV is
installed for ``--video``, ``--live`` can bind its address, ``--host``, ``--port``, ``--fps``
and ``--video-size`` come with the option they tune), the mission (a path, or the name of a
bundled mission ``missions/<name>.yaml``) and its ``--set`` values, the baseline file (or,
when it is to be made, its writable folder), the run folder (claimed and locked: a second run
on the same ``--out`` is refused); only then the run. The run itself happens in a forked
process of its own and the run folder is written here (:mod:`baobab.missions.run.child_process`),
unless this process already runs other threads.

What cannot be written after the run does not lose it: a run folder the file system refuses
is written to a fallback folder that the message names (exit code: the run's own); if that
fails too, the result is only printed and the exit code is :data:`EXIT_NOT_SAVED`. A
recording that fails during the run stops with one line and the run goes on.

SIGINT, SIGTERM or SIGHUP during the run stops it at the next tick: the tree is halted, the
robot stopped, the result is CANCELED, the recordings are finished, the run folder is
written, and the exit code is ``128 + signal`` (:mod:`baobab.missions.cli.interrupts`).

``--viewer`` without a display prints a warning on stderr and runs headless (so a script that
asks for the viewer still gets its run folder); with a display, and with ``--live``, the run is
paced to the wall clock.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from baobab.missions.cli.arguments import add_robot, add_set, port, positive_int, video_size
from baobab.missions.cli.interrupts import RunSignals
from baobab.missions.cli.run_job import (
    FinishedRun,
    RunRequest,
    prepare_run_process,
    save_run,
    shower,
    simulate,
    simulate_in_child,
)
from baobab.missions.language.bundled_missions import resolve_mission
from baobab.missions.language.loader import Mission, load_mission
from baobab.missions.run.exit_codes import EXIT_NOT_INTENDED, EXIT_NOT_SAVED
from baobab.missions.run.output_checks import check_output_file
from baobab.missions.run.recording_hook import (
    DEFAULT_FPS,
    DEFAULT_HOST,
    DEFAULT_PORT,
    DEFAULT_VIDEO_SIZE,
    RecordingOptions,
)
from baobab.robots.catalog import RobotInfo
from baobab.sim.errors import BaobabError

if TYPE_CHECKING:
    from baobab.missions.run.child_process import StartedChild
    from baobab.missions.run.progress_display import LineProgress, LiveProgress
    from baobab.missions.testing.baseline import Baseline


def kernels_cached(robot: RobotInfo) -> bool:
    """Whether numba's disk cache holds the kernel ``robot``'s runs need first (its registry
    entry's ``kernel``; if not, this run compiles them).

    numba keeps an index file ``<module>.<function>-<line>.py<version>.nbi`` per cached
    function, in ``__pycache__`` beside the module or under ``NUMBA_CACHE_DIR``.
    """
    if robot.kernel is None:
        return True
    module, function = robot.kernel
    spec = importlib.util.find_spec(module)
    if spec is None or spec.origin is None:
        return True
    pattern = f"{module.rsplit('.', 1)[1]}.{function}-*.nbi"
    cache_dir = os.environ.get("NUMBA_CACHE_DIR")
    if cache_dir:
        return any(Path(cache_dir).rglob(pattern))
    return any((Path(spec.origin).parent / "__pycache__").glob(pattern))


def configure_run(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``baobab run``."""
    parser.add_argument(
        "mission", metavar="MISSION", help="a mission file, or the name of a bundled mission"
    )
    add_set(parser)
    add_robot(parser, "the mission's robot (where the mission fits it)")
    parser.add_argument(
        "--world",
        metavar="PATH",
        help="run in this world instead of the mission's: a bundled name, a world YAML file "
        "or a map_server map YAML (a map has no spawn: the mission needs a start)",
    )
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
        type=port,
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
        type=positive_int,
        metavar="N",
        help=f"video frames per second of sim time (default {DEFAULT_FPS})",
    )
    seeing.add_argument(
        "--video-size",
        type=video_size,
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


def run_command(args: argparse.Namespace, overrides: Mapping[str, str]) -> int:
    """The ``run`` handler; returns the exit code (BaobabError means invalid input, exit 2)."""
    recording = recording_options(args)
    if args.seed is not None and args.seed < 0:
        raise BaobabError(f"--seed must be >= 0, got {args.seed}")
    child = _start_run_process()
    try:
        return _checked_run(args, overrides, recording, child)
    finally:
        if child is not None:
            child.discard()  # refused input: the run's process ends unused


def _start_run_process() -> StartedChild | None:
    """Fork the run's process now, to load the simulation stack while this one checks the
    input; None where forking is not safe (the run then happens in this process)."""
    from baobab.missions.run.child_process import fork_is_safe, start_child

    return start_child(prepare_run_process) if fork_is_safe() else None


def _checked_run(
    args: argparse.Namespace,
    overrides: Mapping[str, str],
    recording: RecordingOptions,
    child: StartedChild | None,
) -> int:
    """Load and check the mission, the baseline and the run folder; then run and report."""
    mission = load_mission(
        resolve_mission(args.mission), overrides, robot=args.robot, world=args.world
    )
    baseline = None
    if args.baseline and not args.baseline.exists():  # made after the run: must be writable
        check_output_file("--baseline", args.baseline, create_folders=True)
    elif args.baseline:
        from baobab.missions.testing.baseline import read_baseline

        baseline = read_baseline(args.baseline, mission.name)
    # The simulation stack (MuJoCo, NumPy, the robots) never loads in this process, so a bad
    # mission is refused as fast as by `baobab validate`: it loads in the run's own process,
    # forked before the mission was loaded (and ended unused when the input is refused), and
    # the plotting stack loads in this one while the run runs (see run/child_process.py).
    from baobab.missions.run.run_folder import claimed_run_folder, default_run_folder

    folder: Path = args.out if args.out is not None else default_run_folder(mission.name)
    signals = RunSignals()
    with signals.installed():
        with claimed_run_folder(folder):
            outcome = _run_and_save(args, mission, recording, baseline, folder, signals, child)
        if outcome is None:
            return EXIT_NOT_INTENDED
        finished, saved_in = outcome
        _report(args, finished.result)
        if saved_in is None:
            return signals.exit_code(EXIT_NOT_SAVED)
        return signals.exit_code(finished.exit_code)


def _title(args: argparse.Namespace, mission: Mission) -> str:
    seed = mission.seed if args.seed is None else args.seed
    return f"{mission.name}: {mission.robot.name} in {mission.world_name}, seed {seed}"


def _display(args: argparse.Namespace, mission: Mission) -> LineProgress | LiveProgress:
    """The progress display: live on a terminal, else plain lines (on stderr with --json)."""
    from baobab.missions.run.progress_display import LineProgress, LiveProgress

    stream = sys.stderr if args.json else sys.stdout
    if stream.isatty():
        return LiveProgress(stream, _title(args, mission))
    stream.write(f"running {_title(args, mission)}\n")
    stream.flush()
    return LineProgress(stream)


def _run_and_save(
    args: argparse.Namespace,
    mission: Mission,
    recording: RecordingOptions,
    baseline: Baseline | None,
    folder: Path,
    signals: RunSignals,
    child: StartedChild | None,
) -> tuple[FinishedRun, Path | None] | None:
    """Run (in the run's process where there is one), then write the run folder.

    Returns:
        The finished run and where its folder went (None: nowhere), or None when the run's
        process died without a result (said on stderr).
    """
    from baobab.missions.run.child_process import ChildProcessDiedError

    progress = _display(args, mission)
    request = RunRequest(
        mission,
        args.seed,
        args.realtime,
        recording,
        args.baseline,
        baseline,
        folder,
        progress.schedule,
    )
    try:
        if not kernels_cached(mission.robot):
            sys.stderr.write(
                "first run on this machine: compiling baobab's kernels "
                "(about a minute; later runs load them from the cache)\n"
            )
        if not args.json:
            progress.phase(_starting(mission.robot))
        show = shower(progress)
        try:
            if child is not None:
                finished = child.run(
                    simulate_in_child,
                    request,
                    show,
                    on_signal=signals.note,
                    meanwhile=_load_plotting,
                    earlier=lambda: signals.first,
                )
            else:
                finished = simulate(request, signals, show)
        except ChildProcessDiedError as exc:
            print(f"baobab run: {exc}; no run folder was written", file=sys.stderr)
            return None
        finished.result["exit_code"] = signals.exit_code(finished.exit_code)
        if not args.json:
            progress.phase("writing the run folder...")
        return finished, save_run(request.folder, finished)
    finally:
        progress.close()


def _load_plotting() -> None:
    """Import the plotting stack in this process while the run's process simulates."""
    from baobab.missions.run.plotting import load_plotting  # after the fork: NumPy's threads

    load_plotting()


def _starting(robot: RobotInfo) -> str:
    """What the live display says until the run's first tick."""
    if kernels_cached(robot):
        return "starting: loading MuJoCo, the world, the robot and its compiled kernels..."
    return "starting: compiling baobab's kernels (first run on this machine, about a minute)..."


def _report(args: argparse.Namespace, result: Mapping[str, Any]) -> None:
    """The result on stdout: one JSON object (``--json``) or the summary table."""
    from baobab.missions.run.progress_display import print_summary

    if args.json:
        sys.stdout.write(json.dumps(result) + "\n")
    else:
        print_summary(sys.stdout, result, rich=sys.stdout.isatty())
        _print_recording(result.get("recording", {}))
    sys.stdout.flush()


def _print_recording(outputs: Mapping[str, object]) -> None:
    """One line naming what the run recorded, filmed or served."""
    parts = [str(outputs[key]) for key in ("mcap", "btlog", "live") if key in outputs]
    if "video" in outputs:
        parts.append(f"{outputs['video']} ({outputs.get('video_frames')} frames)")
    if parts:
        print(f"recorded: {', '.join(parts)}")


def recording_options(args: argparse.Namespace) -> RecordingOptions:
    """The recording flags of ``baobab run``, checked before anything runs.

    Raises:
        BaobabError: a tuning flag without the flag it tunes, a file that cannot be written
            (:func:`~baobab.missions.run.output_checks.check_output_file`: a missing or read-only
            folder, a folder or a device where a file goes, a full disk), a ``--btlog``
            without its suffix, ``--video`` without PyAV, a ``--live`` address the server
            could not listen on.
    """
    if not args.live and (args.host is not None or args.port is not None):
        raise BaobabError("--host and --port set up --live, which is not given")
    if args.video is None and (args.fps is not None or args.video_size is not None):
        raise BaobabError("--fps and --video-size set up --video, which is not given")
    if args.btlog is not None and args.btlog.suffix != ".btlog":
        raise BaobabError(f"--btlog {args.btlog}: Groot2 reads only files ending in .btlog")
    for flag, path in (("--record", args.record), ("--video", args.video), ("--btlog", args.btlog)):
        if path is not None:
            check_output_file(flag, path)
    if args.video is not None:
        try:
            import av  # noqa: F401  (PyAV: the video extra)
        except ImportError:
            raise BaobabError(
                '--video needs PyAV, which is not installed: pip install "baobab[video]"'
            ) from None
    host = DEFAULT_HOST if args.host is None else args.host
    port = DEFAULT_PORT if args.port is None else args.port
    if args.live:
        from baobab.sim.recording_sinks import LiveSink

        LiveSink.check_address(host, port)  # a RecordingError: exit 2 before the run
    return RecordingOptions(
        record=args.record,
        live=args.live,
        host=host,
        port=port,
        video=args.video,
        fps=DEFAULT_FPS if args.fps is None else args.fps,
        video_size=DEFAULT_VIDEO_SIZE if args.video_size is None else args.video_size,
        btlog=args.btlog,
        viewer=args.viewer,
    )
