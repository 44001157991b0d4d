"""Point-to-point navigation (seed §6): the law, the state machine, and a run in the walls world."""

from __future__ import annotations

import math

import pytest

from baobab.robots.diff_drive import (
    GoToGoalController,
    GoToGoalParams,
    NavState,
    angle_wrap,
    go_to_goal_command,
)
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.world import Pose2D, load_world

THETA_MAX = math.radians(70.0)


@pytest.mark.parametrize(
    ("pose", "goal", "expected"),
    [
        # Aligned: full speed, no turn.
        (Pose2D(x=0.0, y=0.0, yaw=0.0), (2.0, 0.0), (0.20, 0.0)),
        # 10 deg off: proportional turn, speed scaled by the error.
        (
            Pose2D(x=0.0, y=0.0, yaw=0.0),
            (math.cos(math.radians(10)), math.sin(math.radians(10))),
            (0.20 * (1 - 10 / 70), 1.5 * math.radians(10)),
        ),
        # 35 deg off: the turn saturates at 0.6 rad/s, speed halves.
        (
            Pose2D(x=0.0, y=0.0, yaw=math.radians(35)),
            (1.0, 0.0),
            (0.10, -0.6),
        ),
        # 90 deg off (beyond theta_max): turn in place.
        (Pose2D(x=0.0, y=0.0, yaw=0.0), (0.0, 3.0), (0.0, 0.6)),
        # Goal behind: turn in place.
        (Pose2D(x=1.0, y=1.0, yaw=0.0), (0.0, 1.0), (0.0, 0.6)),
        # Across +-pi: the error is 20 deg to the left, not 340 deg to the right.
        (
            Pose2D(x=0.0, y=0.0, yaw=math.radians(170)),
            (math.cos(math.radians(-170)), math.sin(math.radians(-170))),
            (0.20 * (1 - 20 / 70), 0.6 * min(1.0, 1.5 * math.radians(20) / 0.6)),
        ),
    ],
)
def test_go_to_goal_law(
    pose: Pose2D, goal: tuple[float, float], expected: tuple[float, float]
) -> None:
    assert go_to_goal_command(pose, goal) == pytest.approx(expected, abs=1e-9)


def test_angle_wrap() -> None:
    assert angle_wrap(3 * math.pi / 2) == pytest.approx(-math.pi / 2)
    assert angle_wrap(-3 * math.pi / 2) == pytest.approx(math.pi / 2)
    assert angle_wrap(0.3) == pytest.approx(0.3)


def test_params_default_to_the_seed_and_reject_nonsense() -> None:
    params = GoToGoalParams()
    assert (params.heading_gain, params.theta_max) == (1.5, THETA_MAX)
    assert (params.linear_speed, params.angular_speed) == (0.20, 0.6)
    assert (params.goal_tolerance, params.period) == (0.05, 0.05)
    with pytest.raises(ValueError, match="goal_tolerance"):
        GoToGoalParams(goal_tolerance=0.0)


def test_reaches_the_open_goal_in_the_walls_world() -> None:
    world = load_world("walls")
    goal = world.locations["goal_open"]
    assert (goal.x, goal.y) == (2.0, 2.0)
    sim, robot = build_turtlebot3_sim(world)
    controller = GoToGoalController(sim, robot.base)
    assert controller.state is NavState.IDLE
    controller.set_goal(goal.x, goal.y)
    assert controller.state is NavState.GO_TO_GOAL
    touched: set[str] = set()
    sim.every(0.01, lambda _t: touched.update(robot.base.robot_contacts()), name="contacts")
    while controller.state is NavState.GO_TO_GOAL and sim.time < 40.0:
        sim.step_for(0.5)
    sim.step_for(1.0)  # let the base come to rest

    pose = robot.base.pose()
    assert controller.reached
    assert controller.state is NavState.IDLE
    assert math.hypot(pose.x - goal.x, pose.y - goal.y) < 0.05
    assert robot.base.body_velocity() == pytest.approx((0.0, 0.0), abs=1e-3)
    assert abs(angle_wrap(pose.yaw - math.pi / 4)) < 0.2  # it drove the straight line
    assert touched == set()
    assert sim.time < 20.0  # 2.83 m at 0.2 m/s plus the initial turn


def test_idle_controller_leaves_the_base_alone() -> None:
    sim, robot = build_turtlebot3_sim("walls")
    controller = GoToGoalController(sim, robot.base)
    robot.base.command(0.1, 0.0)
    sim.step_for(0.5)
    assert robot.base.target == (0.1, 0.0)
    here = robot.base.pose()
    controller.set_goal(here.x + 0.01, here.y)  # already within tolerance
    sim.step_for(0.1)
    assert controller.state is NavState.IDLE and controller.reached
    assert robot.base.target == (0.0, 0.0)


def test_cancel_stops_the_robot() -> None:
    sim, robot = build_turtlebot3_sim("walls")
    controller = GoToGoalController(sim, robot.base)
    controller.set_goal(2.0, 2.0)
    sim.step_for(2.0)
    controller.close()
    sim.step_for(1.0)
    assert controller.state is NavState.IDLE and not controller.reached
    assert robot.base.body_velocity() == pytest.approx((0.0, 0.0), abs=1e-3)
    stopped = robot.base.pose()
    sim.step_for(0.5)
    assert robot.base.pose().x == pytest.approx(stopped.x, abs=1e-4)
