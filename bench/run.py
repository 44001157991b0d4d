"""All of baobab's performance figures in one table, each measured in this run.

    python bench/run.py                 # every figure but the test suite (a few minutes)
    python bench/run.py --with-tests    # also time `pytest -n 2` (about 3 more minutes)
    python bench/run.py --only planner startup
    python bench/run.py --only longrun badinputs   # optional sections, not in the default set

Ratios are taken against a baseline measured in the same run (bare MuJoCo stepping of the same
model), so machine noise cancels. Prints a table (figure, value, target, met?) and writes
bench.json. Targets come from the performance issue.
"""

from __future__ import annotations

import argparse
import json
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
MOBILE_MISSIONS = (
    "walls_go_to_goal",
    "walls_bug2",
    "cafe_delivery",
    "waypoint_patrol",
    "farm_rows",
    "town_nav_to_pose",
    "assisted_teleop",
)
ARM_MISSIONS = ("panda_pick",)


@dataclass
class Figure:
    """One measured figure and its target."""

    name: str
    value: float
    unit: str
    target: float
    higher_is_better: bool
    command: str

    @property
    def met(self) -> bool:
        """True when the value reaches the target."""
        if self.higher_is_better:
            return self.value >= self.target
        return self.value <= self.target


def _baobab_command() -> list[str]:
    return [str(Path(sys.executable).with_name("baobab"))]


def _compiled_env(cache: str) -> dict[str, str]:
    """The environment of an installed baobab: modules compiled to bytecode once, then reused.

    A development shell may set PYTHONDONTWRITEBYTECODE (this one does), which makes every
    process compile baobab's modules from source again (~0.1 s at start-up); the bytecode goes
    to a private cache here instead of the source tree.
    """
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPYCACHEPREFIX"] = cache
    return env


def _bundled(name: str) -> Path:
    from baobab.missions.language.bundled_missions import resolve_mission

    return Path(resolve_mission(name))


def _run_in_process(name: str, runs: int = 2) -> tuple[float, float, float]:
    """Run a bundled mission in this process; return (sim time, loop wall time, bare wall time).

    The loop time is the best of ``runs`` runs: the first run of a process also loads the
    compiled kernels' caches, which is start-up (figure 4), not simulation speed. The bare
    time steps a fresh MjData of the same MjModel with ``mj_step`` for the same sim duration,
    right after the runs, so both see the same machine load.
    """
    import mujoco

    from baobab.missions.language.loader import load_mission
    from baobab.missions.run.rig import build_rig
    from baobab.missions.run.runner import run_mission

    mission = load_mission(_bundled(name))
    records = [run_mission(mission) for _ in range(runs)]
    record = min(records, key=lambda run: run.wall_time)
    sim_time = float(record.outcome.sim_time)
    model = build_rig(mission, mission.seed).sim.model
    data = mujoco.MjData(model)
    steps = round(sim_time / model.opt.timestep)
    start = time.perf_counter()
    mujoco.mj_step(model, data, steps)
    bare = time.perf_counter() - start
    return sim_time, record.wall_time, bare


def mission_figures() -> list[Figure]:
    """Figures 1 and 2: cafe_delivery overhead over bare physics; RTF of every mission."""
    figures: list[Figure] = []
    for name in MOBILE_MISSIONS + ARM_MISSIONS:
        try:
            sim_time, wall, bare = _run_in_process(name)
        except Exception as exc:  # a mission that does not exist yet or fails: say so
            print(f"  {name}: not measured ({type(exc).__name__}: {exc})", file=sys.stderr)
            continue
        arm = name in ARM_MISSIONS
        figures.append(
            Figure(
                f"real-time factor {name}",
                sim_time / wall,
                "x",
                20.0 if arm else 100.0,
                True,
                f"baobab run {name} --json (sim_time / wall_time)",
            )
        )
        if name == "cafe_delivery":
            figures.append(
                Figure(
                    "mission overhead cafe_delivery (wall / bare mj_step)",
                    wall / bare,
                    "ratio",
                    3.0,
                    False,
                    "python bench/run.py --only missions",
                )
            )
    return figures


def planner_figures(queries: int = 200, seed: int = 0) -> list[Figure]:
    """Figure 3: A* query time (median, p95) on the cafe and farm maps."""
    import numpy as np

    from baobab.nav.layered_costmap import LayeredCostmap
    from baobab.nav.planner import GlobalPlanner
    from baobab.sim.geometry import clearance
    from baobab.sim.world import Pose2D, load_world

    figures: list[Figure] = []
    for world_name in ("cafe", "farm"):
        world = load_world(world_name)
        costmap = LayeredCostmap.global_costmap(world).costmap
        planner = GlobalPlanner()
        rng = np.random.default_rng(seed)
        x_min, y_min, x_max, y_max = world.bounds
        diagonal = float(np.hypot(x_max - x_min, y_max - y_min))
        times: list[float] = []
        while len(times) < queries:
            points = rng.uniform((x_min, y_min), (x_max, y_max), size=(2, 2))
            if np.linalg.norm(points[0] - points[1]) < diagonal / 3:
                continue
            if (clearance(world, points) < 0.3).any():
                continue
            start, goal = (Pose2D(x=float(p[0]), y=float(p[1])) for p in points)
            began = time.perf_counter()
            try:
                planner.create_plan(start, goal, costmap)
            except Exception:
                continue
            times.append((time.perf_counter() - began) * 1e3)
        command = "python bench/run.py --only planner"
        figures.append(
            Figure(
                f"planner median {world_name}", statistics.median(times), "ms", 5.0, False, command
            )
        )
        figures.append(
            Figure(
                f"planner p95 {world_name}",
                float(np.percentile(times, 95)),
                "ms",
                20.0,
                False,
                command,
            )
        )
    return figures


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


def startup_figures(repeats: int = 3) -> list[Figure]:
    """Figure 4: process start to the first tree tick; `baobab validate` of every mission.

    Each command runs once untimed first, so the bytecode cache is warm (see _compiled_env).
    """
    first_tick: list[float] = []
    missions = sorted(str(path) for path in (REPO / "missions").glob("*.yaml"))
    validate: list[float] = []
    with tempfile.TemporaryDirectory() as out:
        env = _compiled_env(f"{out}/pycache")
        for index in range(repeats + 1):
            began = time.perf_counter()
            process = subprocess.Popen(
                [*_baobab_command(), "run", "walls_go_to_goal", "--out", f"{out}/{index}"],
                stdout=subprocess.PIPE,
                stderr=subprocess.DEVNULL,
                text=True,
                env=env,
            )
            assert process.stdout is not None
            process.stdout.readline()  # "running <title>": the mission is loaded
            process.stdout.readline()  # the first progress line is written at the first tick
            if index:
                first_tick.append(time.perf_counter() - began)
            process.kill()
            process.wait()
        for index in range(repeats + 1):
            began = time.perf_counter()
            subprocess.run(
                [*_baobab_command(), "validate", *missions],
                check=False,
                capture_output=True,
                env=env,
            )
            if index:
                validate.append(time.perf_counter() - began)
    return [
        Figure(
            "start-up: process start to first tick",
            min(first_tick),
            "s",
            1.0,
            False,
            "baobab run walls_go_to_goal (time to the first progress line)",
        ),
        Figure(
            f"start-up: baobab validate of {len(missions)} missions",
            min(validate),
            "s",
            0.5,
            False,
            "baobab validate missions/*.yaml",
        ),
    ]


def arm_figures() -> list[Figure]:
    """Figure 5: microseconds per impedance control step."""
    sys.path.insert(0, str(REPO / "bench"))
    from bench_panda import bench_control_step

    step = bench_control_step()
    value = float(step.get("median_us", step.get("us", float("nan"))))
    return [
        Figure("arm control step", value, "us", 30.0, False, "python bench/bench_panda.py (median)")
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


def _peak_memory_mb(out: str) -> float:
    """ru_maxrss (MB) of the largest process of one `baobab run cafe_delivery`.

    Taken in a wrapper process: RUSAGE_CHILDREN keeps the largest child a process ever waited
    for, so in this one the earlier sections' children would count too.
    """
    process = subprocess.run(
        [
            sys.executable,
            "-c",
            "import resource, subprocess, sys\n"
            "subprocess.run(sys.argv[1:], check=False, capture_output=True)\n"
            "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n",
            *_baobab_command(),
            "run",
            "cafe_delivery",
            "--json",
            "--out",
            out,
        ],
        check=True,
        capture_output=True,
        text=True,
    )
    return int(process.stdout) / 1024


def memory_figures() -> list[Figure]:
    """Figure 6: peak resident memory of `baobab run cafe_delivery` (its largest process).

    Measured with the libraries paged in on demand and freshly read (see _set_page_cache);
    each is the larger of two runs, after a first run that warms numba's kernel cache. Pages
    mapped by a running process cannot be dropped, so :func:`main` measures this first, before
    this process loads MuJoCo, NumPy or numba itself.
    """
    libraries = _shared_libraries() if hasattr(os, "posix_fadvise") else []
    figures: list[Figure] = []
    with tempfile.TemporaryDirectory() as out:
        _peak_memory_mb(f"{out}/warm")
        for label, read in (("paged in on demand", False), ("freshly read", True)):
            peaks = []
            for index in range(2):
                _set_page_cache(libraries, read=read)
                peaks.append(_peak_memory_mb(f"{out}/{label}-{index}"))
            figures.append(
                Figure(
                    f"peak memory of one mission run (libraries {label})",
                    max(peaks),
                    "MB",
                    300.0,
                    False,
                    "baobab run cafe_delivery (ru_maxrss of its largest process)",
                )
            )
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
    """Figure 7: wall time of the whole test suite with two workers."""
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
    "missions": mission_figures,
    "planner": planner_figures,
    "getpath": get_path_figures,
    "startup": startup_figures,
    "arm": arm_figures,
    "memory": memory_figures,
    "ros": ros_figures,
    "scripts": script_sleep_figures,
}
OPTIONAL_SECTIONS: dict[str, Callable[[], list[Figure]]] = {
    "longrun": longrun_figures,
    "badinputs": bad_input_figures,
}
"""Sections that take several minutes each: measured only when named with --only."""


def main() -> None:
    """Measure, print the table, write bench.json."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--only", nargs="+", choices=sorted(SECTIONS | OPTIONAL_SECTIONS), default=None
    )
    parser.add_argument("--with-tests", action="store_true", help="also time the test suite")
    parser.add_argument("--output", default="bench.json")
    args = parser.parse_args()
    os.environ.setdefault("MUJOCO_GL", "egl")
    figures: list[Figure] = []
    chosen = args.only or list(SECTIONS)
    for name in sorted(chosen, key=lambda section: section != "memory"):  # memory first
        print(f"measuring {name} ...", file=sys.stderr)
        figures.extend((SECTIONS | OPTIONAL_SECTIONS)[name]())
    if args.with_tests:
        figures.extend(test_suite_figures())
    width = max(len(figure.name) for figure in figures)
    print(f"{'figure':<{width}}  {'value':>10}  {'target':>10}  met?")
    for figure in figures:
        relation = ">=" if figure.higher_is_better else "<="
        print(
            f"{figure.name:<{width}}  {figure.value:>8.2f} {figure.unit:<4}"
            f" {relation}{figure.target:>7g}  {'yes' if figure.met else 'NO'}"
        )
    report = [{**asdict(figure), "met": figure.met} for figure in figures]
    Path(args.output).write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
