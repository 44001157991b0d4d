"""baobab against pyrobosim (the closest pure-Python peer), the cafe round trip, issue 28.

Run: ``python bench/bench_pyrobosim.py [--pyrobosim-python PATH] [--repeats 9] [--output F]``.

pyrobosim is no dependency of baobab: install it in a venv of its own
(``python3 -m venv /tmp/pyrobosim && /tmp/pyrobosim/bin/pip install pyrobosim==5.0.1``) and pass
that venv's Python with ``--pyrobosim-python`` (or set ``BAOBAB_PYROBOSIM_PYTHON``). Without
it the bench says so and exits 0.

The job, for both: the cafe's kitchen (-0.3, 7.3) to table 3's serving point (0.792, -8.27)
and back to the kitchen, one goal after the other, as fast as each can run:

- baobab: ``BasicNavigator`` in the bundled cafe, ``setInitialPose`` at the kitchen, then
  ``goToPose`` and ``isTaskComplete``/``getFeedback`` polls to the end of each goal;
- pyrobosim: the same room and doorway as a pyrobosim world (dining room, kitchen, the 1.8 m
  doorway as a hallway; the tables as pyrobosim ``table`` locations), A* on a 0.05 m grid
  inflated by the Burger's radius, ``robot.navigate(goal, realtime_factor=-1)`` at the
  Burger's speed (0.22 m/s, 2.84 rad/s) and 20 Hz trajectory steps (``dt = 0.05``). Two
  variants: as shipped, and with the executor's ``time.sleep`` calls made no-ops (its fixed
  0.1 s at the end of every path is most of a short run's wall time).

Each repetition runs baobab, then both pyrobosim variants, each in a fresh process
(interleaved, so both see the same machine load); the figure of a process is sim seconds per
wall second of the round trip itself (set-up, imports and world loading are reported apart).
Sim seconds are each simulator's own: baobab's physics clock from the first goal to the end
of the second, pyrobosim's trajectory time (the sum of its two trajectories' durations).
The paired ratio of one repetition is baobab's figure over pyrobosim's; the report gives the
median and range of the nine.

What is and is not comparable (also in README.md, "baobab beside pyrobosim"): both plan on a
0.05 m grid and drive the same distance at the same top speed, and both report sim time per
wall time; but pyrobosim is kinematic (it sets the robot's pose along a constant-velocity
trajectory: no dynamics, no sensors, no costmaps, no controller, no replanning), while baobab
steps rigid-body physics at 200 Hz with a 360-beam lidar, two costmaps, a 20 Hz controller and
1 Hz replanning. baobab's robot accelerates, slows for turns and the goal, so its sim time for
the trip is longer than pyrobosim's trajectory time.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

KITCHEN = (-0.3, 7.3, 1.5708)
"""The cafe's kitchen location (m, m, rad)."""
TABLE_3 = (0.792, -8.27, 0.0)
"""Table 3's serving point (m, m, rad)."""
BURGER_RADIUS = 0.105
"""TurtleBot3 Burger footprint radius (m)."""
BURGER_SPEED = (0.22, 2.84)
"""TurtleBot3 Burger top speeds: linear (m/s), angular (rad/s)."""
STEP = 0.05
"""pyrobosim's trajectory step (s): 20 Hz, baobab's controller rate."""
VARIANTS = ("pyrobosim", "pyrobosim_no_sleep")


def baobab_round_trip() -> dict[str, float]:
    """The round trip with baobab's BasicNavigator (runs in a fresh process)."""
    began = time.perf_counter()
    from baobab.nav import msgs
    from baobab.nav.navigator import BasicNavigator
    from baobab.sim.errors import BaobabError

    navigator = BasicNavigator(world="cafe", seed=0)
    navigator.setInitialPose(msgs.pose_stamped(*KITCHEN))
    navigator.waitUntilNav2Active()
    setup = time.perf_counter() - began
    clock = navigator.get_clock()
    sim_start = clock.now().nanoseconds / 1e9
    start, cpu_start = time.perf_counter(), time.process_time()
    for x, y, yaw in (TABLE_3, KITCHEN):
        navigator.goToPose(msgs.pose_stamped(x, y, yaw, stamp=clock.now()))
        while not navigator.isTaskComplete():
            navigator.getFeedback()
        if navigator.getResult().name != "SUCCEEDED":
            raise BaobabError(f"baobab did not reach ({x}, {y}): {navigator.getTaskError()}")
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu_start
    sim = clock.now().nanoseconds / 1e9 - sim_start
    return {"sim_s": sim, "wall_s": wall, "cpu_s": cpu, "setup_s": setup}


def _pyrobosim_world() -> dict[str, Any]:
    """The cafe as a pyrobosim world description (see the module docstring)."""
    tables = [(-2.0, -0.6), (2.2, -4.55), (1.6, -8.95), (-4.0, -8.2), (-3.5, -3.3)]
    return {
        "params": {"name": "cafe", "object_radius": 0.0375},
        "metadata": {"locations": ["$DATA/example_location_data_furniture.yaml"]},
        "robots": [
            {
                "name": "burger",
                "radius": BURGER_RADIUS,
                "pose": {"position": {"x": KITCHEN[0], "y": KITCHEN[1]}},
                "max_linear_velocity": BURGER_SPEED[0],
                "max_angular_velocity": BURGER_SPEED[1],
                "path_planner": {
                    "type": "astar",
                    "grid_resolution": 0.05,
                    "grid_inflation_radius": BURGER_RADIUS,
                },
                "path_executor": {
                    "type": "constant_velocity",
                    "linear_velocity": BURGER_SPEED[0],
                    "max_angular_velocity": BURGER_SPEED[1],
                    "dt": STEP,
                    "validate_during_execution": False,
                },
            }
        ],
        "rooms": [
            {
                "name": "dining",
                "footprint": {"type": "box", "dims": [8.6, 13.6]},
                "pose": {"position": {"x": -0.7, "y": -3.4}},
                "wall_width": 0.2,
            },
            {
                "name": "kitchen",
                "footprint": {"type": "box", "dims": [8.6, 4.6]},
                "pose": {"position": {"x": -0.7, "y": 6.3}},
                "wall_width": 0.2,
            },
        ],
        "hallways": [
            {
                "room_start": "dining",
                "room_end": "kitchen",
                "width": 1.8,
                "conn_method": "points",
                "conn_points": [[1.5, 2.9], [1.5, 4.5]],
            }
        ],
        "locations": [
            {
                "name": f"table_{index}",
                "category": "table",
                "parent": "dining",
                "pose": {"position": {"x": x, "y": y}},
            }
            for index, (x, y) in enumerate(tables, start=1)
        ],
    }


def pyrobosim_round_trip(no_sleep: bool) -> dict[str, float]:
    """The round trip in pyrobosim (runs in a fresh process of pyrobosim's venv)."""
    began = time.perf_counter()
    from pyrobosim.core import WorldYamlLoader
    from pyrobosim.navigation import execution
    from pyrobosim.utils.general import get_data_folder
    from pyrobosim.utils.pose import Pose

    if no_sleep:

        class _NoSleep:
            time = staticmethod(time.time)

            @staticmethod
            def sleep(_seconds: float) -> None:
                return None

        execution.time = _NoSleep  # type: ignore[assignment]
    world = WorldYamlLoader().from_yaml(_pyrobosim_world(), world_dir=get_data_folder())
    robot = world.robots[0]
    setup = time.perf_counter() - began
    sim = 0.0
    start, cpu_start = time.perf_counter(), time.process_time()
    for x, y, yaw in (TABLE_3, KITCHEN):
        result = robot.navigate(goal=Pose(x=x, y=y, yaw=yaw), realtime_factor=-1.0)
        if not result.is_success():
            raise RuntimeError(f"pyrobosim did not reach ({x}, {y}): {result.message}")
        sim += float(robot.path_executor.traj.t_pts[-1])
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu_start
    world.shutdown()
    return {"sim_s": sim, "wall_s": wall, "cpu_s": cpu, "setup_s": setup}


def _child(python: str, kind: str) -> dict[str, float]:
    """One round trip in a fresh process; its figures."""
    began = time.perf_counter()
    completed = subprocess.run(
        [python, __file__, "--child", kind],
        capture_output=True,
        text=True,
        check=True,
        env={**os.environ, "MUJOCO_GL": "egl"},
    )
    figures: dict[str, float] = json.loads(completed.stdout.strip().splitlines()[-1])
    figures["process_s"] = time.perf_counter() - began
    return figures


def _pyrobosim_python(given: str | None) -> str | None:
    """A Python that imports pyrobosim: ``given``, the environment's, or this one; else None."""
    for candidate in (given, os.environ.get("BAOBAB_PYROBOSIM_PYTHON"), sys.executable):
        if not candidate:
            continue
        try:
            probe = subprocess.run(
                [candidate, "-c", "import pyrobosim"], capture_output=True, check=False
            )
        except OSError:  # no such interpreter
            continue
        if probe.returncode == 0:
            return candidate
    return None


def measure(pyrobosim_python: str, repeats: int) -> dict[str, Any]:
    """Interleaved repetitions and their paired ratios."""
    runs: dict[str, list[dict[str, float]]] = {"baobab": [], **{v: [] for v in VARIANTS}}
    load = [os.getloadavg()[0]]
    for repeat in range(repeats):
        runs["baobab"].append(_child(sys.executable, "baobab"))
        for variant in VARIANTS:
            runs[variant].append(_child(pyrobosim_python, variant))
        load.append(os.getloadavg()[0])
        print(f"  repetition {repeat + 1}/{repeats} done", file=sys.stderr)
    report: dict[str, Any] = {"runs": runs, "load_average_1min": load}
    for clock in ("wall", "cpu"):
        factors = {
            kind: [run["sim_s"] / run[f"{clock}_s"] for run in kind_runs]
            for kind, kind_runs in runs.items()
        }
        for kind, values in factors.items():
            report[f"{kind}_sim_per_{clock}_median"] = statistics.median(values)
        for variant in VARIANTS:
            paired = [b / p for b, p in zip(factors["baobab"], factors[variant], strict=True)]
            report[f"paired_{clock}_ratio_vs_{variant}"] = {
                "median": statistics.median(paired),
                "min": min(paired),
                "max": max(paired),
            }
    return report


def main() -> None:
    """Measure and print (or, without pyrobosim, say why not and exit 0)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pyrobosim-python", default=None)
    parser.add_argument("--repeats", type=int, default=9)
    parser.add_argument("--output", default=None)
    parser.add_argument("--child", choices=("baobab", *VARIANTS), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child == "baobab":
        print(json.dumps(baobab_round_trip()))
        return
    if args.child is not None:
        print(json.dumps(pyrobosim_round_trip(no_sleep=args.child == "pyrobosim_no_sleep")))
        return
    python = _pyrobosim_python(args.pyrobosim_python)
    if python is None:
        print(
            "skipped: pyrobosim is not installed (pip install pyrobosim==5.0.1 into a venv of "
            "its own and pass its Python with --pyrobosim-python)"
        )
        if args.output:
            Path(args.output).write_text(json.dumps({"skipped": "pyrobosim not installed"}))
        return
    report = measure(python, args.repeats)
    runs = report["runs"]
    print(f"cafe round trip, {args.repeats} interleaved repetitions, medians:")
    for kind in runs:
        sims = statistics.median(run["sim_s"] for run in runs[kind])
        print(
            f"  {kind:<20} sim s per wall s {report[f'{kind}_sim_per_wall_median']:7.1f}, "
            f"per CPU s {report[f'{kind}_sim_per_cpu_median']:7.1f} "
            f"(sim {sims:.1f} s per round trip)"
        )
    for clock in ("wall", "cpu"):
        for variant in VARIANTS:
            paired = report[f"paired_{clock}_ratio_vs_{variant}"]
            print(
                f"  baobab / {variant:<19} paired ratio of sim s per {clock} s "
                f"{paired['median']:.2f} ({paired['min']:.2f}..{paired['max']:.2f})"
            )
    print(f"  load average (1 min) during the run: {report['load_average_1min']}")
    if args.output:
        Path(args.output).write_text(json.dumps(report, indent=2) + "\n")


if __name__ == "__main__":
    main()
