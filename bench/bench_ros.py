"""How fast node code runs against the simulation: ``baobab ros run`` figures (issue 25).

Run: ``python bench/bench_ros.py [--output report.json]``. Each case runs the same node files
three times in this process and keeps the fastest loop (the first run also compiles the
kernels' caches, which is start-up, not speed); the loop is :meth:`RosRuntime.run`, from the
first sim instant to the end, node code, topics and physics included. The bare figure steps a
fresh MjData of the same model with ``mj_step`` for the same sim time, right after the runs.

Cases:
* ``go_to_goal``: the seed's point-to-point node (missions/ros/point2point_nav.py), a 0.05 s
  timer reading TF, in the walls world; a goal at (2, 2) sent on /goal at 1 s; 25 s of sim time.
* ``panda_planner``: the seed's trajectory planner (tests/ros_nodes/exercise_pose_publisher.py)
  publishing at 100 Hz to the Panda's impedance controller; a 3 s goal; 5 s of sim time.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import mujoco

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))

from ros_harness import BUNDLED_NODES, ROS_NODES, run_node_files  # noqa: E402

from baobab.nav.ros.bringup import bring_up  # noqa: E402


def _goal(runtime: Any) -> None:
    from geometry_msgs.msg import PoseStamped

    goal = PoseStamped()
    goal.header.frame_id = "odom"
    goal.pose.position.x, goal.pose.position.y = 2.0, 2.0
    runtime.publish_at(1.0, "/goal", goal)


def _case(robot: str, node: Path, duration: float, **options: Any) -> dict[str, float]:
    loops, wholes = [], []
    for _ in range(3):
        began = time.perf_counter()
        bringup = bring_up(robot, "walls" if robot == "turtlebot3" else None)
        runtime = bringup.runtime
        timed: dict[str, float] = {}
        original = runtime.run

        def run(seconds: float, original: Any = original, timed: dict[str, float] = timed) -> Any:
            start = time.perf_counter()
            try:
                return original(seconds)
            finally:
                timed["loop"] = time.perf_counter() - start

        runtime.run = run  # type: ignore[method-assign]
        end = run_node_files(runtime, [node], duration, **options)
        assert end.failures == [], end.failures
        wholes.append(time.perf_counter() - began)
        loops.append(timed["loop"])
    model = runtime.sim.model if runtime.sim is not None else None
    assert model is not None
    data = mujoco.MjData(model)
    start = time.perf_counter()
    mujoco.mj_step(model, data, round(end.sim_time / model.opt.timestep))
    bare = time.perf_counter() - start
    return {
        "sim_time": end.sim_time,
        "loop_seconds": min(loops),
        "rtf_loop": end.sim_time / min(loops),
        "rtf_with_bringup": end.sim_time / min(wholes),
        "bare_seconds": bare,
        "loop_over_bare": min(loops) / bare,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path, default=None)
    args = parser.parse_args()
    report = {
        "go_to_goal": _case("turtlebot3", BUNDLED_NODES / "point2point_nav.py", 25.0, before=_goal),
        "panda_planner": _case(
            "panda",
            ROS_NODES / "exercise_pose_publisher.py",
            5.0,
            args=["--ros-args", "-p", "goal:=[3.0, 0.45, 0.2, 0.35, 1.0, 0.0, 0.0, 0.0]"],
        ),
    }
    text = json.dumps(report, indent=2)
    print(text)
    if args.output is not None:
        args.output.write_text(text)


if __name__ == "__main__":
    main()
