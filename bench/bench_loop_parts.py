"""Where a mission's loop spends its wall time, per physics step (us), part by part.

Run: ``python bench/bench_loop_parts.py [MISSION ...]`` (default ``cafe_delivery``). Each
mission runs once to warm the compiled kernels' caches, then ``--runs`` times measured (the
best run is shown). Every periodic callback (:meth:`Simulation.every`), every ``mj_step`` batch
and the hot methods of the navigation tick, the run loop and its recording are wrapped in a
wall-clock timer; a part's figure is its *self* time (time inside it minus the timed parts it
called), so the rows add up to the loop's wall time. Figures are per physics step (us; the
cafe's robot steps at 200 Hz, so 1 us per step is 0.2 ms per sim second). A timer costs
about half a microsecond per call, most of it in the self time of the part that made the call:
the table lists the timers' estimated total (calls times a calibrated cost) as a row of its
own, and "the rest" (the run loop's own work: scheduling callbacks, checking the state, timed
events) is what remains.

``bench/bench_callbacks.py`` gives the CPU time per callback alone; this one splits the 20 Hz
navigation tick (controller, costmap updates, planner, progress checker, feedback) and the
10 Hz run loop (tree tick, trace, fault monitors, progress).
"""

from __future__ import annotations

import argparse
import collections
import importlib
import os
import time
from collections.abc import Callable
from typing import Any

from bench_callbacks import wrap_callbacks  # beside this script

from baobab.missions.language.bundled_missions import resolve_mission
from baobab.missions.language.loader import load_mission
from baobab.missions.run.runner import run_mission

_self: collections.defaultdict[str, float] = collections.defaultdict(float)
_calls: collections.Counter[str] = collections.Counter()
_stack: list[list[float]] = []  # per open timer: [time spent in timed children]

TIMED: dict[str, tuple[str, ...]] = {
    # part: the methods ("module:Class.method") whose self time counts to it
    "nav tick: server, task and BT glue": ("baobab.nav.server:NavigationServer._on_control",),
    "nav tick: planner (1 Hz)": (
        "baobab.nav.server:NavigationServer.compute_path",
        "baobab.nav.server:NavigationServer.compute_path_through_poses",
    ),
    "nav tick: task slot": ("baobab.nav.task_slot:TaskSlot.tick",),
    "nav tick: Nav2 tree traversal": ("baobab.nav.navigate:NavigateTask.tick",),
    "nav tick: navigator feedback": ("baobab.nav.navigate:NavigateTask._update_feedback",),
    "nav tick: FollowPath leaf": ("baobab.nav.bt_nodes:FollowPath.update",),
    "nav tick: controller cycle glue": ("baobab.nav.controller_server:PathFollower.cycle",),
    "nav tick: controller tracking feedback": (
        "baobab.nav.controller_server:PathFollower._tracking",
    ),
    "nav tick: progress checker": ("baobab.nav.checkers:SimpleProgressChecker.check",),
    "nav tick: goal checker": ("baobab.nav.checkers:SimpleGoalChecker.is_goal_reached",),
    "nav tick: RPP controller": ("baobab.nav.pure_pursuit:RegulatedPurePursuit.compute_velocity",),
    "costmap: local update (5 Hz)": ("baobab.nav.server:NavigationServer._update_local",),
    "costmap: global update (1 Hz)": ("baobab.nav.server:NavigationServer._update_global",),
    "costmap: scan marking": ("baobab.nav.costmap_updates:CostmapUpdates.on_scan",),
    "costmap: master refresh": ("baobab.nav.layered_costmap:LayeredCostmap._refresh",),
    "robot pose and speed reads": (
        "baobab.robots.diff_drive.base:DiffDriveBase.pose",
        "baobab.robots.diff_drive.base:DiffDriveBase.body_velocity",
    ),
    "mission tree tick (10 Hz)": ("baobab.missions.run.tick_loop:RunLoop._tick_tree",),
    "trace: tree statuses": ("baobab.missions.run.tick_loop:RunLoop._record_tree",),
    "trace: robot state": ("baobab.missions.run.tick_loop:RunLoop._record_state",),
    "trace: sim records": ("baobab.missions.run.tick_loop:RunLoop._record_sim",),
    "progress report": ("baobab.missions.run.tick_loop:RunLoop._report",),
    "fault monitors": ("baobab.missions.run.fault_monitors:FaultMonitors.check",),
}
"""The parts timed by wrapping methods, beside the periodic callbacks and ``mj_step``."""


def _timed(part: str, work: Callable[..., Any]) -> Callable[..., Any]:
    def run(*args: Any, **kwargs: Any) -> Any:
        _stack.append([0.0])
        began = time.perf_counter()
        try:
            return work(*args, **kwargs)
        finally:
            elapsed = time.perf_counter() - began
            children = _stack.pop()[0]
            _self[part] += elapsed - children
            _calls[part] += 1
            if _stack:
                _stack[-1][0] += elapsed

    return run


def _part(name: str) -> str:
    """The part a periodic callback (by its name) or ``mj_step`` counts to."""
    if name.startswith("lidar"):
        return "lidar scan (5 Hz)"
    if name.startswith("nav control"):
        return "nav tick: server, task and BT glue"
    if name.startswith(("nav local", "nav global")):
        return "costmap: scheduling"
    return name if name.startswith("physics") else f"callback {name}"


def _install_timers() -> None:
    wrap_callbacks(lambda name, work: _timed(_part(name), work))
    for part, methods in TIMED.items():
        for name in methods:
            module_name, _, qualified = name.partition(":")
            class_name, _, method = qualified.partition(".")
            cls = getattr(importlib.import_module(module_name), class_name)
            if method not in vars(cls):  # renamed or moved: say so rather than time nothing
                raise SystemExit(f"bench_loop_parts: {name} is gone; update TIMED")
            setattr(cls, method, _timed(part, vars(cls)[method]))


def _timer_cost() -> float:
    """Wall seconds a timer adds per call (the wrapper around a function doing nothing)."""

    def nothing() -> None:
        return None

    timed = _timed("calibration", nothing)
    calls = 200_000
    began = time.perf_counter()
    for _ in range(calls):
        timed()
    wrapped = time.perf_counter() - began
    began = time.perf_counter()
    for _ in range(calls):
        nothing()
    plain = time.perf_counter() - began
    _self.pop("calibration", None)
    _calls.pop("calibration", None)
    return max(wrapped - plain, 0.0) / calls


def measure(name: str, runs: int) -> None:
    """Run ``name`` once to warm up, then ``runs`` times; print the best run's split."""
    mission = load_mission(resolve_mission(name))
    run_mission(mission)
    best: tuple[float, float, dict[str, float], dict[str, int]] | None = None
    for _ in range(runs):
        _self.clear()
        _calls.clear()
        began = time.perf_counter()
        record = run_mission(mission)
        total = time.perf_counter() - began
        wall = record.wall_time
        if best is None or wall < best[0]:
            parts = dict(_self)
            timers = _timer_cost() * sum(_calls.values())
            parts["timers (calls x their measured cost)"] = timers
            parts["run loop (the rest)"] = wall - sum(parts.values())
            best = (wall, float(record.outcome.sim_time), parts, dict(_calls))
        del total
    assert best is not None
    wall, sim_time, parts, calls = best
    steps = round(sim_time * 200)
    load = os.getloadavg()[0]
    print(
        f"{name}: {sim_time:.1f} s of sim, loop {wall:.3f} s wall, "
        f"{1e6 * wall / steps:.2f} us per physics step (load {load:.2f})"
    )
    for part, cost in sorted(parts.items(), key=lambda item: -item[1]):
        rate = calls.get(part, 0) / sim_time
        print(f"  {part:44s} {1e6 * cost / steps:6.2f} us/step  ({rate:6.1f} calls/sim s)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("missions", nargs="*", default=["cafe_delivery"])
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    _install_timers()
    for name in args.missions:
        measure(name, args.runs)


if __name__ == "__main__":
    main()
