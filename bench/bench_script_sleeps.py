"""A Nav2 script that sleeps between polls against the same script without sleeps (issue 24).

Run: ``python bench/bench_script_sleeps.py [--repeats 3] [--output report.json]``.

Two scripts drive the TurtleBot3 from the town's spawn to its gas station (11, -6.2) with
``goToPose`` (about a minute of sim time) and poll ``isTaskComplete`` / ``getFeedback`` to the
end; one also calls ``time.sleep(0.2)`` after every poll, as Nav2's assisted-teleop example
does. Each runs as
``baobab nav2 SCRIPT --world town`` in a fresh process (start-up, the run and shutting down
all counted), ``--repeats`` times alternately; the median wall times are compared. Under
baobab the sleep is simulation time, so the sleeping script should take about as long as the
other (target: at most 1.5x). The sim time each script ends at is reported too.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BAOBAB = str(Path(sys.executable).with_name("baobab"))
"""The ``baobab`` command of this Python's environment."""

SCRIPT = """\
import time

import rclpy
from geometry_msgs.msg import PoseStamped
from nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult

rclpy.init()
navigator = BasicNavigator()
goal = PoseStamped()
goal.header.frame_id = "map"
goal.pose.position.x = 11.0
goal.pose.position.y = -6.2
task = navigator.goToPose(goal)
polls = 0
while not navigator.isTaskComplete(task=task):
    feedback = navigator.getFeedback(task=task)
    polls += 1
{sleep}
assert navigator.getResult() == TaskResult.SUCCEEDED
print(navigator.get_clock().now().nanoseconds / 1e9, polls)
"""


def run_script(path: Path) -> tuple[float, float, int]:
    """Wall seconds of ``baobab nav2 path --world town``, and the sim time and polls it printed."""
    began = time.perf_counter()
    completed = subprocess.run(
        [BAOBAB, "nav2", str(path), "--world", "town"],
        capture_output=True,
        text=True,
        check=True,
    )
    wall = time.perf_counter() - began
    sim, polls = completed.stdout.split()
    return wall, float(sim), int(polls)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--output", type=Path, default=Path("bench_script_sleeps.json"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        scripts = {
            "no_sleep": Path(folder) / "poll.py",
            "sleep_0.2": Path(folder) / "poll_and_sleep.py",
        }
        scripts["no_sleep"].write_text(SCRIPT.format(sleep=""), encoding="utf-8")
        scripts["sleep_0.2"].write_text(
            SCRIPT.format(sleep="    time.sleep(0.2)"), encoding="utf-8"
        )
        run_script(scripts["no_sleep"])  # warm the kernel caches
        runs: dict[str, list[tuple[float, float, int]]] = {name: [] for name in scripts}
        for _ in range(args.repeats):
            for name, path in scripts.items():
                runs[name].append(run_script(path))
    report: dict[str, object] = {}
    for name, results in runs.items():
        report[name] = {
            "wall_s": statistics.median(wall for wall, _, _ in results),
            "sim_s": results[0][1],
            "polls": results[0][2],
        }
    ratio = report["sleep_0.2"]["wall_s"] / report["no_sleep"]["wall_s"]  # type: ignore[index]
    report["ratio"] = ratio
    text = json.dumps(report, indent=2)
    args.output.write_text(text + "\n", encoding="utf-8")
    print(text)


if __name__ == "__main__":
    main()
