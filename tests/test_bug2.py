"""Bug 2 (seed §7): scan sectors, the M-line, wall-following rules, and runs behind walls."""

from __future__ import annotations

import math

import numpy as np
import pytest

from baobab.robots.diff_drive import (
    Bug2Controller,
    Bug2Params,
    NavState,
    dist_to_mline,
    follow_left_wall,
    min_range_in_sector,
)
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.lidar import LaserScan
from baobab.sim.world import Pose2D, load_world

INCREMENT = 2 * math.pi / 360


def _scan(ranges: np.ndarray) -> LaserScan:
    return LaserScan(
        stamp=0.0,
        frame_id="base_scan",
        angle_min=0.0,
        angle_max=359 * INCREMENT,
        angle_increment=INCREMENT,
        range_min=0.12,
        range_max=3.5,
        ranges=ranges,
        sensor_pose=Pose2D(x=0.0, y=0.0),
    )


def _one_close_beam(index: int, value: float = 0.5) -> LaserScan:
    ranges = np.full(360, 3.0)
    ranges[index] = value
    return _scan(ranges)


@pytest.mark.parametrize(
    ("close_beam", "center_deg", "half_width_deg", "expected"),
    [
        (90, 90.0, 10.0, 0.5),
        (80, 90.0, 10.0, 0.5),  # the limits are inclusive
        (100, 90.0, 10.0, 0.5),
        (79, 90.0, 10.0, 3.0),
        (101, 90.0, 10.0, 3.0),
        # Centred on 0 deg: i_start > i_end, two pieces [0, i_end] and [i_start, 359].
        (355, 0.0, 10.0, 0.5),
        (5, 0.0, 10.0, 0.5),
        (0, 0.0, 10.0, 0.5),
        (359, 0.0, 10.0, 0.5),
        (180, 0.0, 10.0, 3.0),
        (11, 0.0, 10.0, 3.0),
        (349, 0.0, 10.0, 3.0),
        # A negative centre is the same as centre + 360.
        (270, -90.0, 5.0, 0.5),
        # An upper limit just under 360 deg rounds to beam 0.
        (0, 349.7, 10.0, 0.5),
        # The whole turn.
        (200, 0.0, 180.0, 0.5),
    ],
)
def test_min_range_in_sector(
    close_beam: int, center_deg: float, half_width_deg: float, expected: float
) -> None:
    scan = _one_close_beam(close_beam)
    assert min_range_in_sector(scan, center_deg, half_width_deg) == expected


def test_min_range_in_sector_without_returns_is_inf() -> None:
    assert min_range_in_sector(_scan(np.full(360, math.inf)), 0.0, 30.0) == math.inf


@pytest.mark.parametrize(
    ("start", "goal", "point", "expected"),
    [
        ((0.0, 0.0), (2.0, 0.0), (1.0, 0.5), 0.5),
        ((0.0, 0.0), (2.0, 0.0), (3.0, -1.0), 1.0),  # the line, not the segment
        ((0.0, 0.0), (2.0, 2.0), (2.0, 0.0), math.sqrt(2.0)),
        ((1.0, 1.0), (1.0, 3.0), (1.0, 7.0), 0.0),
        ((1.0, 1.0), (1.0, 1.0), (4.0, 5.0), 5.0),  # start == goal: distance to the point
    ],
)
def test_dist_to_mline(
    start: tuple[float, float],
    goal: tuple[float, float],
    point: tuple[float, float],
    expected: float,
) -> None:
    assert dist_to_mline(start, goal, point) == pytest.approx(expected)


@pytest.mark.parametrize(
    ("front", "left", "expected"),
    [
        (0.3, 0.45, (0.0, -0.6)),  # obstacle ahead: turn right in place
        (0.3, 2.0, (0.0, -0.6)),  # ... even with no wall on the left
        (0.8, 0.51, (0.0, 0.6)),  # wall too far on the left (> 1.25 * 0.4): turn left
        (0.8, math.inf, (0.0, 0.6)),
        (0.8, 0.5, (0.2, 0.0)),  # at 1.25 * wall_dist exactly: go ahead
        (0.4, 0.3, (0.2, 0.0)),
    ],
)
def test_follow_left_wall(front: float, left: float, expected: tuple[float, float]) -> None:
    assert follow_left_wall(front, left) == expected


def test_params_default_to_the_seed() -> None:
    params = Bug2Params()
    assert (params.wall_dist, params.mline_tol) == (0.4, 0.1)
    assert (params.linear_speed, params.angular_speed, params.goal_tolerance) == (0.2, 0.6, 0.05)
    with pytest.raises(ValueError, match="wall_dist"):
        Bug2Params(wall_dist=-1.0)


@pytest.mark.parametrize("goal_name", ["goal_behind_wall", "goal_behind_north_wall"])
def test_reaches_a_goal_behind_a_wall_without_touching_it(goal_name: str) -> None:
    world = load_world("walls")
    goal = world.locations[goal_name]
    sim, robot = build_turtlebot3_sim(world)
    bug = Bug2Controller(sim, robot.base, robot.lidar)
    touched: set[str] = set()
    clearance = [math.inf]

    def watch(_time: float) -> None:
        touched.update(robot.base.robot_contacts())

    def measure(_time: float) -> None:
        clearance[0] = min(clearance[0], robot.base.min_clearance())

    sim.every(0.005, watch, name="contacts")  # every physics step
    sim.every(0.05, measure, name="clearance")
    bug.set_goal(goal.x, goal.y)
    start = bug.start
    assert start is not None
    while bug.state is not NavState.IDLE and sim.time < 90.0:
        sim.step_for(1.0)

    pose = robot.base.pose()
    assert bug.reached
    assert math.hypot(pose.x - goal.x, pose.y - goal.y) < 0.05 + 0.01  # stop within ramp-down
    assert touched == set()
    assert clearance[0] > 0.05
    # The wall blocked the M-line: the robot met it, went round it and left it on the far side.
    assert len(bug.hit_points) >= 1 and len(bug.leave_points) >= 1
    for hit, leave in zip(bug.hit_points, bug.leave_points, strict=False):
        hit_to_goal = math.hypot(goal.x - hit[0], goal.y - hit[1])
        leave_to_goal = math.hypot(goal.x - leave[0], goal.y - leave[1])
        assert dist_to_mline(start, (goal.x, goal.y), leave) < 0.1
        assert leave_to_goal < hit_to_goal
    first_hit = bug.hit_points[0]
    assert dist_to_mline(start, (goal.x, goal.y), first_hit) < 0.1  # it was on its way


def test_goal_behind_wall_is_behind_wall_east() -> None:
    # The run above must meet wall_east: the straight line from the spawn crosses it.
    world = load_world("walls")
    goal, spawn = world.locations["goal_behind_wall"], world.spawn
    wall = next(box for box in world.boxes if box.name == "wall_east")
    west_face = wall.center[0] - wall.size[0] / 2
    fraction = (west_face - spawn.x) / (goal.x - spawn.x)
    y = spawn.y + fraction * (goal.y - spawn.y)
    assert 0 < fraction < 1
    assert abs(y - wall.center[1]) < wall.size[1] / 2


def test_hit_and_leave_points_are_recorded_on_the_far_side() -> None:
    world = load_world("walls")
    goal = world.locations["goal_behind_wall"]
    sim, robot = build_turtlebot3_sim(world)
    bug = Bug2Controller(sim, robot.base, robot.lidar)
    bug.set_goal(goal.x, goal.y)
    states: set[NavState] = set()
    sim.every(0.05, lambda _t: states.add(bug.state), name="states")
    while bug.state is not NavState.IDLE and sim.time < 90.0:
        sim.step_for(1.0)
    assert states == {NavState.GO_TO_GOAL, NavState.WALL_FOLLOW, NavState.IDLE}
    wall_x = 1.2
    assert bug.hit_points[0][0] < wall_x - 0.3  # stopped short of the wall's near face
    assert bug.leave_points[-1][0] > wall_x + 0.3  # left it beyond the far face


def test_sector_distances_follow_each_new_scan() -> None:
    # The controller works the sectors out once per scan: a new scan must refresh them.
    sim, robot = build_turtlebot3_sim(load_world("walls"))
    controller = Bug2Controller(sim, robot.base, robot.lidar)
    sim.step_for(sim.physics_dt)
    first = robot.lidar.latest
    assert first is not None
    params = controller.params
    assert controller.front_dist() == min_range_in_sector(first, 0.0, params.front_half_width_deg)
    robot.base.command(0.2, 0.5)
    sim.step_for(1.0)
    latest = robot.lidar.latest
    assert latest is not None and latest is not first
    assert controller.front_dist() == min_range_in_sector(latest, 0.0, params.front_half_width_deg)
    assert controller.left_dist() == min_range_in_sector(
        latest, params.left_center_deg, params.left_half_width_deg
    )
    assert controller.left_dist() != min_range_in_sector(
        first, params.left_center_deg, params.left_half_width_deg
    )
