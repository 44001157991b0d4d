r"""``baobab run``'s run as a job in a process of its own, and saving what it sends back.

The job (:func:`simulate`, on a :class:`RunRequest`) runs the mission and, with
``--baseline``, compares or creates the baseline; it sends its progress, warnings and notes to
the parent as :data:`RunMessage`\ s and ends with a :class:`FinishedRun`, which
:func:`save_run` writes to the run folder (or a fallback folder). The run's process is forked
before the mission is loaded and loads the simulation stack meanwhile
(:func:`prepare_run_process`); the request, plain data, reaches it through a pipe.
"""

from __future__ import annotations

import contextlib
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from baobab.missions.cli.interrupts import RunSignals
from baobab.missions.language.loader import Mission
from baobab.missions.run.exit_codes import EXIT_NOT_SAVED
from baobab.missions.run.recording_hook import RecordingOptions

if TYPE_CHECKING:
    from baobab.missions.run.plot_data import PlotData
    from baobab.missions.run.progress_display import (
        LineProgress,
        LiveProgress,
        ProgressSchedule,
        ProgressSnapshot,
    )
    from baobab.missions.run.runner import RunRecord
    from baobab.missions.testing.baseline import Baseline


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
    """Sends the snapshots the parent's display would show (its schedule says) to be drawn."""

    def __init__(self, schedule: ProgressSchedule, send: Callable[[RunMessage], None]) -> None:
        self.schedule = schedule
        self.send = send

    def update(self, snapshot: ProgressSnapshot) -> None:
        """Send ``snapshot`` when the display shows it."""
        if self.schedule.due(snapshot):
            self.send(("progress", snapshot))


@dataclass(frozen=True)
class RunRequest:
    """What the run needs, as plain data: it travels to a process forked before it was known.

    Attributes:
        mission: the loaded mission.
        seed: ``--seed``, or None for the mission's.
        realtime: ``--realtime``.
        recording: the recording flags, checked.
        baseline_file: ``--baseline``, or None.
        baseline: the baseline read from it, or None when it is to be created.
        folder: the run folder (claimed by the parent).
        schedule: which progress snapshots the parent's display shows.
    """

    mission: Mission
    seed: int | None
    realtime: bool
    recording: RecordingOptions
    baseline_file: Path | None
    baseline: Baseline | None
    folder: Path
    schedule: ProgressSchedule


def simulate(
    request: RunRequest, signals: RunSignals, send: Callable[[RunMessage], None]
) -> FinishedRun:
    """The run: progress and warnings go to ``send``; ``signals`` cancel it."""
    from baobab.missions.run.runner import run_mission

    record = run_mission(
        request.mission,
        seed=request.seed,
        progress=ForwardedProgress(request.schedule, send),
        realtime=request.realtime,
        recording=request.recording,
        interrupted=signals.reason,
        warn=lambda message: send(("warn", message)),
    )
    if request.baseline_file is not None:
        note = lambda text: send(("note", text))  # noqa: E731
        _baseline(record, request.baseline_file, request.baseline, note)
    exit_code = signals.exit_code(record.exit_code)
    trace = record.trace.text()
    return FinishedRun(record.result_object(request.folder), trace, record.plot, exit_code)


def simulate_in_child(request: RunRequest, send: Callable[[RunMessage], None]) -> FinishedRun:
    """The run in the process :func:`~baobab.missions.run.child_process.start_child` forked:
    its own handlers for the signals the parent forwards first, then the run."""
    from baobab.missions.run.child_process import handle_forwarded_signals

    signals = RunSignals()
    with signals.installed():
        handle_forwarded_signals()
        return simulate(request, signals, send)


def prepare_run_process() -> None:
    """What a run's process loads before it knows its mission: the run's modules (MuJoCo,
    py_trees, numba) and the compiled control dispatcher every robot uses."""
    import baobab.missions.run.runner  # noqa: F401  (imported for its cost, now)
    from baobab.sim.native_control import load_dispatcher

    load_dispatcher()


def shower(progress: LineProgress | LiveProgress) -> Callable[[RunMessage], None]:
    """Shows what the run's process sends: progress, warnings, notes."""

    def show(message: RunMessage) -> None:
        kind, payload = message
        if kind == "progress":
            progress.draw(payload)
        elif kind == "warn":
            warn(payload)
        else:
            print(payload, file=sys.stderr)

    return show


def save_run(folder: Path, finished: FinishedRun) -> Path | None:
    """Write the run folder; where that fails, into a fallback folder the message names.

    Returns:
        Where the folder was written, or None when nowhere (said on stderr); the result's
        ``run_folder`` says the same.
    """
    from baobab.missions.run.run_folder import RunFolderError, write_run_folder

    result = finished.result
    try:
        return write_run_folder(folder, result, finished.trace_text, finished.plot)
    except RunFolderError as error:  # something else wrote into it meanwhile
        first = f"could not write the run folder: {error}"
    except OSError as error:
        first = f"could not write the run folder {folder}: {error.strerror or error}"
    fallback: Path | None = None
    try:
        fallback = Path(tempfile.mkdtemp(prefix=f"baobab-{folder.name or 'run'}-"))
        result["run_folder"] = str(fallback)
        write_run_folder(fallback, result, finished.trace_text, finished.plot)
    except OSError as error:
        result["run_folder"] = None
        if fallback is not None:
            with contextlib.suppress(OSError):
                fallback.rmdir()
        place = tempfile.gettempdir() if fallback is None else fallback.parent
        warn(
            f"{first}; nor a fallback folder in {place}: {error.strerror or error}; "
            f"the run is not saved (exit {EXIT_NOT_SAVED})"
        )
        return None
    warn(f"{first}; written to {fallback} instead")
    return fallback


def _baseline(
    record: RunRecord, path: Path, baseline: Baseline | None, note: Callable[[str], None]
) -> None:
    """Compare with the baseline, or create it from a run that turned out as intended."""
    from baobab.missions.testing.baseline import compare, write_baseline

    if baseline is not None:
        record.add_expectations(compare(baseline, record.metrics))
        record.extra["baseline"] = {"file": str(path), "status": "compared"}
        return
    if record.intended and not record.outcome.interrupted:
        try:
            write_baseline(
                path, record.mission.name, record.seed, record.mission.params, record.metrics
            )
        except OSError as error:  # the disk filled or turned read-only during the run
            status = f"not created: {error.strerror or error}"
            note(f"baobab run: --baseline {path}: {status}")
        else:
            status = "created"
            note(f"baseline created: {path}")
        record.extra["baseline"] = {"file": str(path), "status": status}
        return
    record.extra["baseline"] = {
        "file": str(path),
        "status": "not created: the run did not turn out as intended",
    }


def warn(message: str) -> None:
    """Tell the user on standard error, as ``baobab run: <message>``."""
    print(f"baobab run: {message}", file=sys.stderr)
