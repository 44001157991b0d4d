"""The Burger model and its differential-drive base, on real MuJoCo physics."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from baobab.robots.diff_drive import DiffDriveBase, MobileRobot
from baobab.robots.diff_drive.ground_truth_kernel import ground_truth_reference
from baobab.robots.turtlebot3 import (
    BURGER,
    attach_turtlebot3,
    build_turtlebot3_sim,
    start_turtlebot3,
)
from baobab.sim import Simulation
from baobab.sim.builder import MOVABLE_GROUP, ROBOT_GROUP, STATIC_GROUP, world_spec
from baobab.sim.world import Box, Floor, Pose2D, World, load_world


def _open_floor(boxes: list[Box] | None = None) -> World:
    return World(
        name="open",
        floor=Floor(size=(12.0, 12.0)),
        boxes=boxes or [],
        spawns={"default": Pose2D(x=0.0, y=0.0)},
    )


def _settled(world: World | str = "walls", start: Pose2D | None = None) -> MobileRobot:
    """A Burger that has stood still for 0.2 s, so it sits on its wheels and caster."""
    sim, robot = build_turtlebot3_sim(world, start)
    sim.step_for(0.2)
    return robot


def _robot_geoms(model: mujoco.MjModel) -> np.ndarray:
    root = model.body("tb3/base_link").id
    return np.flatnonzero(model.body_rootid[model.geom_bodyid] == root)


def test_model_has_the_burger_figures() -> None:
    sim, robot = build_turtlebot3_sim(_open_floor())
    model, data = sim.model, sim.data
    assert model.body_subtreemass[model.body("tb3/base_link").id] == pytest.approx(1.0, abs=0.05)
    left, right = (data.body(f"tb3/wheel_{side}").xpos for side in ("left", "right"))
    assert np.linalg.norm(left - right) == pytest.approx(0.160)
    assert model.geom("tb3/wheel_left").size[0] == pytest.approx(0.033)
    assert data.site("tb3/base_scan").xpos[2] == pytest.approx(0.182, abs=0.002)
    assert 0.17 <= BURGER.lidar.z <= 0.19
    assert (BURGER.max_linear_speed, BURGER.max_angular_speed) == (0.22, 2.84)
    geoms = _robot_geoms(model)
    assert set(model.geom_group[geoms]) == {ROBOT_GROUP}
    assert (
        model.actuator("tb3/wheel_left_velocity").trnid[0] == model.joint("tb3/wheel_left_joint").id
    )
    assert robot.names.root_joint == "tb3/root"


def test_colliding_geoms_fit_inside_the_footprint_circle() -> None:
    sim, _ = build_turtlebot3_sim(_open_floor())
    model, data = sim.model, sim.data
    mujoco.mj_forward(model, data)
    centre = data.body("tb3/base_link").xpos[:2]
    for geom in _robot_geoms(model):
        if model.geom_contype[geom] == 0 and model.geom_conaffinity[geom] == 0:
            continue
        # Farthest horizontal reach of the geom's (unrotated) half extent around its centre.
        half = _planar_half_extent(model, geom)
        offset = np.abs(data.geom_xpos[geom, :2] - centre)
        reach = np.linalg.norm(offset + half)
        assert reach <= BURGER.footprint_radius + 0.002, model.geom(geom).name


def _planar_half_extent(model: mujoco.MjModel, geom: int) -> np.ndarray:
    size = model.geom_size[geom]
    kind = model.geom_type[geom]
    if kind == mujoco.mjtGeom.mjGEOM_BOX:
        return size[:2]
    if kind == mujoco.mjtGeom.mjGEOM_ELLIPSOID:
        return size[:2]
    return np.array([size[0], size[0]])


def test_drives_one_metre_straight() -> None:
    robot = _settled(_open_floor())
    start = robot.base.pose()
    robot.base.command(0.2, 0.0)
    robot.sim.step_for(5.0)
    robot.base.stop()
    robot.sim.step_for(0.5)
    end = robot.base.pose()
    assert math.hypot(end.x - start.x, end.y - start.y) == pytest.approx(1.0, abs=0.02)
    assert abs(end.y - start.y) < 0.005
    assert robot.base.body_velocity() == pytest.approx((0.0, 0.0), abs=1e-3)


def test_turns_a_quarter_in_place() -> None:
    robot = _settled(_open_floor())
    start = robot.base.pose()
    robot.base.command(0.0, math.pi / 4)
    robot.sim.step_for(2.0)
    robot.base.stop()
    robot.sim.step_for(0.5)
    end = robot.base.pose()
    assert math.remainder(end.yaw - start.yaw - math.pi / 2, 2 * math.pi) == pytest.approx(
        0.0, abs=0.02
    )
    assert math.hypot(end.x - start.x, end.y - start.y) < 0.01


def test_odometry_agrees_with_ground_truth_within_one_percent() -> None:
    robot = _settled(_open_floor())
    base, sim = robot.base, robot.sim
    travelled = [0.0]

    def integrate_speed(_time: float) -> None:
        travelled[0] += abs(base.body_velocity()[0]) * 0.01

    sim.every(0.01, integrate_speed, name="distance")
    for linear, angular, duration in ((0.2, 0.0, 3.0), (0.15, 0.6, 4.0), (0.2, -0.4, 3.0)):
        base.command(linear, angular)
        sim.step_for(duration)
    base.command(0.0, 1.5)
    sim.step_for(2.0)
    base.stop()
    sim.step_for(0.5)

    truth, odom, origin = base.pose(), base.odometry.pose, base.odom_origin
    cos, sin = math.cos(origin.yaw), math.sin(origin.yaw)
    odom_in_map = (
        origin.x + cos * odom.x - sin * odom.y,
        origin.y + sin * odom.x + cos * odom.y,
    )
    assert travelled[0] > 1.7
    error = math.hypot(odom_in_map[0] - truth.x, odom_in_map[1] - truth.y)
    assert error < 0.01 * travelled[0]
    assert abs(math.remainder(odom.yaw + origin.yaw - truth.yaw, 2 * math.pi)) < 0.02


def test_odometry_reads_the_wheel_encoders_not_the_physics() -> None:
    robot = _settled(_open_floor())
    data = robot.sim.data
    before = robot.base.pose()
    # Turn both wheels by one radian by hand, as if the encoders had counted it.
    for joint in robot.names.wheel_joints:
        data.joint(joint).qpos[0] += 1.0
    robot.sim.step_for(0.01)
    tick = 2 * math.pi / BURGER.encoder_ticks_per_rev
    assert robot.base.odometry.pose.x == pytest.approx(BURGER.wheel_radius, abs=tick * 0.033)
    after = robot.base.pose()
    assert math.hypot(after.x - before.x, after.y - before.y) < 1e-4


def test_odometry_twist_follows_the_wheels() -> None:
    robot = _settled(_open_floor())
    robot.base.command(0.1, 0.5)
    robot.sim.step_for(1.0)
    odometry = robot.base.odometry
    assert odometry.linear == pytest.approx(0.1, abs=0.005)
    assert odometry.angular == pytest.approx(0.5, abs=0.03)
    assert odometry.stamp == pytest.approx(robot.sim.time - 0.01)


def test_commands_are_clipped_and_ramped() -> None:
    robot = _settled(_open_floor())
    base = robot.base
    base.command(1.0, -5.0)
    assert base.target == (0.22, -2.84)
    robot.sim.step_for(0.04)
    linear, angular = base.commanded
    assert linear == pytest.approx(2.5 * 0.04, abs=1e-9)
    assert angular == pytest.approx(-3.2 * 0.04, abs=1e-9)
    robot.sim.step_for(1.5)
    left, right = base.wheel_speeds(*base.commanded)
    assert max(abs(left), abs(right)) * BURGER.wheel_radius == pytest.approx(BURGER.max_wheel_speed)
    with pytest.raises(ValueError, match="finite"):
        base.command(math.nan, 0.0)


def test_wheel_speeds_keep_the_curvature_when_saturated() -> None:
    _, robot = build_turtlebot3_sim(_open_floor())
    left, right = robot.base.wheel_speeds(0.22, 2.84)
    assert max(abs(left), abs(right)) * BURGER.wheel_radius == pytest.approx(BURGER.max_wheel_speed)
    r, half = BURGER.wheel_radius, BURGER.wheel_separation / 2
    linear, angular = (left + right) * r / 2, (right - left) * r / (2 * half)
    assert angular / linear == pytest.approx(2.84 / 0.22)


def test_teleport_places_the_robot_at_rest_and_restarts_odometry() -> None:
    robot = _settled()
    robot.base.command(0.2, 0.3)
    robot.sim.step_for(1.0)
    target = Pose2D(x=-1.0, y=0.5, yaw=2.0)
    robot.base.teleport(target)
    pose = robot.base.pose()
    assert (pose.x, pose.y, pose.yaw) == pytest.approx((-1.0, 0.5, 2.0), abs=1e-9)
    assert robot.base.body_velocity() == pytest.approx((0.0, 0.0), abs=1e-12)
    assert robot.base.odometry.pose.x == 0.0
    assert robot.base.odom_origin.yaw == pytest.approx(2.0)
    robot.sim.step_for(0.5)
    still = robot.base.pose()
    assert math.hypot(still.x - target.x, still.y - target.y) < 1e-3


def _state_from_the_physics(robot: MobileRobot) -> tuple[float, float, float, float, float]:
    """x, y (m), yaw (rad), forward speed (m/s), yaw rate (rad/s), read from MjData now."""
    root = robot.sim.data.joint(robot.names.root_joint)
    return ground_truth_reference(root.qpos, root.qvel)


def _read(robot: MobileRobot) -> tuple[float, float, float, float, float]:
    pose = robot.base.pose()
    read = (pose.x, pose.y, pose.yaw, *robot.base.body_velocity())
    assert robot.base.ground_truth() == read
    return read


def test_pose_and_speed_reads_are_cached_until_the_state_changes() -> None:
    """One read per state: a second read returns the same pose; a step, a teleport or an edit
    followed by ``forward`` gives the new state's figures (the cache never serves stale ones)."""
    robot = _settled()
    base, sim = robot.base, robot.sim
    assert base.pose() is base.pose()
    base.command(0.2, 0.5)
    for _ in range(3):
        before = _read(robot)
        sim.step_for(0.1)
        assert _read(robot) == _state_from_the_physics(robot) != before
    base.teleport(Pose2D(x=-1.0, y=0.5, yaw=2.0))
    assert _read(robot) == _state_from_the_physics(robot)
    assert _read(robot)[:3] == pytest.approx((-1.0, 0.5, 2.0), abs=1e-9)
    root = sim.data.joint(robot.names.root_joint)
    root.qpos[0] += 0.25
    root.qvel[0] = 0.1
    sim.forward()
    assert _read(robot) == _state_from_the_physics(robot)
    assert _read(robot)[0] == pytest.approx(-0.75, abs=1e-9)


def test_start_defaults_to_the_world_spawn() -> None:
    world = load_world("walls")
    _, robot = build_turtlebot3_sim(world)
    pose = robot.base.pose()
    assert (pose.x, pose.y, pose.yaw) == pytest.approx(
        (world.spawn.x, world.spawn.y, world.spawn.yaw), abs=1e-9
    )


def test_contacts_name_the_wall_the_robot_drives_into() -> None:
    wall = Box(name="wall", center=(1.0, 0.0), size=(0.1, 2.0))
    robot = _settled(_open_floor([wall]))
    assert robot.base.robot_contacts() == []
    assert robot.base.min_clearance() == pytest.approx(0.95 - 0.105, abs=2e-3)
    robot.base.command(0.2, 0.0)
    touched: set[str] = set()

    def watch(_time: float) -> None:
        touched.update(robot.base.robot_contacts())

    robot.sim.every(0.005, watch, name="contacts")
    robot.sim.step_for(6.0)
    assert touched == {"wall"}
    assert robot.base.min_clearance() < 0.005


def test_min_clearance_sees_rotated_boxes_and_ignores_far_ones() -> None:
    tilted = Box(name="tilted", center=(0.0, 1.0), size=(1.0, 0.2), yaw=math.pi / 2)
    robot = _settled(_open_floor([tilted]))
    # The box stands on end: its near face is 1.0 - 0.5 m from the robot's centre.
    assert robot.base.min_clearance() == pytest.approx(0.5 - 0.105, abs=2e-3)
    assert robot.base.min_clearance(max_distance=0.2) == math.inf


@pytest.mark.parametrize("world", ["cafe", "town"])
def test_min_clearance_equals_the_exhaustive_search(world: str) -> None:
    # The culling bounds must never change the answer: compare with mj_geomDistance against
    # every obstacle geom, at random poses, with a movable box placed at a slant.
    sim, robot = build_turtlebot3_sim(world)
    model, data = sim.model, sim.data
    slot = model.geom("movable_0").id
    rng = np.random.default_rng(7)
    footprint = model.geom(robot.names.footprint_geom).id
    obstacles = [
        geom
        for geom in range(model.ngeom)
        if model.geom_group[geom] in (STATIC_GROUP, MOVABLE_GROUP)
    ]
    x0, y0, x1, y1 = model.stat.center[0] - 5, model.stat.center[1] - 10, 5, 10
    for trial in range(150):
        x, y = rng.uniform(x0, x0 + 2 * abs(x1)), rng.uniform(y0, y0 + 2 * abs(y1))
        body = model.geom_bodyid[slot]
        data.mocap_pos[model.body_mocapid[body]] = [x + 0.4, y - 0.3, 0.25]
        mujoco.mju_axisAngle2Quat(
            data.mocap_quat[model.body_mocapid[body]], np.array([0.0, 0.0, 1.0]), trial * 0.3
        )
        robot.base.teleport(Pose2D(x=x, y=y, yaw=rng.uniform(-math.pi, math.pi)))
        exhaustive = min(
            mujoco.mj_geomDistance(model, data, footprint, geom, 2.0, None) for geom in obstacles
        )
        expected = exhaustive if exhaustive < 2.0 else math.inf
        assert robot.base.min_clearance(2.0) == expected


def test_two_robots_attach_under_their_own_prefixes() -> None:
    spec = world_spec(_open_floor())
    attach_turtlebot3(spec, Pose2D(x=0.0, y=0.0), prefix="alpha/")
    attach_turtlebot3(spec, Pose2D(x=2.0, y=1.0, yaw=1.0), prefix="beta/")
    sim = Simulation(spec.compile())
    alpha = start_turtlebot3(sim, prefix="alpha/")
    beta = start_turtlebot3(sim, prefix="beta/")
    assert isinstance(beta.base, DiffDriveBase)
    alpha.base.command(0.2, 0.0)
    sim.step_for(1.0)
    assert alpha.base.pose().x > 0.15
    assert beta.base.pose().x == pytest.approx(2.0, abs=1e-3)
    assert alpha.lidar.latest is not None
