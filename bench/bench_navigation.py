"""Benchmark: a whole NavigateToPose run, as sim time over wall time.

Usage: ``python bench/bench_navigation.py [--world cafe] [--goal table_3] [--repeats 3]``

Each repeat builds the TurtleBot3 in the world, wires a NavigationServer to it and drives
from the spawn to the goal. It reports, best of ``--repeats``:

- the whole run's real-time factor (sim seconds per wall second), the number this benchmark
  is about;
- the same sim duration with the robot alone (base controller and lidar, no navigation),
  driven by a constant command, for the physics baseline;
- wall milliseconds per sim second spent in the navigation server's own callbacks (local and
  global costmap updates; the control tick: tree, planning, controller, feedback), from a
  separate run of a server subclass that times them.

The numba kernels are loaded (or compiled) before timing starts, by one plan in a warm-up.
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from typing import Any

from baobab.nav import build_navigation
from baobab.nav.server import NavigationServer
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.tasks import TaskStatus
from baobab.sim.world import load_world


class TimedServer(NavigationServer):
    """A navigation server that adds up the wall time of its own sim callbacks."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.totals: dict[str, float] = {"costmap_local": 0.0, "costmap_global": 0.0}
        self.totals["control"] = 0.0
        super().__init__(*args, **kwargs)

    def _timed(self, key: str, callback: Callable[[float], None], now: float) -> None:
        start = time.perf_counter()
        callback(now)
        self.totals[key] += time.perf_counter() - start

    def _update_local(self, now: float) -> None:
        self._timed("costmap_local", super()._update_local, now)

    def _update_global(self, now: float) -> None:
        self._timed("costmap_global", super()._update_global, now)

    def _on_control(self, now: float) -> None:
        self._timed("control", super()._on_control, now)


def navigation_run(world_name: str, goal_name: str, timed: bool) -> dict[str, Any]:
    """One run from the spawn to ``goal_name``; sim and wall seconds."""
    world = load_world(world_name)
    sim, robot = build_turtlebot3_sim(world)
    if timed:
        server: NavigationServer = TimedServer(sim, robot.base, world, lidar=robot.lidar)
    else:
        server = build_navigation(sim, robot.base, robot.lidar, world)
    server.compute_path(None, world.pose(goal_name))  # warm-up: load the numba kernels
    start = time.perf_counter()
    handle = server.navigate_to_pose(world.pose(goal_name))
    while handle.status is TaskStatus.RUNNING:
        sim.step_for(0.1)
    wall = time.perf_counter() - start
    outcome = handle.outcome
    totals = server.totals if isinstance(server, TimedServer) else {}
    return {
        "result": outcome.status.value if outcome else "?",
        "sim": sim.time,
        "wall": wall,
        "callbacks_ms_per_sim_s": {k: 1e3 * v / sim.time for k, v in totals.items()},
        "distance_driven": server.metrics.distance_driven,
        "plans": server.metrics.plans,
    }


def physics_run(world_name: str, duration: float) -> float:
    """Wall seconds for ``duration`` sim seconds of the robot alone (base + lidar)."""
    sim, robot = build_turtlebot3_sim(load_world(world_name))
    robot.base.command(0.1, 0.3)
    start = time.perf_counter()
    sim.step_for(round(duration, 1))
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--world", default="cafe")
    parser.add_argument("--goal", default="table_3")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    runs = [navigation_run(args.world, args.goal, False) for _ in range(args.repeats)]
    best = min(runs, key=lambda run: run["wall"])
    profiled = navigation_run(args.world, args.goal, True)
    physics = min(physics_run(args.world, best["sim"]) for _ in range(args.repeats))
    report = {
        "world": args.world,
        "goal": args.goal,
        "result": best["result"],
        "sim_seconds": round(best["sim"], 3),
        "wall_seconds": round(best["wall"], 3),
        "real_time_factor": round(best["sim"] / best["wall"], 1),
        "physics_only_real_time_factor": round(best["sim"] / physics, 1),
        "navigation_callbacks_ms_per_sim_s": {
            k: round(v, 3) for k, v in profiled["callbacks_ms_per_sim_s"].items()
        },
        "distance_driven_m": round(best["distance_driven"], 2),
        "plans": best["plans"],
    }
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
