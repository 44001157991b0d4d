"""Unmodified Nav2 Simple Commander scripts run against baobab (``baobab nav2``).

The seed's three scripts (seed 001: waypoint follower in the cafe, navigation through 41 poses
on the farm, navigation to a pose in the town) are extracted from the seed text at test time
and run as they are; the tests skip when the shared folder is absent. Our own examples in
``examples/`` always run. Runs happen in-process through the CLI, except one in a subprocess.
Each in-process run records the navigator's final pose and result, and watches for contacts.
"""

from __future__ import annotations

import re
import subprocess
import sys
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from navigation_rig import ContactWatch, distance

from baobab.missions.cli.command_line import main
from baobab.nav.navigator import BasicNavigator, TaskResult
from baobab.sim.world import Pose2D

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO / ".." / "shared"
EXAMPLES = REPO / "examples"
SEND_CALLS = {
    "waypoint_follower": "followWaypoints",
    "nav_through_poses": "goThroughPoses",
    "nav_to_pose": "goToPose",
}
SEED_WORLDS = {"waypoint_follower": "cafe", "nav_through_poses": "farm", "nav_to_pose": "town"}


def seed_scripts() -> dict[str, str]:
    """The seed's Nav2 scripts by name, cut out of the tutorial text; skip without the seeds."""
    folder = SHARED / "seeds"
    if not folder.is_dir():
        pytest.skip(f"no shared seeds at {folder.resolve()}")
    scripts: dict[str, str] = {}
    pattern = re.compile(
        r"#! /usr/bin/env python3\n.*?\nif __name__ == '__main__':\n  main\(\)\n", re.S
    )
    for seed in sorted(folder.glob("*.txt")):
        for script in pattern.findall(seed.read_text(encoding="utf-8")):
            for name, call in SEND_CALLS.items():
                if f"navigator.{call}(" in script and "BasicNavigator" in script:
                    scripts.setdefault(name, script)
    if len(scripts) != len(SEND_CALLS):
        pytest.skip(f"the seeds hold only {sorted(scripts)}")
    return scripts


def last_goal_before_send(script: str, name: str) -> Pose2D:
    """The last goal pose a script builds before it sends its task (x, y only)."""
    head = script[: script.index(f"navigator.{SEND_CALLS[name]}(")]
    xs = re.findall(r"goal_pose\.pose\.position\.x = (-?[\d.]+)", head)
    ys = re.findall(r"goal_pose\.pose\.position\.y = (-?[\d.]+)", head)
    return Pose2D(x=float(xs[-1]), y=float(ys[-1]))


@dataclass
class Recorded:
    """What a script's navigator did: its final pose, result and contacts."""

    final_pose: Pose2D | None = None
    result: TaskResult | None = None
    sim_time: float = 0.0
    contacts: list[ContactWatch] = field(default_factory=list)


@pytest.fixture
def recorded(monkeypatch: pytest.MonkeyPatch) -> Iterator[Recorded]:
    """Record every navigator a script builds in this test."""
    record = Recorded()
    build, destroy = BasicNavigator.__init__, BasicNavigator.destroy_node

    def watched_build(self: BasicNavigator, *args: object, **kwargs: object) -> None:
        build(self, *args, **kwargs)  # type: ignore[arg-type]
        record.contacts.append(ContactWatch(self.server.sim, "tb3/base_link"))

    def recording_destroy(self: BasicNavigator) -> None:
        if record.final_pose is None:
            record.final_pose = self.robot_pose()
            record.result = self.getResult()
            record.sim_time = self.get_clock().now().nanoseconds / 1e9
        destroy(self)

    monkeypatch.setattr(BasicNavigator, "__init__", watched_build)
    monkeypatch.setattr(BasicNavigator, "destroy_node", recording_destroy)
    yield record


def run(script: Path, world: str, *options: str) -> int:
    return main(["nav2", str(script), "--world", world, *options])


def distances_printed(out: str) -> list[float]:
    return [float(value) for value in re.findall(r"Distance remaining: ([\d.]+)", out)]


# --- the seed's scripts, unmodified -----------------------------------------------------------


def run_seed(
    name: str, tmp_path: Path, capsys: pytest.CaptureFixture[str], recorded: Recorded
) -> tuple[str, Pose2D]:
    script_text = seed_scripts()[name]
    script = tmp_path / f"{name}.py"
    script.write_text(script_text, encoding="utf-8")
    assert run(script, SEED_WORLDS[name]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[-1] == "Goal succeeded!"
    assert recorded.result is TaskResult.SUCCEEDED and recorded.final_pose is not None
    assert not any(watch.touched for watch in recorded.contacts)
    goal = last_goal_before_send(script_text, name)
    assert distance(recorded.final_pose, goal) <= 0.25
    return out, goal


def test_seed_nav_to_pose_reaches_the_town_goal_before_its_preemption(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], recorded: Recorded
) -> None:
    out, goal = run_seed("nav_to_pose", tmp_path, capsys, recorded)
    assert goal == Pose2D(x=10.0, y=-2.0)
    distances = distances_printed(out)
    assert distances[0] > 9.5 and distances[-1] < 0.5
    # The seed moves the goal to x = -3 after 120 s of navigation; the robot is there sooner.
    assert recorded.sim_time < 120.0


def test_seed_waypoint_follower_serves_the_cafe(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], recorded: Recorded
) -> None:
    out, goal = run_seed("waypoint_follower", tmp_path, capsys, recorded)
    assert goal == Pose2D(x=0.0, y=0.0)
    shown = [int(k) for k in re.findall(r"Executing current waypoint: (\d)/6", out)]
    assert shown == sorted(shown) and shown[0] == 1 and shown[-1] == 6
    assert set(shown) == {1, 2, 3, 4, 5, 6}


def test_seed_nav_through_41_farm_poses(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], recorded: Recorded
) -> None:
    out, goal = run_seed("nav_through_poses", tmp_path, capsys, recorded)
    assert goal == Pose2D(x=13.0, y=4.2)
    distances = distances_printed(out)
    assert max(distances) > 80.0 and distances[-1] < 0.5


# --- our examples ---------------------------------------------------------------------------


def test_example_nav_to_pose_preempts_under_baobab_nav2_in_a_subprocess() -> None:
    completed = subprocess.run(
        [
            sys.executable,
            "-c",
            "import sys; from baobab.missions.cli.command_line import main; sys.exit(main())",
            "nav2",
            str(EXAMPLES / "nav_to_pose.py"),
            "--world",
            "town",
            "--seed",
            "4",
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert completed.returncode == 0, completed.stderr
    lines = completed.stdout.splitlines()
    assert lines[-1] == "Goal succeeded!"
    changed = lines.index("Goal changed to x = -1.0.")
    before, after = (
        distances_printed("\n".join(part)) for part in (lines[:changed], lines[changed:])
    )
    # Preempted mid-way, the new goal lies behind the robot: it turns round and gets there.
    assert before[0] > 7.5 and before[-1] > 4.0
    assert after[0] > 2.0 and after[-1] < 0.5
    assert "[INFO]" in completed.stderr and "[INFO]" not in completed.stdout


def test_example_waypoint_follower(capsys: pytest.CaptureFixture[str], recorded: Recorded) -> None:
    assert run(EXAMPLES / "waypoint_follower.py", "cafe") == 0
    out = capsys.readouterr().out
    assert out.splitlines()[-1] == "Goal succeeded!" and "Missed" not in out
    assert "Executing current waypoint: 3/3" in out
    assert recorded.final_pose is not None
    assert distance(recorded.final_pose, Pose2D(x=0.9, y=2.8)) <= 0.25
    assert not any(watch.touched for watch in recorded.contacts)


def test_example_route_follower_drives_the_towns_route_graph(
    capsys: pytest.CaptureFixture[str], recorded: Recorded
) -> None:
    assert run(EXAMPLES / "route_follower.py", "town") == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("Route [3, 13, 14, 15, 22] of cost 18.12")
    assert "Passed node 15, on edge 134 to node 22" in out
    assert out[-2:] == ["Reached node 22", "Goal succeeded!"]
    assert recorded.final_pose is not None
    assert distance(recorded.final_pose, Pose2D(x=11.0, y=-6.0)) <= 0.25
    assert not any(watch.touched for watch in recorded.contacts)


def test_example_gps_waypoint_follower_ends_where_the_waypoints_lie_in_the_farm(
    capsys: pytest.CaptureFixture[str], recorded: Recorded
) -> None:
    assert run(EXAMPLES / "gps_waypoint_follower.py", "farm") == 0
    out = capsys.readouterr().out
    assert out.splitlines()[-1] == "Goal succeeded!"
    assert recorded.final_pose is not None
    assert distance(recorded.final_pose, Pose2D(x=6.0, y=-2.2)) <= 0.25  # the datum's plane
    assert not any(watch.touched for watch in recorded.contacts)


def test_example_nav_through_poses(capsys: pytest.CaptureFixture[str], recorded: Recorded) -> None:
    assert run(EXAMPLES / "nav_through_poses.py", "farm") == 0
    out = capsys.readouterr().out
    assert out.splitlines()[-1] == "Goal succeeded!"
    remaining = [int(n) for n in re.findall(r"poses remaining: (\d)", out)]
    assert remaining[0] == 3 and remaining[-1] == 1
    assert recorded.final_pose is not None
    assert distance(recorded.final_pose, Pose2D(x=-5.0, y=-2.2)) <= 0.25
    assert not any(watch.touched for watch in recorded.contacts)


def test_example_follow_path_keeps_to_its_smoothed_path(
    capsys: pytest.CaptureFixture[str], recorded: Recorded
) -> None:
    assert run(EXAMPLES / "follow_path.py", "cafe") == 0
    out = capsys.readouterr().out
    assert out.splitlines()[-1] == "Goal succeeded!"
    errors = [abs(float(e)) for e in re.findall(r"off the path: ([-+][\d.]+) m", out)]
    assert errors and max(errors) < 0.15
    assert recorded.final_pose is not None
    assert distance(recorded.final_pose, Pose2D(x=1.16, y=-4.23)) <= 0.25
    assert not any(watch.touched for watch in recorded.contacts)


def test_example_recoveries_backs_up_spins_and_drives_home(
    capsys: pytest.CaptureFixture[str], recorded: Recorded
) -> None:
    assert run(EXAMPLES / "recoveries.py", "cafe") == 0
    out = capsys.readouterr().out
    assert out.splitlines()[-1] == "Goal succeeded!"
    backed = [float(d) for d in re.findall(r"Backing up: ([\d.]+) m", out)]
    turned = [float(a) for a in re.findall(r"Spinning: ([\d.]+) rad", out)]
    assert backed == sorted(backed) and 0.2 < backed[-1] <= 0.3
    assert turned == sorted(turned) and 2.5 < turned[-1] <= 3.14
    assert recorded.final_pose is not None
    assert distance(recorded.final_pose, Pose2D(x=0.0, y=0.0)) <= 0.25


def test_example_picking_delivers_from_the_kitchen(
    capsys: pytest.CaptureFixture[str], recorded: Recorded
) -> None:
    assert run(EXAMPLES / "picking.py", "cafe") == 0
    lines = capsys.readouterr().out.splitlines()
    assert "Got the order at the kitchen; taking it to table_3." in lines
    assert lines[-1] == "Order delivered!"
    assert recorded.final_pose is not None
    assert distance(recorded.final_pose, Pose2D(x=0.792, y=-8.27)) <= 0.25


def test_example_security_patrol_goes_there_and_back(
    capsys: pytest.CaptureFixture[str], recorded: Recorded
) -> None:
    assert run(EXAMPLES / "security_patrol.py", "farm") == 0
    lines = capsys.readouterr().out.splitlines()
    assert "Round 1 done, patrolling back." in lines and lines[-1] == "Patrol complete!"
    assert recorded.final_pose is not None
    assert distance(recorded.final_pose, Pose2D(x=-6.5, y=-4.2)) <= 0.25  # back at the start


def test_example_assisted_teleop_stops_short_of_the_wall_while_the_script_sleeps(
    capsys: pytest.CaptureFixture[str], recorded: Recorded
) -> None:
    assert run(EXAMPLES / "assisted_teleop.py", "walls") == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[-1] == "Assisted teleop succeeded!"
    durations = [float(d) for d in re.findall(r"Teleop for ([\d.]+) s", "\n".join(lines))]
    # Each poll: isTaskComplete's 0.1 s, then time.sleep(0.2) of sim time.
    assert durations[1] - durations[0] == pytest.approx(0.3)
    assert 12.0 <= recorded.sim_time < 12.6
    assert recorded.final_pose is not None
    assert 0.6 < recorded.final_pose.x < 1.15 - 0.105  # driven, stopped short of wall_east
    assert not any(watch.touched for watch in recorded.contacts)


ROUTE_SCRIPT = """\
import rclpy
from geometry_msgs.msg import PoseStamped
from nav2_simple_commander.robot_navigator import BasicNavigator, RunningTask, TaskResult
from nav2_simple_commander.utils import euler_to_quaternion


def pose(navigator, x, y, yaw):
    p = PoseStamped()
    p.header.frame_id = "map"
    p.header.stamp = navigator.get_clock().now().to_msg()
    p.pose.position.x, p.pose.position.y = x, y
    p.pose.orientation = euler_to_quaternion(0.0, 0.0, yaw)
    return p


rclpy.init()
navigator = BasicNavigator()
navigator.declare_parameter("start", [0.0, 0.0, 0.0])
navigator.declare_parameter("goal", [2.0, 1.0, 0.0])
start = navigator.get_parameter("start").value
goal = navigator.get_parameter("goal").value
navigator.waitUntilNav2Active()
task = navigator.getAndTrackRoute(pose(navigator, *start), pose(navigator, *goal))
while not navigator.isTaskComplete(task=RunningTask.COMPUTE_AND_TRACK_ROUTE):
    feedback = navigator.getFeedback(task=RunningTask.COMPUTE_AND_TRACK_ROUTE)
print(task, navigator.getTaskError()[0], navigator.getResult().name)
navigator.lifecycleShutdown()
"""


def test_a_rolling_route_script_runs_and_its_route_task_fails_cleanly(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = tmp_path / "route.py"
    script.write_text(ROUTE_SCRIPT, encoding="utf-8")
    assert run(script, "walls") == 0  # imports nav2_simple_commander.utils, reads parameters
    captured = capsys.readouterr()
    assert captured.out == "None 400 UNKNOWN\n"  # ComputeAndTrackRoute's UNKNOWN: no server
    assert "'ComputeAndTrackRoute' action server ('compute_and_track_route') not available" in (
        captured.err
    )


# --- the command line -----------------------------------------------------------------------

SHOW_START = """\
import rclpy
from nav2_simple_commander.robot_navigator import BasicNavigator

rclpy.init()
navigator = BasicNavigator()
pose = navigator.robot_pose()
print(navigator.world.name, round(pose.x, 3), round(pose.y, 3), round(pose.yaw, 3))
navigator.spin(0.3)
while not navigator.isTaskComplete():
    pass
print(navigator.getResult().name, navigator.get_clock().now().nanoseconds > 0)
exit(3)
"""


def test_options_reach_the_navigator_and_the_exit_status_passes_through(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = tmp_path / "show_start.py"
    script.write_text(SHOW_START, encoding="utf-8")
    assert run(script, "farm", "--start=-5.0,-4.2,0.5", "--seed", "7", "--realtime") == 3
    assert capsys.readouterr().out.splitlines() == ["farm -5.0 -4.2 0.5", "SUCCEEDED True"]
    assert run(script, "cafe", "--start", "1,1") == 3
    assert capsys.readouterr().out.splitlines()[0] == "cafe 1.0 1.0 0.0"


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--world", "atlantis"], "unknown world 'atlantis'"),
        (["--world", "cafe", "--start", "1,x"], "--start: expected X,Y,YAW"),
        (["--world", "cafe", "--start=1,2,3,4"], "--start: expected X,Y,YAW"),
        (["--world", "cafe", "--start=-2.0,-0.6"], "'table_1'"),
        (["--world", "cafe", "--seed", "-1"], "--seed: expected a non-negative"),
        (["--world", "cafe", "--seed", "1.5"], "--seed: expected a non-negative"),
    ],
)
def test_bad_arguments_exit_2_with_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], options: list[str], message: str
) -> None:
    script = tmp_path / "never_runs.py"
    script.write_text("print('ran')\n", encoding="utf-8")
    assert main(["nav2", str(script), *options]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.splitlines()
    assert len(lines) == 1 and message in lines[0]


def test_a_missing_script_exits_2_with_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert run(tmp_path / "absent.py", "cafe") == 2
    assert capsys.readouterr().err.splitlines() == [f"{tmp_path / 'absent.py'}:1:1: no such file"]
