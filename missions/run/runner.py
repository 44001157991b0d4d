"""Run a mission: build its robot, compile its tree, loop, measure, judge.

:func:`run_mission` is the one entry point the CLI, pytest scenario tests and campaigns share::

    mission = load_mission("missions/walls_go_to_goal.yaml")
    record = run_mission(mission)
    record.result_object()["result"]      # "SUCCEEDED"
    record.exit_code                      # 0: turned out as intended

It returns a :class:`RunRecord`: how the run ended, the metrics, the evaluated expectations,
the trace (with its digest) and the plot data. Writing the run folder is separate
(:func:`~baobab.missions.run.run_folder.write_run_folder`), so tests and campaigns choose.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import py_trees

from baobab.missions.language.compiler import compile_mission
from baobab.missions.language.loader import Mission
from baobab.missions.run.events import TimedEvents
from baobab.missions.run.exit_codes import EXIT_INTERRUPTED, EXIT_NOT_INTENDED, EXIT_OK
from baobab.missions.run.expectations import (
    ExpectationResult,
    RunEnd,
    all_passed,
    check_metric_names,
    evaluate,
)
from baobab.missions.run.fault_monitors import fault_monitors
from baobab.missions.run.faults import fault_injector
from baobab.missions.run.metrics import MetricValue
from baobab.missions.run.plot_data import PlotData
from baobab.missions.run.recording_hook import RecordingHook, RecordingOptions
from baobab.missions.run.rig import Rig, build_rig
from baobab.missions.run.tick_loop import LoopOutcome, MissionErrorCode, ProgressSink, RunLoop
from baobab.missions.run.trace import Trace, jsonable
from baobab.sim.viewer import RealTimePacer

__all__ = [
    "MissionErrorCode",
    "RecordingOptions",
    "RunRecord",
    "run_mission",
]


@dataclass
class RunRecord:
    """Everything a finished run produced.

    Attributes:
        mission: the mission that ran.
        seed: the seed it ran with.
        outcome: how the loop ended.
        metrics: every metric's value.
        expectations: the evaluated ``expect:`` block, then any added later (baselines).
        trace: the trace records and their digest.
        plot: what the run's plot shows.
        wall_time: wall-clock duration of the loop (s).
        extra: additional top-level fields for the result object (e.g. ``baseline``).
    """

    mission: Mission
    seed: int
    outcome: LoopOutcome
    metrics: dict[str, MetricValue]
    expectations: list[ExpectationResult]
    trace: Trace
    plot: PlotData
    wall_time: float
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def intended(self) -> bool:
        """With an ``expect:`` block every expectation held; without, the run SUCCEEDED.

        Expectations added later (``baseline.*``) must hold in both cases.
        """
        if self.mission.expect is None and self.outcome.result != "SUCCEEDED":
            return False
        return all_passed(self.expectations)

    @property
    def exit_code(self) -> int:
        """130 when interrupted, else 0 when the run turned out as intended, else 1."""
        if self.outcome.interrupted:
            return EXIT_INTERRUPTED
        return EXIT_OK if self.intended else EXIT_NOT_INTENDED

    @property
    def trace_digest(self) -> str:
        """SHA-256 of the deterministic trace."""
        return self.trace.digest

    def add_expectations(self, results: list[ExpectationResult]) -> None:
        """Append more checked expectations (they count towards :attr:`intended`)."""
        self.expectations.extend(results)

    def result_object(self, run_folder: Path | None = None) -> dict[str, Any]:
        """The JSON result (``result.json`` and ``--json``)."""
        mission = self.mission
        outcome = self.outcome
        world = Path(mission.world_name).name if "/" in mission.world_name else mission.world_name
        speedup = outcome.sim_time / self.wall_time if self.wall_time > 0 else None
        return {
            "mission": mission.name,
            "mission_file": str(mission.path),
            "robot": mission.robot.name,
            "world": world,
            "seed": self.seed,
            "params": jsonable(mission.params, None),
            "result": outcome.result,
            "error_code": outcome.error_code,
            "error_name": outcome.error_name,
            "error_msg": outcome.error_msg,
            "sim_time": round(outcome.sim_time, 6),
            "wall_time": round(self.wall_time, 3),
            "speedup": None if speedup is None else round(speedup, 1),
            "intended": self.intended,
            "exit_code": self.exit_code,
            "metrics": jsonable(self.metrics),
            "expectations": [jsonable(result.as_dict()) for result in self.expectations],
            "trace_digest": self.trace.digest,
            "run_folder": None if run_folder is None else str(run_folder),
            **self.extra,
        }


def run_mission(
    mission: Mission,
    *,
    seed: int | None = None,
    progress: ProgressSink | None = None,
    realtime: bool = False,
    viewer: bool = False,
    recording: RecordingOptions | None = None,
    interrupted: Callable[[], bool | str | None] | None = None,
    warn: Callable[[str], None] | None = None,
) -> RunRecord:
    """Run ``mission`` headless and deterministic, and judge it.

    Args:
        mission: from :func:`~baobab.missions.language.loader.load_mission`.
        seed: overrides the mission's seed.
        progress: receives a snapshot after every tick.
        realtime: pace the sim to the wall clock.
        viewer: show MuJoCo's passive viewer, paced to the wall clock; without a display,
            ``warn`` is told and the run goes on headless.
        recording: record to MCAP, serve live to Foxglove, film, log the tree for Groot2
            (see :class:`~baobab.missions.run.recording_hook.RecordingHook`); recording only
            reads the simulation, so the trace digest does not change.
        interrupted: polled every tick; a true value ends the run as CANCELED (see RunLoop).
        warn: receives warnings for people (default: dropped).

    Raises:
        MissionError: an ``expect: metrics:`` name this run does not measure, or a capability
            the tree needs that the robot lacks (located, before anything runs).
        BaobabError: the robot or the world cannot be built, or a recording cannot be
            started (file, port, OpenGL).
    """
    run_seed = mission.seed if seed is None else seed
    rig = build_rig(mission, run_seed)
    check_metric_names(mission, rig.metrics.number_names(), rig.metrics.names())
    compiled = compile_mission(mission, rig.capabilities)
    trace = _started_trace(mission, rig, run_seed)
    events = TimedEvents(
        mission.events, rig.obstacles, rig.teleop, fault_injector(rig), ros=rig.ros
    )
    options = recording or RecordingOptions()
    if viewer:
        options = replace(options, viewer=True)
    hook = RecordingHook(options, rig, compiled, warn=warn or _drop) if options.enabled else None
    pacer = RealTimePacer() if realtime or (hook is not None and hook.needs_pacing) else None
    loop = RunLoop(
        compiled,
        rig,
        trace,
        events,
        mission.timeout,
        progress=progress,
        pacer=pacer,
        interrupted=interrupted,
        on_tick=None if hook is None else hook.after_tick,
        faults=fault_monitors(rig),
    )
    started = time.perf_counter()
    try:
        outcome = loop.run()
    finally:
        if rig.ros is not None:
            rig.ros.close()
        if hook is not None:
            hook.close()
        # py_trees' blackboard is process-global: nothing a run wrote reaches the next one.
        py_trees.blackboard.Blackboard.clear()
    wall_time = time.perf_counter() - started
    record = _judged(mission, run_seed, rig, outcome, trace, wall_time)
    outputs = {} if hook is None else hook.outputs()
    if outputs:
        record.extra["recording"] = outputs
    return record


def _started_trace(mission: Mission, rig: Rig, seed: int) -> Trace:
    """A trace that begins with the run's ``start`` record."""
    trace = Trace()
    trace.add(
        rig.sim.time,
        "start",
        mission=mission.name,
        robot=mission.robot.name,
        seed=seed,
        params=mission.params,
        timeout=mission.timeout,
    )
    return trace


def _judged(
    mission: Mission, seed: int, rig: Rig, outcome: LoopOutcome, trace: Trace, wall_time: float
) -> RunRecord:
    """The record of a finished run: its metrics read, its ``expect:`` block evaluated."""
    metrics = rig.metrics.values()
    end = RunEnd(outcome.result, outcome.error_code, outcome.error_name, outcome.sim_time)
    expectations = evaluate(mission.expect, end, metrics, mission)
    plot = rig.plot_data(_title(mission, seed, outcome))
    return RunRecord(mission, seed, outcome, metrics, expectations, trace, plot, wall_time)


def _drop(_message: str) -> None:
    """Ignore a warning."""


def _title(mission: Mission, seed: int, outcome: LoopOutcome) -> str:
    error = f" {outcome.error_name}" if outcome.error_code else ""
    return (
        f"{mission.name} ({mission.robot.name}, seed {seed}): {outcome.result}{error} "
        f"after {outcome.sim_time:.1f} s"
    )
