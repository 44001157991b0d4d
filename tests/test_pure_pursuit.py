"""Regulated Pure Pursuit: each regulation on its own, collision ahead, and a closed loop."""

from __future__ import annotations

import math

import numpy as np
import pytest

from baobab.nav.checkers import SimpleGoalChecker, SimpleProgressChecker
from baobab.nav.costmap import INSCRIBED_INFLATED_OBSTACLE, MAX_NON_OBSTACLE, Costmap2D
from baobab.nav.errors import CollisionAheadError, FollowPathError, NavigationError
from baobab.nav.footprint import project_motion
from baobab.nav.layered_costmap import LayeredCostmap
from baobab.nav.path import Path
from baobab.nav.planner import GlobalPlanner
from baobab.nav.pure_pursuit import RegulatedPurePursuit, RegulatedPurePursuitParams
from baobab.sim.world import Box, Floor, Pose2D, World, load_world

ORIGIN = Pose2D(x=0.01, y=0.01, yaw=0.0)


def local_costmap(*boxes: Box, at: Pose2D = ORIGIN) -> Costmap2D:
    world = World(
        name="test",
        floor=Floor(size=(10.0, 10.0)),
        boxes=list(boxes),
        spawns={"default": Pose2D(x=0.0, y=0.0)},
    )
    return LayeredCostmap.local_costmap(world, at).costmap


def line(x0: float, y0: float, x1: float, y1: float, yaw: float | None = None) -> Path:
    n = max(round(math.dist((x0, y0), (x1, y1)) / 0.05), 1) + 1
    points = np.column_stack([np.linspace(x0, x1, n), np.linspace(y0, y1, n)])
    return Path.from_points(points, math.atan2(y1 - y0, x1 - x0) if yaw is None else yaw)


def test_straight_path_drives_at_full_speed() -> None:
    v, w = RegulatedPurePursuit().compute_velocity(
        ORIGIN, (0.22, 0.0), line(0.01, 0.01, 3.0, 0.01), local_costmap()
    )
    assert v == pytest.approx(0.22)
    assert w == pytest.approx(0.0, abs=1e-9)


def test_goal_behind_rotates_in_place_within_the_acceleration_limit() -> None:
    path = line(0.01, 0.01, -3.0, 0.01)
    costmap = local_costmap()
    v, w = RegulatedPurePursuit().compute_velocity(ORIGIN, (0.0, 0.0), path, costmap)
    assert (v, w) == (0.0, pytest.approx(3.2 * 0.05))
    v, w = RegulatedPurePursuit().compute_velocity(ORIGIN, (0.0, 1.8), path, costmap)
    assert (v, w) == (0.0, pytest.approx(1.8))
    # A carrot 60 degrees to the right is not enough to rotate in place (limit 45 degrees).
    right = line(0.01, 0.01, 0.31, -0.51)
    v, w = RegulatedPurePursuit().compute_velocity(ORIGIN, (0.0, -1.8), right, costmap)
    assert (v, w) == (0.0, pytest.approx(-1.8))
    slight = line(0.01, 0.01, 1.0, -0.5)
    v, w = RegulatedPurePursuit().compute_velocity(ORIGIN, (0.2, 0.0), slight, costmap)
    assert v > 0 and w < 0


def test_nearby_obstacles_slow_the_robot_by_cost() -> None:
    wall = Box(name="wall", center=(1.0, 0.42), size=(4.0, 0.1))  # face 0.36 m from the robot
    costmap = local_costmap(wall)
    cost = costmap.cost(ORIGIN.x, ORIGIN.y)
    assert 0 < cost < INSCRIBED_INFLATED_OBSTACLE
    distance = -math.log(cost / MAX_NON_OBSTACLE) / 3.0 + 0.105
    v, w = RegulatedPurePursuit().compute_velocity(
        ORIGIN, (0.22, 0.0), line(0.01, 0.01, 3.0, 0.01), costmap
    )
    assert v == pytest.approx(0.22 * distance / 0.6)
    assert w == pytest.approx(0.0, abs=1e-9)
    assert 0.11 < v < 0.22


def test_high_curvature_slows_the_robot() -> None:
    radius = 0.5
    theta = np.linspace(0.0, math.pi, 200)
    arc = np.column_stack([radius * np.sin(theta), radius * (1 - np.cos(theta))]) + 0.01
    v, w = RegulatedPurePursuit().compute_velocity(
        ORIGIN, (0.22, 0.0), Path.from_points(arc, math.pi), local_costmap()
    )
    assert v == pytest.approx(0.22 * radius / 0.9, rel=1e-3)
    assert w == pytest.approx(v / radius, rel=1e-3)


def test_approach_to_the_goal_slows_the_robot() -> None:
    costmap = local_costmap()
    for remaining in (0.3, 0.5):
        path = line(-1.0, 0.01, 0.01 + remaining, 0.01)
        v, _ = RegulatedPurePursuit().compute_velocity(ORIGIN, (0.22, 0.0), path, costmap)
        assert v == pytest.approx(0.22 * remaining / 0.6, rel=1e-6)


def test_near_the_goal_rotates_to_the_goal_heading() -> None:
    path = line(-1.0, 0.01, 0.2, 0.01, yaw=math.pi / 2)
    v, w = RegulatedPurePursuit().compute_velocity(ORIGIN, (0.0, 0.5), path, local_costmap())
    assert v == 0.0
    assert w == pytest.approx(0.5 + 3.2 * 0.05)


def test_collision_ahead_is_detected_up_to_the_carrot() -> None:
    straight = line(0.01, 0.01, 3.0, 0.01)
    # Nav2 projects at most 1 s ahead: at the regulated 0.11 m/s that is 0.11 m.
    crate = Box(name="crate", center=(0.27, 0.0), size=(0.1, 0.6))
    with pytest.raises(CollisionAheadError) as caught:
        RegulatedPurePursuit().compute_velocity(ORIGIN, (0.22, 0.0), straight, local_costmap(crate))
    assert caught.value.code == FollowPathError.NO_VALID_CONTROL == 106
    # With a longer horizon the projection still stops at the carrot (0.6 m ahead).
    patient = RegulatedPurePursuit(
        RegulatedPurePursuitParams(max_allowed_time_to_collision_up_to_carrot=10.0)
    )
    before = Box(name="crate", center=(0.6, 0.0), size=(0.1, 0.6))
    with pytest.raises(CollisionAheadError):
        patient.compute_velocity(ORIGIN, (0.22, 0.0), straight, local_costmap(before))
    beyond = Box(name="crate", center=(0.9, 0.0), size=(0.1, 0.6))
    v, _ = patient.compute_velocity(ORIGIN, (0.22, 0.0), straight, local_costmap(beyond))
    assert v > 0


def test_passed_poses_stay_pruned_and_bad_paths_are_invalid() -> None:
    controller = RegulatedPurePursuit()
    path = line(0.01, 0.01, 3.0, 0.01)
    costmap = local_costmap()
    controller.compute_velocity(ORIGIN, (0.2, 0.0), path, costmap)
    assert controller.closest_index == 0
    ahead = Pose2D(x=1.01, y=0.05, yaw=0.0)
    controller.compute_velocity(ahead, (0.2, 0.0), path, local_costmap(at=ahead))
    assert controller.closest_index == 20
    controller.compute_velocity(ORIGIN, (0.2, 0.0), path, costmap)
    assert controller.closest_index == 20  # never back to passed poses
    assert controller.last_carrot is not None
    for bad in (Path(np.zeros((0, 3))), line(5.0, 5.0, 6.0, 5.0)):
        with pytest.raises(NavigationError) as caught:
            RegulatedPurePursuit().compute_velocity(ORIGIN, (0.0, 0.0), bad, costmap)
        assert caught.value.code == FollowPathError.INVALID_PATH


def test_closed_loop_reaches_a_goal_behind_a_wall() -> None:
    world = load_world("walls")
    global_map = LayeredCostmap.global_costmap(world)
    local = LayeredCostmap.local_costmap(world, world.spawn, static=global_map.static_layer)
    goal = Pose2D(x=2.2, y=0.0, yaw=math.pi / 2)
    path = GlobalPlanner().create_plan(world.spawn, goal, global_map.costmap)
    controller, goal_checker, progress = (
        RegulatedPurePursuit(),
        SimpleGoalChecker(),
        SimpleProgressChecker(),
    )
    pose, velocity, dt = world.spawn, (0.0, 0.0), 0.05
    for step in range(1200):  # 60 s at the controller's 20 Hz
        now = step * dt
        if step % 4 == 0:
            local.update(pose)  # the caller updates the local costmap at 5 Hz
        if goal_checker.is_goal_reached(pose, goal, velocity):
            break
        assert progress.check(pose, now)
        velocity = controller.compute_velocity(pose, velocity, path, local.costmap)
        x, y, yaw = project_motion(pose, *velocity, dt, dt)[0]
        pose = Pose2D(x=float(x), y=float(y), yaw=float(yaw))
        assert global_map.costmap.cost(pose.x, pose.y) <= MAX_NON_OBSTACLE
    else:
        pytest.fail(f"goal not reached, robot at {pose}")
    assert math.dist((pose.x, pose.y), (goal.x, goal.y)) <= 0.25
    assert 10.0 < now < 40.0
