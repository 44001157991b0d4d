"""One scenario test: run a mission, judge it, keep its baseline and write its run folder.

The pytest plugin (:mod:`baobab.missions.testing.pytest_plugin`) turns each mission file with an
``expect:`` block into a test item whose body is :func:`run_scenario`. The baseline lives
beside the mission (``<stem>.baseline.json``, see :mod:`baobab.missions.testing.baseline`): when it
exists it is compared and a regression beyond its tolerance makes the run "not as intended";
with ``update_baseline`` the run (re)writes it instead, if the run turned out as intended.
"""

from __future__ import annotations

import shlex
from dataclasses import dataclass
from pathlib import Path

from baobab.missions.language.loader import Mission
from baobab.missions.run.run_folder import write_run_folder
from baobab.missions.run.runner import RunRecord, run_mission
from baobab.missions.testing.baseline import compare, read_baseline, write_baseline
from baobab.missions.testing.expectation_table import expectation_table
from baobab.sim.errors import BaobabError

BASELINE_SUFFIX = ".baseline.json"


class ScenarioFailedError(BaobabError):
    """A scenario ran but did not turn out as intended; the message is the full report."""

    def __init__(self, scenario: ScenarioRun) -> None:
        self.scenario = scenario
        super().__init__(scenario.report())


def baseline_path(mission_file: Path) -> Path:
    """``missions/patrol.yaml`` -> ``missions/patrol.baseline.json``."""
    return mission_file.with_name(mission_file.stem + BASELINE_SUFFIX)


@dataclass(frozen=True)
class ScenarioRun:
    """A finished scenario.

    Attributes:
        record: the run.
        folder: its run folder (written).
        baseline: the baseline file beside the mission.
        baseline_status: ``none``, ``compared``, ``written`` or why it was not written.
    """

    record: RunRecord
    folder: Path
    baseline: Path
    baseline_status: str

    @property
    def intended(self) -> bool:
        """Every expectation (and baseline comparison) held."""
        return self.record.intended

    def report(self) -> str:
        """The failure report: what happened, the expectations table, where to look."""
        record = self.record
        outcome = record.outcome
        mission = record.mission
        error = f" {outcome.error_name} ({outcome.error_code})" if outcome.error_code else ""
        message = f": {outcome.error_msg}" if outcome.error_msg else ""
        path = shown_path(mission.path)
        lines = [
            f"mission '{mission.name}' ({path}, seed {record.seed}) did not turn out as intended",
            f"ended {outcome.result}{error} after {outcome.sim_time:.1f} s of sim time{message}",
            "",
        ]
        if record.expectations:
            lines.append(expectation_table(record.expectations))
        else:
            lines.append("no expect: entries; a run without them must end SUCCEEDED")
        lines += [
            "",
            f"baseline: {self._baseline_line()}",
            f"run folder: {self.folder}",
            f"replay: baobab run {shlex.quote(str(path))} --seed {record.seed}",
        ]
        return "\n".join(lines)

    def _baseline_line(self) -> str:
        shown = shown_path(self.baseline)
        if self.baseline_status == "none":
            return f"none ({shown} is written by pytest --baobab-update-baseline)"
        if self.baseline_status == "compared":
            return f"compared with {shown}"
        if self.baseline_status == "written":
            return f"written to {shown}"
        return f"{shown}: {self.baseline_status}"


def shown_path(path: Path) -> Path:
    """``path`` relative to the working directory when inside it, else as it is."""
    try:
        return path.resolve().relative_to(Path.cwd())
    except ValueError:
        return path


def run_scenario(
    mission: Mission,
    *,
    seed: int | None,
    update_baseline: bool,
    folder: Path,
    plots: str = "failed",
) -> ScenarioRun:
    """Run ``mission`` (with ``seed`` if given), handle its baseline, write ``folder``.

    ``plots`` says when the folder gets its ``plot.png``: ``failed`` (the scenario did not
    turn out as intended), ``all`` or ``none``.

    Raises:
        BaselineError: the baseline beside the mission cannot be read (before the run).
        MissionError: a mission problem found only when the robot is built.
        RunFolderError: ``folder`` exists and is not empty.
    """
    path = baseline_path(mission.path)
    baseline = None if update_baseline else read_baseline(path, mission.name)
    record = run_mission(mission, seed=seed)
    if baseline is not None:
        record.add_expectations(compare(baseline, record.metrics))
        status = "compared"
    elif not update_baseline:
        status = "none"
    elif record.intended:
        write_baseline(path, mission.name, record.seed, mission.params, record.metrics)
        status = "written"
    else:
        status = "not written: the run did not turn out as intended"
    record.extra["baseline"] = {"file": str(path), "status": status}
    drawn = plots == "all" or (plots == "failed" and not record.intended)
    plot = record.plot if drawn else None
    write_run_folder(folder, record.result_object(folder), record.trace.text(), plot)
    return ScenarioRun(record, folder, path, status)
