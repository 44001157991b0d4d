"""Seed 000's rule: clear the costmaps every 0.5 s while the robot makes no forward progress.

The decorator is checked tick by tick against a scripted robot, then end to end: a robot
walled in by four spawned boxes stalls until one box is taken away, and the rule clears the
costmaps all the while (the ``costmap_clears`` metric counts the tree's clearings).
"""

from __future__ import annotations

import math
from pathlib import Path

import py_trees
import pytest

from baobab.behaviours.progress import ClearCostmapsWhenStuck, forward_speed
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.missions.run.runner import run_mission
from baobab.sim.world import Pose2D

Status = py_trees.common.Status
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
TICK = 0.1


class _Running(py_trees.behaviour.Behaviour):
    """A child that runs until told otherwise."""

    def __init__(self) -> None:
        super().__init__(name="navigate")
        self.result = Status.RUNNING

    def update(self) -> Status:
        return self.result


class _Robot:
    """A scripted robot: each tick it moves by (forward m, turn rad) and the clock advances."""

    def __init__(self) -> None:
        self.time = 0.0
        self.pose = Pose2D(x=0.0, y=0.0, yaw=0.0)
        self.clear_times: list[float] = []

    def step(self, forward: float, turn: float = 0.0) -> None:
        pose = self.pose
        self.pose = Pose2D(
            x=pose.x + forward * math.cos(pose.yaw),
            y=pose.y + forward * math.sin(pose.yaw),
            yaw=pose.yaw + turn,
        )
        self.time = round(self.time + TICK, 9)

    def clear(self) -> None:
        self.clear_times.append(self.time)


def _decorated(robot: _Robot, period: float = 0.5) -> tuple[ClearCostmapsWhenStuck, _Running]:
    child = _Running()
    rule = ClearCostmapsWhenStuck(
        "rule",
        child,
        clear=robot.clear,
        robot_pose=lambda: robot.pose,
        clock=lambda: robot.time,
        period=period,
    )
    return rule, child


def _run(rule: ClearCostmapsWhenStuck, robot: _Robot, moves: list[tuple[float, float]]) -> None:
    rule.tick_once()
    for forward, turn in moves:
        robot.step(forward, turn)
        rule.tick_once()


def test_forward_speed_is_the_displacement_along_the_earlier_heading() -> None:
    start = Pose2D(x=1.0, y=1.0, yaw=math.pi / 2)
    north, south = Pose2D(x=1.0, y=1.2, yaw=1.5), Pose2D(x=1.0, y=0.9, yaw=1.5)
    assert forward_speed(start, north, 0.1) == pytest.approx(2.0)
    assert forward_speed(start, south, 0.1) == pytest.approx(-1.0)
    sideways = Pose2D(x=1.3, y=1.0, yaw=0.0)
    assert forward_speed(start, sideways, 0.1) == pytest.approx(0.0, abs=1e-12)


def test_a_robot_standing_still_gets_its_costmaps_cleared_every_half_second() -> None:
    robot = _Robot()
    rule, _ = _decorated(robot)
    _run(rule, robot, [(0.0, 0.0)] * 20)  # 2 s
    assert robot.clear_times == [0.5, 1.0, 1.5, 2.0]
    assert rule.clears == 4 and not rule.moving_forward
    assert rule.status is Status.RUNNING


def test_driving_forward_never_clears_and_turning_or_reversing_does() -> None:
    robot = _Robot()
    rule, _ = _decorated(robot)
    _run(rule, robot, [(0.02, 0.0)] * 20)  # 0.2 m/s straight ahead for 2 s
    assert robot.clear_times == [] and rule.moving_forward
    _run(rule, robot, [(0.0, 0.1)] * 10)  # turning in place for 1 s
    assert len(robot.clear_times) == 2
    robot.clear_times.clear()
    _run(rule, robot, [(-0.015, 0.0)] * 10)  # backing up for 1 s
    assert len(robot.clear_times) == 2


def test_crawling_below_the_minimum_speed_is_no_progress() -> None:
    robot = _Robot()
    rule, _ = _decorated(robot)
    _run(rule, robot, [(0.0005, 0.0)] * 10)  # 5 mm/s, below 0.01 m/s
    assert robot.clear_times == [0.5, 1.0]


def test_the_rule_keeps_its_own_period_and_stops_with_the_child() -> None:
    robot = _Robot()
    rule, child = _decorated(robot, period=1.0)
    _run(rule, robot, [(0.0, 0.0)] * 25)
    assert robot.clear_times == [1.0, 2.0]
    child.result = Status.SUCCESS
    robot.step(0.0)
    rule.tick_once()
    assert rule.status is Status.SUCCESS
    assert robot.clear_times == [1.0, 2.0]


def test_a_fresh_activation_restarts_the_clearing_clock() -> None:
    robot = _Robot()
    rule, child = _decorated(robot)
    _run(rule, robot, [(0.0, 0.0)] * 4)  # 0.4 s: nothing due yet
    child.result = Status.FAILURE
    rule.tick_once()
    child.result = Status.RUNNING
    _run(rule, robot, [(0.0, 0.0)] * 4)
    assert robot.clear_times == []
    _run(rule, robot, [(0.0, 0.0)])
    assert robot.clear_times == [0.9]


def test_invalid_settings_are_refused() -> None:
    robot = _Robot()
    with pytest.raises(ValueError, match="period > 0"):
        ClearCostmapsWhenStuck(
            "rule", _Running(), clear=robot.clear, robot_pose=lambda: robot.pose,
            clock=lambda: robot.time, period=0.0,
        )  # fmt: skip


# --- in missions -------------------------------------------------------------------------------


def _mission(tmp_path: Path, body: str) -> Path:
    path = tmp_path / "m.yaml"
    path.write_text(HEADER + body, encoding="utf-8")
    return path


def test_mission_files_spell_the_rule_long_or_short(tmp_path: Path) -> None:
    body = (
        "mission: stuck\nworld: walls\nrobot: turtlebot3\ntree:\n  sequence:\n"
        "    - clear_costmaps_when_stuck: {navigate_to_pose: goal_open}\n"
        "    - clear_costmaps_when_stuck:\n        period: 1.5\n        which: local\n"
        "        min_speed: 0.05\n        child: {navigate_to_pose: goal_behind_wall}\n"
    )
    mission = load_mission(_mission(tmp_path, body))
    rules = [node for node in mission.tree.walk() if node.type == "clear_costmaps_when_stuck"]
    assert [node.label for node in rules] == [
        "clear_costmaps_when_stuck all every 0.5 s",
        "clear_costmaps_when_stuck local every 1.5 s",
    ]


@pytest.mark.parametrize(
    ("tree", "message"),
    [
        (
            "clear_costmaps_when_stuck: {period: 0, child: {navigate_to_pose: goal_open}}",
            r"m.yaml:6:\d+: .*period",
        ),
        (
            "clear_costmaps_when_stuck: {which: map, child: {navigate_to_pose: goal_open}}",
            r"m.yaml:6:\d+: .*which",
        ),
    ],
)
def test_bad_rule_parameters_are_located(tmp_path: Path, tree: str, message: str) -> None:
    body = f"mission: stuck\nworld: walls\nrobot: turtlebot3\ntree:\n  {tree}\n"
    with pytest.raises(MissionError, match=message):
        load_mission(_mission(tmp_path, body))


def test_the_rule_needs_a_robot_that_navigates(tmp_path: Path) -> None:
    body = "mission: arm\nrobot: panda\ntree:\n  clear_costmaps_when_stuck: {gripper: open}\n"
    with pytest.raises(MissionError, match="navigation"):
        load_mission(_mission(tmp_path, body))


# Four boxes wall the robot in half a second after the start; at 10 s the northern one is
# carried away to the far corner and the way to goal_open is free again. Only the lidar knows
# the boxes: every clearing keeps what it sees, so the robot stays clear of them while walled
# in (no_contact). Should navigation give up inside the walls, the retry sends the goal
# again, as cafe_delivery does.
WALLED_IN = """
mission: walled_in
world: walls
robot: turtlebot3
seed: 4
tree:
  retry:
    num_failures: 5
    child:
      clear_costmaps_when_stuck: {navigate_to_pose: goal_open}
events:
  - {at: 0.5, spawn_obstacle: {name: north, x: 0.0, y: 0.55, size: [1.3, 0.1, 0.5]}}
  - {at: 0.5, spawn_obstacle: {name: south, x: 0.0, y: -0.55, size: [1.3, 0.1, 0.5]}}
  - {at: 0.5, spawn_obstacle: {name: east, x: 0.55, y: 0.0, size: [0.1, 1.3, 0.5]}}
  - {at: 0.5, spawn_obstacle: {name: west, x: -0.55, y: 0.0, size: [0.1, 1.3, 0.5]}}
  - {at: 10.0, move_obstacle: {name: north, x: -2.5, y: -2.6}}
timeout: 90
expect:
  result: SUCCEEDED
  final_pose_near: {location: goal_open}
  no_contact: true
"""


def test_a_walled_in_robot_clears_its_costmaps_while_stuck_and_then_arrives(
    tmp_path: Path,
) -> None:
    stuck = run_mission(load_mission(_mission(tmp_path, WALLED_IN)))
    free_body = WALLED_IN.split("events:")[0] + "timeout: 90\n"
    free = run_mission(load_mission(_mission(tmp_path, free_body)))
    assert stuck.exit_code == 0, [e.as_dict() for e in stuck.expectations]
    assert free.outcome.result == "SUCCEEDED"
    stuck_clears, free_clears = stuck.metrics["costmap_clears"], free.metrics["costmap_clears"]
    assert isinstance(stuck_clears, int) and isinstance(free_clears, int)
    # Walled in from 0.5 s to at least 10 s: about two clearings per second without progress.
    assert stuck_clears >= free_clears + 10
    assert stuck.outcome.sim_time > 10.0


def test_clearings_by_nav2_recoveries_are_not_counted_as_the_trees(tmp_path: Path) -> None:
    body = WALLED_IN.replace(
        "clear_costmaps_when_stuck: {navigate_to_pose: goal_open}", "navigate_to_pose: goal_open"
    )
    assert "clear_costmaps_when_stuck" not in body
    record = run_mission(load_mission(_mission(tmp_path, body)))
    assert record.metrics["costmap_clears"] == 0
    recoveries = record.metrics["number_of_recoveries"]
    assert isinstance(recoveries, int) and recoveries > 0
