"""Run a campaign: dispatch its runs to an executor, record each row as it finishes.

At most :meth:`~baobab.missions.campaigns.executors.CampaignExecutor.slots` runs are in flight; the
next is submitted when one finishes, so nothing waits in a queue that a Ctrl-C would have to
drain. Each finished run's row is written to the results table at once, with its replay
command (and, for a run with a mission variant, the variant file it names).

Interruption, polled between runs (:class:`Interruption`): the first SIGINT stops dispatching
and lets the runs in flight finish (their rows are kept); a second one aborts them (their
rows are dropped); a third raises KeyboardInterrupt.

Python API (the CLI is :mod:`baobab.missions.cli.campaign_command`)::

    spec = build_spec(mission, path, text, {}, ["start.x=uniform(-0.1,0.1)"], [], 8, 0)
    executor = LocalExecutor(2)
    table = ResultsTable(results_path(folder))
    try:
        run_campaign(spec, executor, table, replay_target(spec, str(path), folder))
    finally:
        table.close()
        executor.close()
    rows = read_rows(results_path(folder))
"""

from __future__ import annotations

import shlex
import shutil
import signal
import threading
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, CancelledError, Future, wait
from contextlib import contextmanager
from dataclasses import dataclass
from datetime import UTC, datetime
from importlib import resources
from pathlib import Path
from types import FrameType
from typing import Any

from baobab.missions.campaigns.executors import ERROR, CampaignExecutor, RunOutcome, failed_row
from baobab.missions.campaigns.results import RESULTS_FILE, ResultsTable
from baobab.missions.campaigns.spec import CampaignSpec, RunTask
from baobab.missions.campaigns.variant import REPLAY_SCHEMA

POLL_PERIOD = 0.2
"""How often the loop looks for a Ctrl-C while runs are in flight (s, wall clock)."""
WORKER_ATTEMPTS = 2
"""Tries of a run whose worker process dies under it (a crash takes its neighbours in a
process pool down too; they deserve another go, the culprit fails twice)."""
RowSink = Callable[[dict[str, Any]], None]


class Interruption:
    """Counts SIGINTs: ``stopping`` after the first, ``aborting`` after the second."""

    def __init__(self) -> None:
        self.count = 0

    @property
    def stopping(self) -> bool:
        """Dispatch no more runs."""
        return self.count >= 1

    @property
    def aborting(self) -> bool:
        """Stop the runs in flight too."""
        return self.count >= 2

    def signal(self) -> None:
        """One more SIGINT; the third raises KeyboardInterrupt."""
        self.count += 1
        if self.count >= 3:
            raise KeyboardInterrupt


@contextmanager
def catch_sigint(interruption: Interruption) -> Iterator[Interruption]:
    """Count SIGINTs into ``interruption`` while inside (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield interruption
        return

    def handler(_signum: int, _frame: FrameType | None) -> None:
        interruption.signal()

    previous = signal.signal(signal.SIGINT, handler)
    try:
        yield interruption
    finally:
        signal.signal(signal.SIGINT, previous)


@dataclass(frozen=True)
class ReplayTarget:
    """How replay commands name the mission: as the user wrote it, and its world file.

    Attributes:
        mission: MISSION as given on the command line (a path or a bundled name).
        folder: the campaign folder as given (variant files go below it).
        world_file: the mission's world file relative to the mission's folder, if it names
            one (copied next to the variant files, which need it there).
        mission_folder: the mission file's folder.
    """

    mission: str
    folder: Path
    world_file: str | None
    mission_folder: Path

    def command(self, task: RunTask, *, variant: bool) -> str:
        """``baobab run MISSION --seed S --set KEY=VALUE ...`` reproducing ``task``.

        Args:
            task: the run.
            variant: the run has a variant file (else the mission file: a run whose ``--set``
                values failed before its variant was made replays from the file).
        """
        target = str(self.folder / task.variant_label) if variant else self.mission
        words = ["baobab", "run", target, "--seed", str(task.seed)]
        for key, value in task.overrides.items():
            words += ["--set", f"{key}={value}"]
        return shlex.join(words)

    def write_variant(self, task: RunTask, text: str) -> Path:
        """Write the variant file of ``task`` (and, once, the world file it needs and the
        schema its editor comment names)."""
        path = self.folder / task.variant_label
        path.parent.mkdir(parents=True, exist_ok=True)
        schema = path.parent / REPLAY_SCHEMA
        if not schema.exists():
            shutil.copyfile(Path(str(resources.files("baobab.missions") / REPLAY_SCHEMA)), schema)
        if self.world_file is not None:
            world_copy = path.parent / self.world_file
            if not world_copy.exists():
                world_copy.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(self.mission_folder / self.world_file, world_copy)
        path.write_text(text, encoding="utf-8")
        return path


def replay_target(spec: CampaignSpec, mission_argument: str, folder: Path) -> ReplayTarget:
    """The :class:`ReplayTarget` of a campaign (its world file, when it names one)."""
    written = spec.mission.document.data.get("world")
    is_file = isinstance(written, str) and (
        "/" in written or "\\" in written or written.endswith((".yaml", ".yml"))
    )
    world_file = written if is_file else None
    return ReplayTarget(mission_argument, folder, world_file, spec.mission_path.parent)


def run_campaign(
    spec: CampaignSpec,
    executor: CampaignExecutor,
    table: ResultsTable,
    replay: ReplayTarget,
    *,
    on_row: RowSink | None = None,
    interruption: Interruption | None = None,
    notify: Callable[[str], None] | None = None,
) -> int:
    """Run every task of ``spec`` on ``executor``; returns the number of rows written.

    Args:
        spec: the campaign.
        executor: where runs go.
        table: where each finished run's row goes, at once.
        replay: names the replay commands and writes variant files.
        on_row: told each row after it is written (progress).
        interruption: polled between runs (see the module docstring).
        notify: told what an interruption does, for people.
    """
    interruption = interruption or Interruption()
    tell = notify or _quiet
    tasks = spec.tasks()
    in_flight: dict[Future[RunOutcome], tuple[RunTask, int]] = {}
    stopped = aborted = False
    written = 0
    while True:
        while not interruption.stopping and len(in_flight) < executor.slots():
            task = next(tasks, None)
            if task is None:
                break
            in_flight[executor.submit(task)] = (task, 1)
        if not in_flight:
            return written
        if interruption.stopping and not stopped:
            stopped = True
            tell(
                f"interrupted: no more runs; waiting for the {len(in_flight)} in flight "
                "(Ctrl-C again stops them)"
            )
        if interruption.aborting and not aborted:
            aborted = True
            tell(f"stopping the {len(in_flight)} runs in flight (their rows are dropped)")
            executor.abort()
        done, _ = wait(in_flight, timeout=POLL_PERIOD, return_when=FIRST_COMPLETED)
        for future in done:
            task, attempt = in_flight.pop(future)
            try:
                outcome = future.result()
            except CancelledError:
                continue
            except Exception as exc:  # the worker died (not the run: execute_run catches that)
                if aborted:
                    continue
                if attempt < WORKER_ATTEMPTS and not interruption.stopping:
                    in_flight[executor.submit(task)] = (task, attempt + 1)
                    continue
                outcome = _worker_failed(task, exc)
            if outcome.interrupted:
                continue
            row = _finish_row(outcome, task, replay)
            table.add(row)
            written += 1
            if on_row is not None:
                on_row(row)


def _quiet(_message: str) -> None:
    """Tell nobody."""


def _worker_failed(task: RunTask, exc: Exception) -> RunOutcome:
    """An ERROR row for a run whose worker failed every attempt."""
    detail = f"{type(exc).__name__}: {exc}" if str(exc) else type(exc).__name__
    row = failed_row(task, ERROR, "WORKER_FAILED", f"{detail} ({WORKER_ATTEMPTS} attempts)")
    row["wall_time"] = 0.0
    return RunOutcome(row, None)


def _finish_row(outcome: RunOutcome, task: RunTask, replay: ReplayTarget) -> dict[str, Any]:
    if outcome.variant_text is not None:
        replay.write_variant(task, outcome.variant_text)
    finished = datetime.now(UTC).isoformat(timespec="milliseconds")
    command = replay.command(task, variant=outcome.variant_text is not None)
    return {**outcome.row, "replay": command, "finished_at": finished}


def results_path(folder: Path) -> Path:
    """The results table of a campaign folder."""
    return folder / RESULTS_FILE
