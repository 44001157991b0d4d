"""All of baobab's performance figures in one table, each measured in this run.

    python bench/run.py                 # every figure but the test suite (several minutes)
    python bench/run.py --with-tests    # also time `pytest -n 2` (about 3 more minutes)
    python bench/run.py --only planner startup
    python bench/run.py --only robots    # cafe_delivery's real-time factor on each mobile robot
    python bench/run.py --only install --with-tests  # fresh clones, venvs and installs (long)
    python bench/run.py --only longrun badinputs     # optional sections, not in the default set
    BAOBAB_PYROBOSIM_PYTHON=/path/to/venv/bin/python python bench/run.py --only pyrobosim

Every figure names the mission it comes from. Ratios are taken against a baseline measured in
the same run (bare MuJoCo stepping of the same model, a bare ``import mujoco``), so machine
noise cancels; wall-clock figures of whole processes are medians of repeats. A mission that
fails is in the table as FAILED, with why. Prints a table (figure, value, target, met?) with
the load average before and after, and writes bench.json. Targets come from the performance
issues. Process-level sections live in ``bench_whole_run.py``.

The loop's overhead (``--only missions``, issue 28: at most 1.5) is ``cafe_delivery``'s loop
wall time over bare ``mj_step`` of the same model stepping the same motion: the run's initial
state and each step's actuator controls, replayed open loop on a fresh MjData by a compiled
control callback (``bare_replay.py``; the replay must end where the run ended). Beside it, for
comparison, the same number of steps of a fresh MjData: the robot resting where the model
puts it.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import sysconfig
import tempfile
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "bench"))

from bench_whole_run import (  # noqa: E402  (beside this script)
    Figure,
    baobab_command,
    compiled_env,
    install_figures,
    mission_process_figures,
    suite_figures,
    whole_figures,
)

ROBOT_MISSION = "cafe_delivery"
"""The mission every bundled mobile robot runs for the per-robot real-time factor."""


def _bundled_missions() -> list[str]:
    from baobab.missions.language.bundled_missions import bundled_missions

    return list(bundled_missions())


def _bundled(name: str) -> Path:
    from baobab.missions.language.bundled_missions import resolve_mission

    return Path(resolve_mission(name))


@dataclass
class LoopTimes:
    """One bundled mission run in this process, beside bare stepping of its model (s)."""

    sim_time: float
    loop: float
    """The loop's wall time, best of the runs."""
    bare_replay: float | None = None
    """``mj_step`` of a fresh MjData replaying the run's motion (:mod:`bare_replay`)."""
    bare_resting: float | None = None
    """``mj_step`` of a fresh MjData for as many steps: the robot at rest."""
    replay_error: float = 0.0
    """The replay's largest final position difference against the run (m or rad)."""
    steps: int = 0
    """Physics steps of the run (with ``bare``)."""


def _run_in_process(
    name: str, runs: int = 2, robot: str | None = None, *, bare: bool = False
) -> LoopTimes:
    """Run a bundled mission in this process (on ``robot`` instead of its own, if given).

    The loop time is the best of ``runs`` runs: the first run of a process also loads the
    compiled kernels' caches, which is start-up (the ``startup`` and ``missions`` figures),
    not simulation speed. With ``bare``, two baselines follow, right after the runs so that
    they see the same load: the run's own motion replayed open loop on a fresh MjData of the
    same model (its initial state and each step's actuator controls, recorded in one more
    run; ``bare_replay.py``), and a fresh MjData stepped as long (the robot at rest).
    """
    from baobab.missions.language.loader import load_mission
    from baobab.missions.run.rig import build_rig
    from baobab.missions.run.runner import run_mission

    mission = load_mission(_bundled(name), robot=robot)
    records = [run_mission(mission) for _ in range(runs)]
    record = min(records, key=lambda run: run.wall_time)
    times = LoopTimes(float(record.outcome.sim_time), record.wall_time)
    if bare:
        import bare_replay

        controls = bare_replay.record_controls(lambda: run_mission(mission))
        model = build_rig(mission, mission.seed).sim.model
        times.bare_replay, times.replay_error = bare_replay.replay(model, controls)
        times.bare_resting = bare_replay.resting(model, len(controls.table))
        times.steps = len(controls.table)
    return times


def mission_figures() -> list[Figure]:
    """Every bundled mission as a process (loop and whole RTF); cafe_delivery's overhead
    against bare ``mj_step`` of its model replaying its motion (issue 28: <= 1.5) and, for
    comparison, stepping the robot at rest."""
    figures = mission_process_figures(_bundled_missions())
    command = "python bench/run.py --only missions"
    replayed = "cafe_delivery loop / bare mj_step of its model replaying the run's motion"
    resting = "cafe_delivery loop / bare mj_step of its model, robot at rest"
    try:
        times = _run_in_process("cafe_delivery", bare=True)
    except Exception as exc:  # a failing mission is a row of the table
        failed = f"{type(exc).__name__}: {exc}"
        return [*figures, Figure(replayed, math.nan, "ratio", 1.5, False, command, failed=failed)]
    assert times.bare_replay is not None and times.bare_resting is not None
    steps = times.steps
    drift = None
    if times.replay_error > 1e-9:
        drift = f"the replay ended {times.replay_error:.3g} away from the run"
    return [
        *figures,
        Figure(
            replayed, times.loop / times.bare_replay, "ratio", 1.5, False, command, failed=drift
        ),
        Figure(resting, times.loop / times.bare_resting, "ratio", None, False, command),
        Figure(
            "cafe_delivery loop per physics step",
            1e6 * times.loop / steps,
            "us",
            None,
            False,
            command,
        ),
        Figure(
            "cafe_delivery bare mj_step replaying the run, per step",
            1e6 * times.bare_replay / steps,
            "us",
            None,
            False,
            command,
        ),
    ]


def get_path_figures() -> list[Figure]:
    """Issue 28: ``BasicNavigator.getPath`` for the 16.2 m cafe query, median (ms)."""
    report = _script_report("bench_get_path.py", quiet=True)
    return [
        Figure(
            f"getPath cafe kitchen -> table_3 ({report['path_length_m']:.1f} m), median",
            report["median_ms"]["getPath"],
            "ms",
            2.0,
            False,
            "python bench/bench_get_path.py",
        )
    ]


def robot_figures() -> list[Figure]:
    """The real-time factor of the same mission (:data:`ROBOT_MISSION`) on each mobile robot,
    and its ratio to the default robot's (both measured in this run)."""
    from baobab.robots.catalog import DEFAULT_MOBILE_ROBOT, MOBILE_ROBOTS

    figures: list[Figure] = []
    factors: dict[str, float] = {}
    for robot in MOBILE_ROBOTS:
        times = _run_in_process(ROBOT_MISSION, robot=robot)
        factors[robot] = times.sim_time / times.loop
        figures.append(
            Figure(
                f"real-time factor {ROBOT_MISSION} on {robot}",
                factors[robot],
                "x",
                100.0,
                True,
                f"baobab run {ROBOT_MISSION} --robot {robot} --json (sim_time / wall_time)",
            )
        )
    for robot in MOBILE_ROBOTS:
        if robot != DEFAULT_MOBILE_ROBOT:
            figures.append(
                Figure(
                    f"real-time factor {robot} / {DEFAULT_MOBILE_ROBOT} ({ROBOT_MISSION})",
                    factors[robot] / factors[DEFAULT_MOBILE_ROBOT],
                    "ratio",
                    0.5,
                    True,
                    "python bench/run.py --only robots",
                )
            )
    return figures


def _planner_queries(world_name: str, queries: int, seed: int) -> tuple[list[float], list[float]]:
    """Plan between ``queries`` seeded random points of the world's bounds; every query is
    timed, those near or inside obstacles too: (successes' ms, failures' ms)."""
    import numpy as np

    from baobab.nav.errors import NavigationError
    from baobab.nav.layered_costmap import LayeredCostmap
    from baobab.nav.planner import GlobalPlanner
    from baobab.sim.world import Pose2D, load_world

    world = load_world(world_name)
    costmap = LayeredCostmap.global_costmap(world).costmap
    planner = GlobalPlanner()
    rng = np.random.default_rng(seed)
    x_min, y_min, x_max, y_max = world.bounds
    diagonal = float(np.hypot(x_max - x_min, y_max - y_min))
    planned: list[float] = []
    failed: list[float] = []
    while len(planned) + len(failed) < queries:
        points = rng.uniform((x_min, y_min), (x_max, y_max), size=(2, 2))
        if np.linalg.norm(points[0] - points[1]) < diagonal / 3:
            continue  # long queries only; where they start or end is not filtered
        start, goal = (Pose2D(x=float(p[0]), y=float(p[1])) for p in points)
        began = time.perf_counter()
        try:
            planner.create_plan(start, goal, costmap)
        except NavigationError:  # a refused query is timed as a failure
            failed.append((time.perf_counter() - began) * 1e3)
        else:
            planned.append((time.perf_counter() - began) * 1e3)
    return planned, failed


def planner_figures(queries: int = 200, seed: int = 0) -> list[Figure]:
    """A* query time on the cafe and farm maps: all queries, and the failed ones apart."""
    import numpy as np

    figures: list[Figure] = []
    command = "python bench/run.py --only planner"
    for world_name in ("cafe", "farm"):
        planned, failed = _planner_queries(world_name, queries, seed)
        every = planned + failed
        figures += [
            Figure(
                f"planner median {world_name} (all {len(every)} queries)",
                statistics.median(every),
                "ms",
                5.0,
                False,
                command,
            ),
            Figure(
                f"planner p95 {world_name} (all queries)",
                float(np.percentile(every, 95)),
                "ms",
                20.0,
                False,
                command,
            ),
            Figure(
                f"planner failed queries {world_name} (start or goal blocked, no path)",
                len(failed),
                "count",
                None,
                False,
                command,
            ),
        ]
        if failed:
            figures.append(
                Figure(
                    f"planner median of the failed queries {world_name}",
                    statistics.median(failed),
                    "ms",
                    None,
                    False,
                    command,
                )
            )
    return figures


def _time_to_first_tick(mission: str, out: str, env: dict[str, str]) -> float:
    """Process start to the first progress line of ``baobab run MISSION`` (s)."""
    began = time.perf_counter()
    process = subprocess.Popen(
        [*baobab_command(), "run", mission, "--out", out],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
        env=env,
    )
    assert process.stdout is not None
    process.stdout.readline()  # "running <title>": the mission is loaded
    process.stdout.readline()  # the first progress line is written at the first tick
    elapsed = time.perf_counter() - began
    process.kill()
    process.wait()
    return elapsed


def startup_figures(repeats: int = 3) -> list[Figure]:
    """Process start to the first tree tick (walls_go_to_goal, cafe_delivery); `validate`.

    Each command runs once untimed first, so the bytecode cache is warm (see compiled_env).
    """
    missions = sorted(str(path) for path in (REPO / "missions").glob("*.yaml"))
    figures: list[Figure] = []
    validate: list[float] = []
    with tempfile.TemporaryDirectory() as out:
        env = compiled_env(f"{out}/pycache")
        for mission in ("walls_go_to_goal", "cafe_delivery"):
            ticks = [
                _time_to_first_tick(mission, f"{out}/{mission}-{index}", env)
                for index in range(repeats + 1)
            ][1:]
            figures.append(
                Figure(
                    f"start-up {mission}: process start to first tick (median)",
                    statistics.median(ticks),
                    "s",
                    1.0,
                    False,
                    f"baobab run {mission} (time to the first progress line)",
                )
            )
        for index in range(repeats + 1):
            began = time.perf_counter()
            subprocess.run(
                [*baobab_command(), "validate", *missions],
                check=False,
                capture_output=True,
                env=env,
            )
            if index:
                validate.append(time.perf_counter() - began)
    figures.append(
        Figure(
            f"start-up: baobab validate of {len(missions)} missions (median)",
            statistics.median(validate),
            "s",
            0.5,
            False,
            "baobab validate missions/*.yaml",
        )
    )
    return figures


def arm_figures() -> list[Figure]:
    """The Panda's control law as one call, beside its whole 1 kHz loop inside mj_step."""
    from bench_panda import bench_control_step, bench_loop_in_simulation

    step = bench_control_step()
    loop = bench_loop_in_simulation()
    command = "python bench/bench_panda.py"
    return [
        Figure(
            "arm control law, one compute_torque call (median)",
            step["median_us"],
            "us",
            30.0,
            False,
            command,
        ),
        Figure(
            "arm whole 1 kHz loop per physics step, CPU (with the loop - without)",
            loop["control_in_step_us"],
            "us",
            None,
            False,
            command,
        ),
        Figure(
            "arm physics alone per step, CPU (mj_step detached)",
            loop["physics_us"],
            "us",
            None,
            False,
            command,
        ),
    ]


def _shared_libraries() -> list[Path]:
    """The compiled libraries a run maps: every ``.so`` of this environment and libpython."""
    paths = sysconfig.get_paths()
    roots = {Path(paths["purelib"]), Path(paths["platlib"])}
    libraries = [path for root in roots for path in root.rglob("*.so*") if path.is_file()]
    libdir = sysconfig.get_config_var("LIBDIR")
    if libdir:
        libraries.extend(path for path in Path(libdir).glob("libpython*.so*") if path.is_file())
    return libraries


def _set_page_cache(libraries: list[Path], *, read: bool) -> None:
    """Drop the libraries' cached pages; with ``read``, read each file through once.

    Linux maps a library's cached pages into a process in whole folios: pages read through
    (as pip leaves them after an install) sit in large folios, so mapping a library such as
    llvmlite's (178 MB) makes far more of it resident than when it is paged in on demand.
    Only clean page-cache pages are dropped, so this is safe, and a run's memory is measured
    in both states.
    """
    for path in libraries:
        try:
            descriptor = os.open(path, os.O_RDONLY)
        except OSError:
            continue
        try:
            os.posix_fadvise(descriptor, 0, 0, os.POSIX_FADV_DONTNEED)
            while read and os.read(descriptor, 1 << 20):
                pass
        finally:
            os.close(descriptor)


_PEAKS = """\
import json, resource, sys
from baobab.missions.cli.command_line import main
code = main(sys.argv[1:])
own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
child = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
print(json.dumps({"code": code, "parent_kb": own, "child_kb": child}), file=sys.stderr)
"""
"""`baobab run` in this process (its parent) and its forked run: each one's peak RSS (KB)."""


def _peak_memory_mb(out: str) -> tuple[float, float]:
    """Peak RSS (MB) of both processes of one `baobab run cafe_delivery`: (parent, child).

    The command runs as the main of a fresh interpreter, so that interpreter is the run's
    parent (the process that writes the run folder) and its only child is the run's process.
    """
    process = subprocess.run(
        [sys.executable, "-c", _PEAKS, "run", "cafe_delivery", "--json", "--out", out],
        check=True,
        capture_output=True,
        text=True,
    )
    peaks = json.loads(process.stderr.strip().splitlines()[-1])
    return peaks["parent_kb"] / 1024, peaks["child_kb"] / 1024


def memory_figures() -> list[Figure]:
    """Peak resident memory of `baobab run cafe_delivery`: its largest process and the sum.

    The two processes overlap in time (the parent loads matplotlib while the child runs), so
    the sum of their peaks is what the machine may need at once. Measured with the libraries
    paged in on demand and freshly read (see _set_page_cache); each is the larger of two runs,
    after a first run that warms numba's kernel cache. Pages mapped by a running process cannot
    be dropped, so :func:`main` measures this first, before this process loads MuJoCo, NumPy or
    numba itself.
    """
    libraries = _shared_libraries() if hasattr(os, "posix_fadvise") else []
    figures: list[Figure] = []
    command = "baobab run cafe_delivery (ru_maxrss of its parent and its run's process)"
    with tempfile.TemporaryDirectory() as out:
        _peak_memory_mb(f"{out}/warm")
        for label, read in (("paged in on demand", False), ("freshly read", True)):
            peaks = []
            for index in range(2):
                _set_page_cache(libraries, read=read)
                peaks.append(_peak_memory_mb(f"{out}/{label}-{index}"))
            largest = max(max(pair) for pair in peaks)
            both = max(sum(pair) for pair in peaks)
            figures += [
                Figure(
                    f"peak memory cafe_delivery, largest process (libraries {label})",
                    largest,
                    "MB",
                    300.0,
                    False,
                    command,
                ),
                Figure(
                    f"peak memory cafe_delivery, both processes (libraries {label})",
                    both,
                    "MB",
                    None,
                    False,
                    command,
                ),
            ]
    return figures


def _script_report(script: str, *, quiet: bool = False) -> Any:
    """Run ``bench/<script>`` in a fresh process and return the JSON report it writes."""
    with tempfile.TemporaryDirectory() as out:
        report_path = Path(out) / "report.json"
        subprocess.run(
            [sys.executable, str(REPO / "bench" / script), "--output", str(report_path)],
            check=True,
            stdout=subprocess.DEVNULL if quiet else None,
        )
        return json.loads(report_path.read_text())


def longrun_figures() -> list[Figure]:
    """Issue 12: memory over 200 runs in one process, drift over a 2-hour patrol (minutes).

    Runs bench/bench_longrun.py in a fresh process, so the memory is that of the long run only.
    """
    report = _script_report("bench_longrun.py")
    command = "python bench/bench_longrun.py"
    figures = [
        Figure(
            f"long run: RSS growth over {report[part]['runs']} {label} after warm-up",
            report[part]["growth_percent"],
            "%",
            10.0,
            False,
            f"{command} --only {part}",
        )
        for part, label in (("runner", "run_mission runs"), ("navigator", "BasicNavigator goals"))
    ]
    patrol = report["patrol"]
    for clock, key in (("wall", "drift_last_over_first"), ("CPU", "cpu_drift_last_over_first")):
        figures.append(
            Figure(
                f"long run: {clock} per sim s, last / first 10 min of a {patrol['hours']:g} h "
                "patrol",
                patrol[key],
                "ratio",
                1.1,
                False,
                f"{command} --only patrol",
            )
        )
    return figures


def bad_input_figures() -> list[Figure]:
    """Issue 12: the slowest refusal of a bad input by the real command (s)."""
    report = _script_report("bench_bad_inputs.py", quiet=True)
    return [
        Figure(
            f"bad input: slowest of {len(report['timings'])} refusals (exit 2, one line)",
            report["max_seconds"],
            "s",
            1.0,
            False,
            "python bench/bench_bad_inputs.py",
        )
    ]


def map_figures() -> list[Figure]:
    """Issue 22: a 2000 x 2000-cell map loaded and built; its lidar scan against the cafe's."""
    report = _script_report("bench_maps.py", quiet=True)
    command = "python bench/bench_maps.py"
    return [
        Figure(
            f"map {report['cells']} x {report['cells']} cells: load + build the model "
            f"({report['static_boxes']} boxes)",
            report["load_and_build_s"],
            "s",
            1.5,
            False,
            command,
        ),
        Figure("map: lidar scan / the cafe's", report["scan_ratio"], "ratio", 2.0, False, command),
        Figure(
            f"map: mj_step / the cafe's ({report['sensors']} sensors)",
            report["step_ratio"],
            "ratio",
            4.0,
            False,
            command,
        ),
        Figure(
            "map: real-time factor of a 9 m NavigateToPose, set-up included",
            report["navigation"]["rtf"],
            "x",
            20.0,
            True,
            command,
        ),
    ]


def ros_figures() -> list[Figure]:
    """Issue 25: node code against the simulation (``baobab ros run``), loop real-time factor."""
    report = _script_report("bench_ros.py", quiet=True)
    command = "python bench/bench_ros.py"
    return [
        Figure(
            "ros run: node-driven go-to-goal, walls world (loop RTF)",
            report["go_to_goal"]["rtf_loop"],
            "x",
            50.0,
            True,
            command,
        ),
        Figure(
            "ros run: Panda trajectory planner at 100 Hz (loop RTF)",
            report["panda_planner"]["rtf_loop"],
            "x",
            5.0,  # no issue target: the 1 kHz arm and the node's own scipy slerp; say if it drops
            True,
            command,
        ),
    ]


def pyrobosim_figures() -> list[Figure]:
    """Issue 28: the cafe round trip against pyrobosim at the Burger's speed and 20 Hz steps,
    paired ratios of sim s per wall s over nine interleaved repetitions (pyrobosim from
    ``BAOBAB_PYROBOSIM_PYTHON``; no figures, with a message, without it)."""
    report = _script_report("bench_pyrobosim.py")
    if "skipped" in report:
        print(f"  pyrobosim: not measured ({report['skipped']})", file=sys.stderr)
        return []
    command = "python bench/bench_pyrobosim.py --pyrobosim-python PYTHON"
    return [
        Figure(
            f"cafe round trip, baobab / pyrobosim {label} (paired ratio of sim s per wall s)",
            report[f"paired_wall_ratio_vs_{variant}"]["median"],
            "ratio",
            5.0,
            True,
            command,
        )
        for variant, label in (
            ("pyrobosim", "as shipped"),
            ("pyrobosim_no_sleep", "without its end-of-path sleep"),
        )
    ]


def script_sleep_figures() -> list[Figure]:
    """Issue 24: a Nav2 script sleeping 0.2 s per poll, against the same script without."""
    report = _script_report("bench_script_sleeps.py", quiet=True)
    sim = report["sleep_0.2"]["sim_s"]
    return [
        Figure(
            f"nav2 script sleeping 0.2 s per poll over a {sim:.0f} s navigation, wall time / "
            "without sleeps",
            report["ratio"],
            "ratio",
            1.5,
            False,
            "python bench/bench_script_sleeps.py",
        )
    ]


def test_suite_figures() -> list[Figure]:
    """Wall time of the whole test suite with two workers."""
    began = time.perf_counter()
    subprocess.run(
        [sys.executable, "-m", "pytest", "-n", "2", "-q", "-p", "no:cacheprovider"],
        cwd=REPO,
        check=False,
        capture_output=True,
    )
    minutes = (time.perf_counter() - began) / 60
    return [Figure("test suite wall time", minutes, "min", 3.0, False, "pytest -n 2")]


SECTIONS: dict[str, Callable[[], list[Figure]]] = {
    "memory": memory_figures,
    "whole": whole_figures,
    "missions": mission_figures,
    "robots": robot_figures,
    "suite": suite_figures,
    "planner": planner_figures,
    "getpath": get_path_figures,
    "startup": startup_figures,
    "arm": arm_figures,
    "maps": map_figures,
    "ros": ros_figures,
    "scripts": script_sleep_figures,
}
OPTIONAL_SECTIONS: dict[str, Callable[[], list[Figure]]] = {
    "longrun": longrun_figures,
    "badinputs": bad_input_figures,
    "pyrobosim": pyrobosim_figures,
}
"""Sections that take several minutes each: measured only when named with --only."""


def _row(figure: Figure, width: int) -> str:
    relation = ">=" if figure.higher_is_better else "<="
    target = f"{relation}{figure.target:>7g}" if figure.target is not None else " " * 9
    met = {True: "yes", False: "NO", None: ""}[figure.met]
    if figure.failed is not None:
        return f"{figure.name:<{width}}  {'FAILED':>13} {target}  NO   {figure.failed}"
    return f"{figure.name:<{width}}  {figure.value:>8.2f} {figure.unit:<4} {target}  {met}"


def main() -> None:
    """Measure, print the table, write bench.json."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    choices = sorted(SECTIONS | OPTIONAL_SECTIONS) + ["install"]
    parser.add_argument("--only", nargs="+", choices=choices, default=None)
    parser.add_argument("--with-tests", action="store_true", help="also time the test suite")
    parser.add_argument("--output", default="bench.json")
    args = parser.parse_args()
    os.environ.setdefault("MUJOCO_GL", "egl")
    load_before = os.getloadavg()
    figures: list[Figure] = []
    chosen = args.only or list(SECTIONS)
    for name in sorted(chosen, key=lambda section: section != "memory"):  # memory first
        print(f"measuring {name} ...", file=sys.stderr)
        if name == "install":  # fresh clones and venvs: with --with-tests, CI's first suite
            figures.extend(install_figures(with_tests=args.with_tests))
        else:
            figures.extend((SECTIONS | OPTIONAL_SECTIONS)[name]())
    if args.with_tests and "install" not in chosen:
        figures.extend(test_suite_figures())
    load_after = os.getloadavg()
    width = max(len(figure.name) for figure in figures)
    print(f"{'figure':<{width}}  {'value':>10}  {'target':>10}  met?")
    for figure in figures:
        print(_row(figure, width))
    print(f"load average (1 min) before / after: {load_before[0]:.1f} / {load_after[0]:.1f}")
    report = {
        "load_average_before": load_before,
        "load_average_after": load_after,
        "figures": [{**asdict(figure), "met": figure.met} for figure in figures],
    }
    Path(args.output).write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
