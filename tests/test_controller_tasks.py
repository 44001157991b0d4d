"""The base-controller server: go-to-goal and Bug2 as goal-style tasks on real physics."""

from __future__ import annotations

import math

from baobab.behaviours.ports import BaseControllerPort
from baobab.robots.diff_drive.controller_tasks import (
    BaseControllerError,
    BaseControllerServer,
    ControllerTaskConfig,
)
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.tasks import TaskHandle, TaskStatus
from baobab.sim.world import Pose2D


def _server(config: ControllerTaskConfig | None = None) -> BaseControllerServer:
    sim, robot = build_turtlebot3_sim("walls", seed=0)
    return BaseControllerServer(sim, robot.base, robot.lidar, config=config)


def _run(server: BaseControllerServer, handle: TaskHandle, limit: float) -> None:
    while handle.status is TaskStatus.RUNNING and server.sim.time < limit:
        server.sim.step_for(0.1)


def test_the_server_is_a_base_controller_port() -> None:
    port: BaseControllerPort = _server()
    assert port is not None


def test_go_to_goal_succeeds_within_the_tutorial_tolerance() -> None:
    server = _server()
    handle = server.go_to_goal(Pose2D(x=2.0, y=2.0))
    assert handle.feedback["distance_remaining"] == math.hypot(2.0, 2.0)
    _run(server, handle, 60.0)
    assert handle.status is TaskStatus.SUCCEEDED
    pose = server.base.pose()
    assert math.hypot(pose.x - 2.0, pose.y - 2.0) < 0.05
    assert server.active is None


def test_bug2_goes_around_the_wall() -> None:
    server = _server()
    handle = server.bug2(Pose2D(x=2.2, y=0.0))
    _run(server, handle, 120.0)
    assert handle.status is TaskStatus.SUCCEEDED
    controller = server.bug2_controller
    assert controller is not None and len(controller.hit_points) >= 1
    assert server.base.robot_contacts() == []


def test_a_robot_pressed_against_a_wall_fails_for_lack_of_progress() -> None:
    server = _server(ControllerTaskConfig(progress_timeout=5.0))
    # Straight at goal_behind_wall: wall_east (x = 1.15..1.25) is in the way.
    handle = server.go_to_goal(Pose2D(x=2.2, y=0.0))
    _run(server, handle, 60.0)
    outcome = handle.outcome
    assert outcome is not None and outcome.status is TaskStatus.FAILED
    assert outcome.error_code == BaseControllerError.FAILED_TO_MAKE_PROGRESS
    assert outcome.error_name == "FAILED_TO_MAKE_PROGRESS"
    assert "made no progress" in outcome.error_msg
    assert server.base.pose().x < 1.15
    assert server.base.target == (0.0, 0.0)


def test_cancel_stops_the_base_and_a_new_goal_preempts() -> None:
    server = _server()
    first = server.go_to_goal(Pose2D(x=2.0, y=2.0))
    server.sim.step_for(2.0)
    assert server.base.target != (0.0, 0.0)
    second = server.bug2(Pose2D(x=-1.0, y=2.2))
    assert first.status is TaskStatus.CANCELED
    assert first.outcome is not None and first.outcome.error_msg == "preempted by a new goal"
    server.sim.step_for(1.0)
    second.cancel()
    assert second.status is TaskStatus.CANCELED
    assert server.base.target == (0.0, 0.0)
    server.sim.step_for(1.0)
    speed, turn = server.base.body_velocity()
    assert abs(speed) < 1e-3 and abs(turn) < 1e-2
