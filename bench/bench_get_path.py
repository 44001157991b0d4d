"""``BasicNavigator.getPath`` for the 16.2 m cafe query (kitchen to table 3), issue 28.

Run: ``python bench/bench_get_path.py [--repeats 31] [--output report.json]``.

Times, interleaved in one process (median of ``--repeats`` calls each, wall ms):

- ``getPath`` as shipped: planning, smoothing and a ``nav_msgs/Path`` whose poses are made
  when first read;
- ``getPath`` and reading ``len(path.poses)`` (every pose message made, vectorised);
- ``getPath`` then ``smoothPath`` of its result (the path goes back unconverted);
- the planner alone (``NavigationServer.compute_path``: A* and smoothing);
- the conversion before issue 28, one scipy ``Rotation.from_euler`` and checked message per
  pose, on the same planner path (the reference the tests compare against).

The navigator logs to stderr; it is sent to /dev/null here, so terminal speed is not counted.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import statistics
import sys
import time
from collections.abc import Callable
from typing import Any

from scipy.spatial.transform import Rotation

from baobab.nav import msgs
from baobab.nav.navigator import BasicNavigator
from baobab.nav.path import Path
from baobab.sim.world import load_world


def scipy_path_message(path: Path, stamp: msgs.TimeMsg) -> msgs.Path:
    """The conversion before issue 28: every pose's quaternion from scipy, built eagerly."""
    poses = []
    for x, y, yaw in path.poses.tolist():
        qx, qy, qz, qw = (float(v) for v in Rotation.from_euler("z", yaw).as_quat())
        poses.append(
            msgs.PoseStamped(
                header=msgs.Header(
                    stamp=msgs.TimeMsg(sec=stamp.sec, nanosec=stamp.nanosec), frame_id="map"
                ),
                pose=msgs.Pose(
                    position=msgs.Point(x=x, y=y),
                    orientation=msgs.Quaternion(x=qx, y=qy, z=qz, w=qw),
                ),
            )
        )
    return msgs.Path(header=msgs.Header(stamp=stamp, frame_id="map"), poses=poses)


def measure(repeats: int) -> dict[str, Any]:
    """Median wall ms of each variant (module docstring), interleaved."""
    world = load_world("cafe")
    navigator = BasicNavigator(world=world, seed=0)
    start, goal = (msgs.from_pose2d(world.pose(name)) for name in ("kitchen", "table_3"))
    server = navigator._live_server()
    planner_path = server.compute_path(world.pose("kitchen"), world.pose("table_3"))
    variants: dict[str, Callable[[], object]] = {
        "getPath": lambda: navigator.getPath(start, goal, use_start=True),
        "getPath, poses read": lambda: len(navigator.getPath(start, goal, use_start=True).poses),
        "getPath then smoothPath": lambda: navigator.smoothPath(
            navigator.getPath(start, goal, use_start=True)
        ),
        "planner alone (A* and smoothing)": lambda: server.compute_path(
            world.pose("kitchen"), world.pose("table_3")
        ),
        "before: scipy per pose, eager": lambda: scipy_path_message(planner_path, msgs.TimeMsg()),
    }
    times: dict[str, list[float]] = {name: [] for name in variants}
    for _ in range(repeats):
        for name, call in variants.items():
            began = time.perf_counter()
            call()
            times[name].append((time.perf_counter() - began) * 1e3)
    return {
        "path_length_m": planner_path.length(),
        "poses": len(planner_path),
        "median_ms": {name: statistics.median(values) for name, values in times.items()},
        "load_average": os.getloadavg(),
    }


def main() -> None:
    """Measure, print, write the JSON report."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=31)
    parser.add_argument("--output", default=None)
    args = parser.parse_args()
    with open(os.devnull, "w") as quiet, contextlib.redirect_stderr(quiet):
        report = measure(args.repeats)
    print(
        f"cafe kitchen -> table_3: {report['path_length_m']:.2f} m, {report['poses']} poses "
        f"(load average {report['load_average'][0]:.1f})"
    )
    for name, value in report["median_ms"].items():
        print(f"  {name:<36} {value:8.3f} ms")
    if args.output:
        with open(args.output, "w") as out:
            json.dump(report, out, indent=2)
    sys.stdout.flush()


if __name__ == "__main__":
    main()
