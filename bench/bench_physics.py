"""Physics throughput of the TurtleBot3 in a bundled world, and the cost of a lidar scan.

Run: ``python bench/bench_physics.py [--world cafe] [--seconds 20]``. Reports, best of
``--repeats`` runs:

- bare ``mj_step`` steps/s and real-time factor, the wheels driven at constant speed;
- the same through :class:`Simulation` with the base controller (100 Hz) and the LDS-01
  (5 Hz) running as callbacks;
- microseconds per 360-beam scan (one ``mj_multiRay`` call plus the range post-processing).
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from pathlib import Path

import mujoco

from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.world import bundled_world_path


def _default_world() -> str:
    return "cafe" if Path(bundled_world_path("cafe")).exists() else "walls"


def _best_seconds(run: Callable[[], object], repeats: int) -> float:
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        best = min(best, time.perf_counter() - start)
    return best


def bench_physics(world: str | None = None, seconds: float = 20.0, repeats: int = 3) -> dict:
    """Measure the figures above in ``world`` over ``seconds`` of sim time; returns a dict."""
    world = world or _default_world()
    sim, robot = build_turtlebot3_sim(world)
    model, data = sim.model, sim.data
    steps = round(seconds / sim.physics_dt)

    # Bare physics: a gentle arc, wheel targets written straight into the actuators.
    left, right = robot.base.wheel_speeds(0.05, 0.3)
    data.actuator(robot.names.wheel_actuators[0]).ctrl[0] = left
    data.actuator(robot.names.wheel_actuators[1]).ctrl[0] = right
    state = mujoco.MjData(model)
    mujoco.mj_copyData(state, model, data)

    def bare() -> None:
        mujoco.mj_copyData(data, model, state)
        mujoco.mj_step(model, data, steps)

    bare_time = _best_seconds(bare, repeats)

    def with_callbacks() -> None:
        run_sim, run_robot = build_turtlebot3_sim(world)
        run_robot.base.command(0.05, 0.3)
        start = time.perf_counter()
        run_sim.step_for(seconds)
        timings.append(time.perf_counter() - start)

    timings: list[float] = []
    for _ in range(repeats):
        with_callbacks()
    callback_time = min(timings)

    scans = 2000
    lidar = robot.lidar
    scan_time = _best_seconds(lambda: [lidar.scan() for _ in range(scans)], repeats) / scans

    return {
        "world": world,
        "sim_seconds": seconds,
        "physics_dt": sim.physics_dt,
        "ngeom": int(model.ngeom),
        "bare_steps_per_s": steps / bare_time,
        "bare_real_time_factor": seconds / bare_time,
        "callbacks_steps_per_s": steps / callback_time,
        "callbacks_real_time_factor": seconds / callback_time,
        "lidar_scan_us": scan_time * 1e6,
    }


def main() -> None:
    """Command-line entry: print the figures as JSON."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", default=None, help="bundled world (default: cafe, or walls)")
    parser.add_argument("--seconds", type=float, default=20.0, help="sim time per run (s)")
    parser.add_argument("--repeats", type=int, default=3, help="runs; the best counts")
    args = parser.parse_args()
    print(json.dumps(bench_physics(args.world, args.seconds, args.repeats), indent=2))


if __name__ == "__main__":
    main()
