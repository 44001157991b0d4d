"""``baobab run``: load, run, judge, write the run folder, report, and choose the exit code.

Order of work, so that invalid input exits 2 with nothing written: the options (the folders
of ``--record``/``--video``/``--btlog`` exist, PyAV is installed for ``--video``, ``--host``,
``--port``, ``--fps`` and ``--video-size`` come with the option they tune), the mission (a
path, or the name of a bundled mission ``missions/<name>.yaml``) and its ``--set`` values, the
baseline file, the run folder, the robot, the tree and the recorders; only then the run.
SIGINT during the run stops it at the next tick: the tree is halted, the robot stopped, the
result is CANCELED, the recordings are finished, the run folder is written, and the exit code
is 130. The run itself happens in a forked process of its own and the run folder is written
here (:mod:`baobab.missions.run_process`), unless this process already runs other threads.

``--viewer`` without a display prints a warning on stderr and runs headless (so a script that
asks for the viewer still gets its run folder); with a display, and with ``--live``, the run is
paced to the wall clock.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING, Any

from baobab.missions.cli import EXIT_NOT_INTENDED
from baobab.missions.loader import load_mission
from baobab.missions.recording_hook import (
    DEFAULT_FPS,
    DEFAULT_HOST,
    DEFAULT_PORT,
    DEFAULT_VIDEO_SIZE,
    RecordingOptions,
)
from baobab.sim.errors import BaobabError

if TYPE_CHECKING:
    from baobab.missions.baseline import Baseline
    from baobab.missions.plotting import PlotData
    from baobab.missions.progress import LineProgress, LiveProgress, ProgressSnapshot
    from baobab.missions.runner import RunRecord


class MissionNotFoundError(BaobabError):
    """MISSION is neither a file nor a bundled mission."""


def bundled_mission_path(name: str) -> Path | None:
    """The file of bundled mission ``name`` (``missions/<name>.yaml``), or None."""
    entry = resources.files("baobab.missions") / f"{name}.yaml"
    return Path(str(entry)) if entry.is_file() else None


def resolve_mission(text: str) -> Path:
    """MISSION as a file path, or as the name of a bundled mission.

    Raises:
        MissionNotFoundError: when it is neither.
    """
    path = Path(text)
    looks_like_a_path = "/" in text or "\\" in text or text.endswith((".yaml", ".yml"))
    if path.is_file() or looks_like_a_path:
        return path  # a missing file or a folder: the loader reports it as path:1:1
    bundled = bundled_mission_path(text)
    if bundled is not None:
        return bundled
    folder = resources.files("baobab.missions")
    names = sorted(
        e.name.removesuffix(".yaml") for e in folder.iterdir() if e.name.endswith(".yaml")
    )
    raise MissionNotFoundError(
        f"no mission file '{text}' and no bundled mission of that name "
        f"(bundled: {', '.join(names) or 'none'})"
    )


@contextmanager
def sigint_flag() -> Iterator[threading.Event]:
    """Turn the first SIGINT into a flag the run loop polls; a second one interrupts at once."""
    flag = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield flag
        return
    previous = signal.getsignal(signal.SIGINT)

    def handler(_signum: int, _frame: FrameType | None) -> None:
        flag.set()
        signal.signal(signal.SIGINT, previous)

    signal.signal(signal.SIGINT, handler)
    try:
        yield flag
    finally:
        signal.signal(signal.SIGINT, previous)


_ROBOT_KERNELS = {
    "turtlebot3": ("baobab.robots.turtlebot3.base_kernel", "base_kernel"),
    "panda": ("baobab.robots.panda.native_loop", "_arm_kernel"),
}
"""Per robot, the module and function of the compiled kernel its runs need first."""


def kernels_cached(robot: str) -> bool:
    """Whether numba's disk cache holds ``robot``'s kernel (if not, this run compiles them).

    numba keeps an index file ``<module>.<function>-<line>.py<version>.nbi`` per cached
    function, in ``__pycache__`` beside the module or under ``NUMBA_CACHE_DIR``.
    """
    if robot not in _ROBOT_KERNELS:
        return True
    module, function = _ROBOT_KERNELS[robot]
    spec = importlib.util.find_spec(module)
    if spec is None or spec.origin is None:
        return True
    pattern = f"{module.rsplit('.', 1)[1]}.{function}-*.nbi"
    cache_dir = os.environ.get("NUMBA_CACHE_DIR")
    if cache_dir:
        return any(Path(cache_dir).rglob(pattern))
    return any((Path(spec.origin).parent / "__pycache__").glob(pattern))


def run_command(args: argparse.Namespace, overrides: Mapping[str, str]) -> int:
    """The ``run`` handler; returns the exit code (BaobabError means invalid input, exit 2)."""
    recording = recording_options(args)
    if args.seed is not None and args.seed < 0:
        raise BaobabError(f"--seed must be >= 0, got {args.seed}")
    mission = load_mission(resolve_mission(args.mission), overrides)
    baseline = None
    if args.baseline:
        from baobab.missions.baseline import read_baseline

        baseline = read_baseline(args.baseline, mission.name)
    # The simulation stack (MuJoCo, NumPy, the robots) loads only once the mission is valid,
    # so a bad mission is refused as fast as by `baobab validate`; it loads in the run's own
    # process, and the plotting stack in this one (see run_process).
    from baobab.missions.progress import LineProgress, LiveProgress, print_summary
    from baobab.missions.run_folder import check_run_folder, default_run_folder, write_run_folder
    from baobab.missions.run_process import ChildProcessDiedError, fork_is_safe, run_in_child

    folder: Path = args.out if args.out is not None else default_run_folder(mission.name)
    check_run_folder(folder)

    stream = sys.stderr if args.json else sys.stdout
    live = stream.isatty()
    seed = mission.seed if args.seed is None else args.seed
    title = f"{mission.name}: {mission.robot.name} in {mission.world_name}, seed {seed}"
    with sigint_flag() as interrupted:
        progress: LineProgress | LiveProgress
        if live:
            progress = LiveProgress(stream, title)
        else:
            progress = LineProgress(stream)
            stream.write(f"running {title}\n")
            stream.flush()
        if not kernels_cached(mission.robot.name):
            sys.stderr.write(
                "first run on this machine: compiling baobab's kernels "
                "(about a minute; later runs load them from the cache)\n"
            )

        def simulate(send: Callable[[RunMessage], None]) -> FinishedRun:
            """The run, in its own process: progress and warnings go to ``send``."""
            from baobab.missions.runner import run_mission

            record = run_mission(
                mission,
                seed=args.seed,
                progress=ForwardedProgress(progress, send),
                realtime=args.realtime,
                recording=recording,
                interrupted=interrupted.is_set,
                warn=lambda message: send(("warn", message)),
            )
            if args.baseline is not None:
                _baseline(record, args.baseline, baseline, lambda note: send(("note", note)))
            return FinishedRun(
                record.result_object(folder), record.trace.text(), record.plot, record.exit_code
            )

        def show(message: RunMessage) -> None:
            kind, payload = message
            if kind == "progress":
                progress.draw(payload)
            elif kind == "warn":
                _warn(payload)
            else:
                print(payload, file=sys.stderr)

        try:
            finished = run_in_child(simulate, show) if fork_is_safe() else simulate(show)
        except ChildProcessDiedError as exc:
            print(f"baobab run: {exc}; no run folder was written", file=sys.stderr)
            return EXIT_NOT_INTENDED
        finally:
            progress.close()
        write_run_folder(folder, finished.result, finished.trace_text, finished.plot)
    result = finished.result
    try:
        if args.json:
            sys.stdout.write(json.dumps(result) + "\n")
            sys.stdout.flush()
        else:
            print_summary(sys.stdout, result, rich=live)
            _print_recording(result.get("recording", {}))
            sys.stdout.flush()
    except BrokenPipeError:
        # Nobody reads stdout any more; the run folder is written. Point stdout at devnull so
        # the interpreter's last flush does not complain either.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    return finished.exit_code


RunMessage = tuple[str, Any]
"""What the run's process tells this one: ("progress", snapshot), ("warn", text), ("note", text)."""


@dataclass(frozen=True)
class FinishedRun:
    """What the run's process sends back: all the run folder and the report need."""

    result: dict[str, Any]
    trace_text: str
    plot: PlotData | None
    exit_code: int


class ForwardedProgress:
    """Sends the snapshots ``display`` would show (its ``due``) to be drawn by the parent."""

    def __init__(
        self, display: LineProgress | LiveProgress, send: Callable[[RunMessage], None]
    ) -> None:
        self.display = display
        self.send = send

    def update(self, snapshot: ProgressSnapshot) -> None:
        """Send ``snapshot`` when the display shows it."""
        if self.display.due(snapshot):
            self.send(("progress", snapshot))


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
        BaobabError: a tuning flag without the flag it tunes, a missing folder or a folder
            where a file goes, a ``--btlog`` without its suffix, ``--video`` without PyAV, a
            ``--live`` address the server could not listen on.
    """
    if not args.live and (args.host is not None or args.port is not None):
        raise BaobabError("--host and --port set up --live, which is not given")
    if args.video is None and (args.fps is not None or args.video_size is not None):
        raise BaobabError("--fps and --video-size set up --video, which is not given")
    for flag, path in (("--record", args.record), ("--video", args.video), ("--btlog", args.btlog)):
        if path is not None and not path.parent.is_dir():
            raise BaobabError(f"{flag} {path}: the folder {path.parent} does not exist")
        if path is not None and path.is_dir():
            raise BaobabError(f"{flag} {path}: is a folder; give a file name")
    if args.btlog is not None and args.btlog.suffix != ".btlog":
        raise BaobabError(f"--btlog {args.btlog}: Groot2 reads only files ending in .btlog")
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


def _warn(message: str) -> None:
    print(f"baobab run: {message}", file=sys.stderr)


def _baseline(
    record: RunRecord, path: Path, baseline: Baseline | None, note: Callable[[str], None]
) -> None:
    """Compare with the baseline, or create it from a run that turned out as intended."""
    from baobab.missions.baseline import compare, write_baseline

    if baseline is not None:
        record.add_expectations(compare(baseline, record.metrics))
        record.extra["baseline"] = {"file": str(path), "status": "compared"}
        return
    if record.intended and not record.outcome.interrupted:
        write_baseline(
            path, record.mission.name, record.seed, record.mission.params, record.metrics
        )
        record.extra["baseline"] = {"file": str(path), "status": "created"}
        note(f"baseline created: {path}")
        return
    record.extra["baseline"] = {
        "file": str(path),
        "status": "not created: the run did not turn out as intended",
    }
