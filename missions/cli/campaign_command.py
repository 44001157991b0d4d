"""``baobab campaign``: check the input, run the campaign, summarise, choose the exit code.

Order of work, so that invalid input exits 2 with nothing written: the options, the mission
(a path or a bundled name) with its ``--set`` values, every ``--vary``/``--grid`` against it,
the campaign folder (``campaigns/<mission>-<UTC>/`` or ``--out``, new or empty), the executor
(``--scheduler`` needs dask.distributed and a reachable scheduler); only then the runs.

The folder ends with ``results.sqlite`` (one row per finished run, see
:mod:`~baobab.missions.campaigns.results`), ``summary.json``, ``outcomes.png`` and, when runs
change more than parameters, ``replay/run-NNNN.yaml`` (each such run's mission variant).

Exit codes: 0 when every run went as intended, 1 otherwise, 2 for invalid input, 130 after
SIGINT (dispatch stops, runs in flight finish and are kept, the summary covers what
finished; a second SIGINT stops the runs in flight and drops them).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections.abc import Mapping
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

from baobab.missions.campaigns.results import (
    CampaignSummary,
    ResultsTable,
    read_rows,
    wilson_interval,
    write_summary,
)
from baobab.missions.campaigns.spec import CampaignSpec, build_spec
from baobab.missions.campaigns.vary import CampaignError
from baobab.missions.cli.arguments import add_set, positive_int
from baobab.missions.language.bundled_missions import resolve_mission
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.missions.run.exit_codes import EXIT_INTERRUPTED, EXIT_NOT_INTENDED, EXIT_OK
from baobab.missions.run.run_folder import check_run_folder, default_run_folder
from baobab.sim.yaml_source import read_yaml_text

if TYPE_CHECKING:
    from baobab.missions.campaigns.executors import CampaignExecutor

# What runs the campaign (the executors, and through them the whole simulation stack) and
# plots it is imported once the input is checked, so a mistake is refused in well under a
# second.

CAMPAIGNS_ROOT = Path("campaigns")


def configure_campaign(parser: argparse.ArgumentParser) -> None:
    """The arguments of ``baobab campaign``."""
    parser.add_argument(
        "mission", metavar="MISSION", help="a mission file, or the name of a bundled mission"
    )
    parser.add_argument(
        "--runs",
        type=positive_int,
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
    add_set(parser)
    parser.add_argument(
        "--seed",
        type=int,
        help="campaign seed; each run's seed derives from it (default: mission's)",
    )
    parser.add_argument(
        "--workers", type=positive_int, help="local worker processes (default: one per core)"
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


def campaign_command(args: argparse.Namespace, overrides: Mapping[str, str]) -> int:
    """The ``campaign`` handler; returns the exit code (BaobabError means invalid input)."""
    if args.workers is not None and args.scheduler is not None:
        raise CampaignError("give --workers or --scheduler, not both")
    path = resolve_mission(args.mission)
    text = read_yaml_text(path, MissionError)
    mission = load_mission(path, overrides, text=text)
    seed = mission.seed if args.seed is None else args.seed
    spec = build_spec(mission, path, text, overrides, args.vary, args.grid, args.runs, seed)
    folder: Path = (
        args.out if args.out is not None else default_run_folder(mission.name, root=CAMPAIGNS_ROOT)
    )
    check_run_folder(folder)
    from baobab.missions.campaigns.dispatch import (
        Interruption,
        catch_sigint,
        replay_target,
        results_path,
        run_campaign,
    )

    executor = open_executor(args.workers, args.scheduler, spec)
    interruption = Interruption()
    stream = sys.stderr if args.json else sys.stdout
    title = (
        f"{mission.name}: {spec.total_runs} runs on {executor.description}, campaign seed {seed}"
    )
    started = time.perf_counter()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        table = ResultsTable(results_path(folder))
        progress = make_progress(stream, title, spec.total_runs)
        try:
            with catch_sigint(interruption):
                run_campaign(
                    spec,
                    executor,
                    table,
                    replay_target(spec, args.mission, folder),
                    on_row=progress.row,
                    interruption=interruption,
                    notify=progress.note,
                )
        finally:
            progress.close()
            table.close()
    finally:
        executor.close()
    summary = summarise(spec, folder, interruption.stopping, executor.description)
    summary.extra["wall_time"] = round(time.perf_counter() - started, 3)
    exit_code = _exit_code(summary)
    result = {**summary.as_json(), "exit_code": exit_code}
    write_summary(folder, result)
    if args.json:
        sys.stdout.write(json.dumps(result) + "\n")
        sys.stdout.flush()
    else:
        sys.stdout.write(describe_summary(result))
        sys.stdout.flush()
    return exit_code


def open_executor(
    workers: int | None, scheduler: str | None, spec: CampaignSpec
) -> CampaignExecutor:
    """A Dask executor for ``--scheduler``, else a local pool (default: one worker per core).

    Raises:
        CampaignError: a bad ``--workers``, dask missing, or an unreachable scheduler.
    """
    from baobab.missions.campaigns.executors import DaskExecutor, LocalExecutor, preload_modules

    if scheduler is not None:
        return DaskExecutor(scheduler)
    if workers is None:
        workers = max(1, min(_cores(), spec.total_runs))
    return LocalExecutor(workers, preload_modules(spec.mission))


def _cores() -> int:
    affinity = getattr(os, "sched_getaffinity", None)
    return len(affinity(0)) if affinity is not None else os.cpu_count() or 1


def summarise(
    spec: CampaignSpec, folder: Path, interrupted: bool, executor: str
) -> CampaignSummary:
    """The summary of the rows in ``folder``'s table; draws ``outcomes.png``."""
    from baobab.missions.campaigns.dispatch import results_path
    from baobab.missions.campaigns.outcomes_plot import PLOT_FILE, save_campaign_plot

    results = results_path(folder)
    rows = read_rows(results)
    summary = CampaignSummary(spec.mission.name, spec.total_runs, rows, interrupted)
    low, high = wilson_interval(summary.successes, summary.runs)
    title = (
        f"{spec.mission.name}: {summary.successes}/{summary.runs} as intended "
        f"(95% CI {100 * low:.0f}-{100 * high:.0f}%), campaign seed {spec.seed}"
    )
    plot = save_campaign_plot(rows, spec.keys, title, folder / PLOT_FILE)
    summary.extra.update(
        {
            "campaign_seed": spec.seed,
            "varied": list(spec.keys),
            "executor": executor,
            "folder": str(folder),
            "results": str(results),
            "plot": None if plot is None else str(plot),
        }
    )
    return summary


def _exit_code(summary: CampaignSummary) -> int:
    if summary.interrupted:
        return EXIT_INTERRUPTED
    return EXIT_OK if summary.all_intended else EXIT_NOT_INTENDED


def describe_summary(result: Mapping[str, Any]) -> str:
    """The closing text of a campaign (without ``--json``)."""
    runs = result["runs"]
    lines = [
        f"{result['mission']}: {runs} of {result['planned']} runs"
        + (" (interrupted)" if result["interrupted"] else "")
        + f" in {result['wall_time']:.1f} s on {result['executor']}",
    ]
    if runs:
        low, high = result["success_ci95"]
        lines.append(
            f"as intended: {result['successes']}/{runs} = {100 * result['success_rate']:.1f}% "
            f"(95% CI {100 * low:.1f}%-{100 * high:.1f}%)"
        )
    for name, unit in (("sim_time", "s"), ("path_length", "m")):
        spread = result[name]
        if spread["p50"] is not None:
            label = name.replace("_", " ")
            lines.append(f"{label}: p50 {spread['p50']:.2f} {unit}, p95 {spread['p95']:.2f} {unit}")
    failures = {failure["run"]: failure for failure in result["failures"]}
    if failures:
        lines.append("failures:")
    for group in result["failure_groups"]:
        lines.append(f"  {group['group']} ({group['count']})")
        for run in group["runs"]:
            lines.append(f"    run {run}: {failures[run]['replay']}")
    lines.append(f"results: {result['results']}")
    if result["plot"] is not None:
        lines.append(f"plot: {result['plot']}")
    return "\n".join(lines) + "\n"


# --- progress -------------------------------------------------------------------------------


def describe_row(row: Mapping[str, Any]) -> str:
    """``run 3: SUCCEEDED, 12.4 s sim (seed 123; goal=goal_open)``."""
    outcome = row["result"]
    if row["error_code"] or row["result"] in ("INVALID", "ERROR"):
        outcome += f" {row['error_name']}"
    if row["result"] == "SUCCEEDED" and not row["intended"]:
        outcome += " (expectations failed)"
    sim = f", {row['sim_time']:.1f} s sim" if row["sim_time"] is not None else ""
    values = "; ".join(f"{key}={value}" for key, value in row["params"].items())
    return f"run {row['run']}: {outcome}{sim} (seed {row['seed']}{'; ' if values else ''}{values})"


class LineCampaignProgress:
    """One line per finished run, for logs and pipes."""

    def __init__(self, stream: IO[str], title: str, total: int) -> None:
        self.stream = stream
        self.total = total
        self.done = 0
        stream.write(f"campaign {title}\n")
        stream.flush()

    def row(self, row: Mapping[str, Any]) -> None:
        """Report a finished run."""
        self.done += 1
        self.stream.write(f"[{self.done}/{self.total}] {describe_row(row)}\n")
        self.stream.flush()

    def note(self, message: str) -> None:
        """Write a message for people."""
        self.stream.write(f"{message}\n")
        self.stream.flush()

    def close(self) -> None:
        """Nothing to tidy up."""


class LiveCampaignProgress:
    """A rich progress bar with counts and ETA, on a terminal."""

    def __init__(self, stream: IO[str], title: str, total: int) -> None:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.console = Console(file=stream)
        self.console.print(title)
        self._progress = Progress(
            TextColumn("[bold]campaign"),
            BarColumn(),
            MofNCompleteColumn(),
            TextColumn("[green]{task.fields[ok]} ok[/] [red]{task.fields[failed]} failed[/]"),
            TimeElapsedColumn(),
            TextColumn("ETA"),
            TimeRemainingColumn(),
            console=self.console,
        )
        self._task = self._progress.add_task("runs", total=total, ok=0, failed=0)
        self._ok = 0
        self._failed = 0
        self._progress.start()

    def row(self, row: Mapping[str, Any]) -> None:
        """Advance the bar; print failed runs above it."""
        from rich.text import Text

        if row["intended"]:
            self._ok += 1
        else:
            self._failed += 1
            self._progress.console.print(Text(describe_row(row), style="red"))
        self._progress.update(self._task, advance=1, ok=self._ok, failed=self._failed)

    def note(self, message: str) -> None:
        """Print a message above the bar."""
        from rich.text import Text

        self._progress.console.print(Text(message, style="yellow"))

    def close(self) -> None:
        """Stop redrawing."""
        self._progress.stop()


def make_progress(
    stream: IO[str], title: str, total: int
) -> LineCampaignProgress | LiveCampaignProgress:
    """A rich bar on a terminal, plain lines otherwise."""
    if stream.isatty():
        return LiveCampaignProgress(stream, title, total)
    return LineCampaignProgress(stream, title, total)
