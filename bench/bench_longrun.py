"""Benchmark: long runs in one process (issue 12): memory over many missions, drift over hours.

Usage: ``python bench/bench_longrun.py [--runs 200] [--hours 2] [--only runner navigator patrol]``

1. runner: a short navigation mission (cafe, lidar noise on, a crate spawned on the way) is
   loaded and run ``--runs`` times through :func:`~baobab.missions.run.runner.run_mission`, and
   its run folder (result, trace, plot) written each time, as the pytest plugin does.
2. navigator: ``--runs`` times a fresh :class:`~baobab.nav.BasicNavigator` in the cafe,
   ``goToPose`` to table_1, polled to completion, then ``lifecycleShutdown`` and
   ``destroy_node``, as a Nav2 script does.
3. patrol: the cafe's six waypoints, looped by a ``repeat`` decorator around
   ``follow_waypoints``, for ``--hours`` of sim time in one run; the wall time per sim second
   of each 10-minute sim window (and the process's CPU time per sim second, which other
   processes on the machine do not inflate), and the resident memory at the end of each window.

For 1 and 2 the resident set size (``/proc/self/statm``, after ``gc.collect()``) is read
after every run; growth is the last run's against the run at the end of the warm-up
(``--warmup``, 20 runs). Every run must end the same way with the same trace digest (runner)
or the same sim time and final pose (navigator): a run that depended on an earlier one would
show here. Drift is the last window's wall time per sim second over the first's. Prints the
figures and writes bench_longrun.json.
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import os
import shutil
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

PAGE_BYTES = os.sysconf("SC_PAGE_SIZE")
WINDOW_S = 600.0
"""Sim seconds per patrol window (10 minutes)."""

HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
SHORT_MISSION = (
    HEADER
    + """\
mission: longrun_short
description: To table_1 in the cafe with lidar noise, past a crate spawned on the way.
world: cafe
robot: turtlebot3
seed: 5
noise: {lidar_std: 0.01}
events:
  - {at: 1.0, spawn_obstacle: {name: crate, x: 0.6, y: -1.2, size: [0.3, 0.3, 0.5]}}
tree:
  navigate_to_pose: table_1
timeout: 60
expect:
  result: SUCCEEDED
"""
)

PATROL_MISSION = (
    HEADER
    + """\
mission: longrun_patrol
description: The cafe's six waypoints, looped until the run is stopped.
world: cafe
robot: turtlebot3
seed: 1
tree:
  repeat:
    num_success: {laps}
    child:
      follow_waypoints:
        waypoints: [wp_1, wp_2, wp_3, wp_4, wp_5, wp_6]
        wait_at_waypoint: 2.0
timeout: {timeout}
"""
)


def rss_mb() -> float:
    """Resident set size of this process (MB), from /proc/self/statm."""
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1]) * PAGE_BYTES / 2**20


@dataclass
class MemorySeries:
    """Resident memory after each of many runs in one process."""

    label: str
    warmup: int
    rss_mb: list[float] = field(default_factory=list)
    wall_s: list[float] = field(default_factory=list)
    live_objects: list[int] = field(default_factory=list)
    outcomes: set[str] = field(default_factory=set)

    @property
    def growth_percent(self) -> float:
        """Growth of the last run's RSS over the RSS at the end of the warm-up (%)."""
        warm = self.rss_mb[min(self.warmup, len(self.rss_mb)) - 1]
        return 100.0 * (self.rss_mb[-1] - warm) / warm

    def summary(self) -> dict[str, object]:
        """The figures for the report."""
        warm = self.rss_mb[min(self.warmup, len(self.rss_mb)) - 1]
        return {
            "runs": len(self.rss_mb),
            "rss_first_mb": round(self.rss_mb[0], 1),
            "rss_after_warmup_mb": round(warm, 1),
            "rss_last_mb": round(self.rss_mb[-1], 1),
            "rss_max_mb": round(max(self.rss_mb), 1),
            "growth_percent": round(self.growth_percent, 2),
            "gc_objects_after_warmup": self.live_objects[min(self.warmup, len(self.rss_mb)) - 1],
            "gc_objects_last": self.live_objects[-1],
            "wall_per_run_s": round(sum(self.wall_s) / len(self.wall_s), 3),
            "distinct_outcomes": sorted(self.outcomes),
        }


def _series(label: str, runs: int, warmup: int, once: Callable[[], str]) -> MemorySeries:
    series = MemorySeries(label, warmup)
    for index in range(runs):
        began = time.perf_counter()
        series.outcomes.add(once())
        series.wall_s.append(time.perf_counter() - began)
        gc.collect()
        series.rss_mb.append(rss_mb())
        series.live_objects.append(len(gc.get_objects()))
        if index % 20 == 19 or index == runs - 1:
            print(
                f"  {label} run {index + 1}: {series.rss_mb[-1]:.1f} MB, "
                f"{series.live_objects[-1]} objects",
                file=sys.stderr,
            )
    return series


def runner_series(runs: int, warmup: int, folder: Path) -> MemorySeries:
    """Load and run the short mission ``runs`` times through ``run_mission``."""
    from baobab.missions.language.loader import load_mission
    from baobab.missions.run.run_folder import write_run_folder
    from baobab.missions.run.runner import run_mission

    path = folder / "longrun_short.yaml"
    path.write_text(SHORT_MISSION)

    def once() -> str:
        record = run_mission(load_mission(path))
        run_folder = folder / "run"
        result = record.result_object(run_folder)
        write_run_folder(run_folder, result, record.trace.text(), record.plot)
        shutil.rmtree(run_folder)
        outcome = record.outcome
        return f"{outcome.result} {outcome.sim_time:.3f} s {record.trace_digest[:16]}"

    return _series("runner", runs, warmup, once)


def navigator_series(runs: int, warmup: int) -> MemorySeries:
    """Create a navigator, drive to table_1, shut it down and destroy it, ``runs`` times."""
    from baobab.nav import BasicNavigator
    from baobab.nav.msgs import pose_stamped

    def once() -> str:
        navigator = BasicNavigator(world="cafe", seed=5)
        navigator.get_logger().set_level(40)  # the ROS console lines: errors only
        navigator.goToPose(pose_stamped(-0.96, -0.92))
        while not navigator.isTaskComplete():
            pass
        result = navigator.getResult().name
        now = navigator.get_clock().now().nanoseconds / 1e9
        pose = navigator.robot_pose()
        navigator.lifecycleShutdown()
        navigator.destroy_node()
        return f"{result} {now:.3f} s at ({pose.x:.6f}, {pose.y:.6f}, {pose.yaw:.6f})"

    return _series("navigator", runs, warmup, once)


@dataclass
class PatrolWindow:
    """One window of sim time of the patrol."""

    sim_end_s: float
    wall_per_sim_s: float
    cpu_per_sim_s: float
    rss_mb: float


class _WindowClock:
    """A progress sink that closes a window every ``WINDOW_S`` of sim time; stops at the end."""

    def __init__(self, duration: float) -> None:
        self.duration = duration
        self.windows: list[PatrolWindow] = []
        self._mark_sim = 0.0
        self._mark_wall = time.perf_counter()
        self._mark_cpu = time.process_time()

    def update(self, snapshot: object) -> None:
        sim_time = float(getattr(snapshot, "sim_time"))  # noqa: B009 (ProgressSnapshot)
        if sim_time - self._mark_sim >= WINDOW_S:
            wall, cpu = time.perf_counter(), time.process_time()
            span = sim_time - self._mark_sim
            per_sim = (wall - self._mark_wall) / span
            cpu_per_sim = (cpu - self._mark_cpu) / span
            self.windows.append(PatrolWindow(round(sim_time, 3), per_sim, cpu_per_sim, rss_mb()))
            print(
                f"  patrol {sim_time / 60:6.1f} min: {per_sim * 1e3:.2f} ms wall and "
                f"{cpu_per_sim * 1e3:.2f} ms CPU per sim s, {self.windows[-1].rss_mb:.1f} MB",
                file=sys.stderr,
            )
            self._mark_sim, self._mark_wall, self._mark_cpu = sim_time, wall, cpu

    def done(self) -> bool:
        return self._mark_sim >= self.duration - 1e-9


def patrol(hours: float, folder: Path) -> dict[str, object]:
    """Loop the cafe waypoints for ``hours`` of sim time; per-window wall time and memory."""
    from baobab.missions.language.loader import load_mission
    from baobab.missions.run.runner import run_mission

    duration = hours * 3600.0
    path = folder / "longrun_patrol.yaml"
    laps = 10 * math.ceil(duration / 60.0)  # far more than fit: the run is stopped by time
    path.write_text(PATROL_MISSION.format(laps=laps, timeout=duration + 3600.0))
    clock = _WindowClock(duration)
    began = time.perf_counter()
    record = run_mission(load_mission(path), progress=clock, interrupted=clock.done)
    wall = time.perf_counter() - began
    per_sim = [window.wall_per_sim_s for window in clock.windows]
    cpu_per_sim = [window.cpu_per_sim_s for window in clock.windows]
    return {
        "hours": hours,
        "result": record.outcome.result,
        "sim_time_s": round(record.outcome.sim_time, 3),
        "wall_time_s": round(wall, 2),
        "real_time_factor": round(record.outcome.sim_time / wall, 1),
        "windows": [asdict(window) for window in clock.windows],
        "drift_last_over_first": per_sim[-1] / per_sim[0] if per_sim else math.nan,
        "drift_max_over_min": max(per_sim) / min(per_sim) if per_sim else math.nan,
        "cpu_drift_last_over_first": cpu_per_sim[-1] / cpu_per_sim[0] if per_sim else math.nan,
        "cpu_drift_max_over_min": max(cpu_per_sim) / min(cpu_per_sim) if per_sim else math.nan,
        "rss_first_window_mb": clock.windows[0].rss_mb if clock.windows else math.nan,
        "rss_last_window_mb": clock.windows[-1].rss_mb if clock.windows else math.nan,
    }


def main() -> None:
    """Measure, print the figures, write bench_longrun.json."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=200, help="runs of the runner and navigator")
    parser.add_argument("--warmup", type=int, default=20, help="runs before memory is compared")
    parser.add_argument("--hours", type=float, default=2.0, help="sim hours of the patrol")
    parser.add_argument(
        "--only", nargs="+", choices=("runner", "navigator", "patrol"), default=None
    )
    parser.add_argument("--output", default="bench_longrun.json")
    args = parser.parse_args()
    os.environ.setdefault("MUJOCO_GL", "egl")
    parts = args.only or ["runner", "navigator", "patrol"]
    report: dict[str, object] = {"rss_at_start_mb": round(rss_mb(), 1)}
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        if "runner" in parts:
            series = runner_series(args.runs, args.warmup, folder)
            report["runner"] = series.summary()
        if "navigator" in parts:
            series = navigator_series(args.runs, args.warmup)
            report["navigator"] = series.summary()
        if "patrol" in parts:
            report["patrol"] = patrol(args.hours, folder)
    for part in ("runner", "navigator"):
        if part in report:
            figures = report[part]
            assert isinstance(figures, dict)
            print(
                f"{part:>9}: {figures['runs']} runs, RSS {figures['rss_after_warmup_mb']} MB "
                f"after warm-up -> {figures['rss_last_mb']} MB "
                f"({figures['growth_percent']:+.2f} %), "
                f"{figures['wall_per_run_s']} s per run, outcomes {figures['distinct_outcomes']}"
            )
    if "patrol" in report:
        figures = report["patrol"]
        assert isinstance(figures, dict)
        print(
            f"   patrol: {figures['sim_time_s']} s sim in {figures['wall_time_s']} s "
            f"({figures['real_time_factor']}x), drift last/first "
            f"{figures['drift_last_over_first']:.3f}, max/min {figures['drift_max_over_min']:.3f} "
            f"(CPU time: {figures['cpu_drift_last_over_first']:.3f}, "
            f"{figures['cpu_drift_max_over_min']:.3f}), "
            f"RSS {figures['rss_first_window_mb']:.1f} -> {figures['rss_last_window_mb']:.1f} MB"
        )
    Path(args.output).write_text(json.dumps(report, indent=2, default=str) + "\n")


if __name__ == "__main__":
    main()
