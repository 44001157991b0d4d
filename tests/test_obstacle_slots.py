"""Run-time obstacles: a spawned box is whole to physics and the lidar, however large.

An obstacle slot is compiled as a 0.3 m box; ``spawn_obstacle`` resizes it. MuJoCo culls
contacts and rays with volumes compiled from that size, so a larger box must bring its
volumes along, or its far parts are passed through and unseen.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from baobab.missions.run.event_targets import ObstacleSlots
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim import Simulation
from baobab.sim.builder import world_spec
from baobab.sim.world import Box, Floor, Pose2D, World

WALL_Y = 1.2
"""The spawned wall's centre line (m): 3 m long along x, 0.1 m thick."""


def _open_floor() -> World:
    return World(
        name="open",
        floor=Floor(size=(12.0, 12.0)),
        boxes=[Box(name="far_post", center=(5.0, 5.0), size=(0.2, 0.2))],
        spawns={"default": Pose2D(x=0.0, y=0.0)},
    )


@pytest.mark.parametrize("size", [(1.3, 0.1, 0.5), (0.1, 3.0, 0.2), (0.3, 0.3, 0.5)])
def test_a_spawned_box_has_the_culling_volumes_mujoco_compiles_for_its_size(
    size: tuple[float, float, float],
) -> None:
    spec = world_spec(_open_floor())
    spec.geom("movable_0").size = np.array(size) / 2
    compiled = spec.compile()
    sim = Simulation(world_spec(_open_floor()).compile())
    ObstacleSlots(sim).spawn("crate", 1.0, 1.0, 0.3, size)
    model = sim.model
    geom, body = model.geom("movable_0").id, model.body("movable_0").id
    np.testing.assert_array_equal(model.geom_size[geom], compiled.geom_size[geom])
    assert model.geom_rbound[geom] == compiled.geom_rbound[geom]
    np.testing.assert_array_equal(model.geom_aabb[geom], compiled.geom_aabb[geom])
    root, compiled_root = model.body_bvhadr[body], compiled.body_bvhadr[body]
    np.testing.assert_array_equal(model.bvh_aabb[root], compiled.bvh_aabb[compiled_root])


def test_the_robot_stops_at_the_far_end_of_a_large_spawned_wall() -> None:
    # 1.3 m east of the wall's centre, 1.15 m from the compiled 0.3 m box: the robot drives
    # north into the wall and must meet it there, not pass through.
    sim, robot = build_turtlebot3_sim(_open_floor(), Pose2D(x=1.3, y=0.7, yaw=math.pi / 2))
    ObstacleSlots(sim).spawn("wall", 0.0, WALL_Y, 0.0, (3.0, 0.1, 0.5))
    touched: set[str] = set()
    sim.every(0.01, lambda _t: touched.update(robot.base.robot_contacts()), name="contacts")
    robot.base.command(0.2, 0.0)
    sim.step_for(5.0)
    assert touched == {"movable_0"}
    assert robot.base.pose().y < WALL_Y - 0.05


def test_the_lidar_sees_a_large_spawned_wall_out_to_its_ends() -> None:
    sim, robot = build_turtlebot3_sim(_open_floor())
    ObstacleSlots(sim).spawn("wall", 0.0, WALL_Y, 0.0, (3.0, 0.1, 0.5))
    scan = robot.lidar.scan()
    origin = scan.sensor_pose
    face = WALL_Y - 0.05
    beams = np.arange(30, 151)  # 1 degree per beam, counter-clockwise from ahead (east)
    angles = scan.angles[beams] + origin.yaw
    distances = (face - origin.y) / np.sin(angles)
    on_wall = np.abs(origin.x + distances * np.cos(angles)) < 1.45
    assert np.count_nonzero(on_wall) > 90
    np.testing.assert_allclose(scan.ranges[beams][on_wall], distances[on_wall], atol=1e-6)
