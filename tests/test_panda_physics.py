"""The table scene's physics settings: a held cube does not creep, a resting cube sleeps until
something touches it, and the robot-environment contact sensor counts what it should."""

from __future__ import annotations

import mujoco
import numpy as np

from baobab.robots.panda.arm_server import ArmServer
from baobab.robots.panda.pose import Pose
from baobab.robots.panda.scene import (
    CUBE_JOINT,
    PREFIX,
    ROBOT_CONTACT_SENSOR,
    TABLE_GEOM,
    build_panda_sim,
    cube_pose,
)
from baobab.sim.simulation import Simulation
from baobab.sim.tasks import TaskHandle, TaskStatus


def _finish(sim: Simulation, handle: TaskHandle) -> None:
    while not handle.status.done:
        sim.step_for(0.01)
    assert handle.status is TaskStatus.SUCCEEDED, handle.outcome


def _cube_in_hand(sim: Simulation, arm: ArmServer) -> np.ndarray:
    tcp = arm.tcp_pose()
    return tcp.rotation.inv().apply(cube_pose(sim).position_array - tcp.position_array)


def _cube_asleep(sim: Simulation) -> bool:
    tree = sim.model.body_treeid[sim.model.body("cube").id]
    return bool(sim.data.tree_asleep[tree] >= 0)


def test_a_held_half_kilogram_cube_does_not_creep() -> None:
    """What the no-slip solver used to guarantee, from impratio 400: < 10 um/s of creep."""
    sim, arm = build_panda_sim(cube_xy=(0.45, -0.1), cube_mass=0.5)
    grasp = Pose.top_down((0.45, -0.1, 0.525))
    _finish(sim, arm.move_to(grasp.translated(dz=0.1), 1.0))
    _finish(sim, arm.move_to(grasp, 0.6))
    _finish(sim, arm.gripper("close", require_object=True))
    _finish(sim, arm.move_to(grasp.translated(dz=0.15), 0.8))
    sim.step_for(0.5)
    start = _cube_in_hand(sim, arm)
    sim.step_for(5.0)
    creep = np.linalg.norm(_cube_in_hand(sim, arm) - start)
    assert creep < 5.0 * 10e-6
    assert cube_pose(sim).position[2] > 0.6


def test_a_resting_cube_sleeps_and_wakes_when_touched_or_moved() -> None:
    sim, arm = build_panda_sim(cube_xy=(0.45, -0.1))
    sim.step_for(0.1)
    assert _cube_asleep(sim)
    resting = cube_pose(sim).position_array
    # The fingers close on it: the first contact wakes it.
    grasp = Pose.top_down((0.45, -0.1, 0.525))
    _finish(sim, arm.move_to(grasp.translated(dz=0.1), 1.0))
    assert _cube_asleep(sim)
    np.testing.assert_array_equal(cube_pose(sim).position_array, resting)
    _finish(sim, arm.move_to(grasp, 0.6))
    _finish(sim, arm.gripper("close", require_object=True))
    assert not _cube_asleep(sim)
    # Edited by hand while asleep: it wakes and falls from where it was put.
    sim, _ = build_panda_sim(cube_xy=(0.45, -0.1))
    sim.step_for(0.1)
    assert _cube_asleep(sim)
    sim.data.joint(CUBE_JOINT).qpos[2] += 0.1
    sim.forward()
    sim.step_for(0.05)
    assert not _cube_asleep(sim)
    assert 0.526 < cube_pose(sim).position[2] < 0.625 - 0.01


def test_contact_sensor_counts_robot_contacts_with_the_table() -> None:
    sim, arm = build_panda_sim(cube_xy=(0.6, -0.25))
    model, data = sim.model, sim.data
    sensor = model.sensor(ROBOT_CONTACT_SENSOR).adr[0]
    table = model.geom(TABLE_GEOM).id
    robot_root = model.body(PREFIX + "link0").id
    counts, expected = [], []

    def record(_time: float) -> None:
        geoms = data.contact.geom[: data.ncon]
        roots = model.body_rootid[model.geom_bodyid[geoms]]
        counts.append(data.sensordata[sensor])
        expected.append(int(np.sum(((geoms == table) & (roots[:, ::-1] == robot_root)).any(1))))

    sim.every(sim.physics_dt, record, name="check")
    handle = arm.move_to(Pose.top_down((0.31, 0.0, 0.35)), 2.0)  # into the table top
    while not handle.status.done:
        sim.step_for(0.01)
    assert max(counts) > 0
    assert counts == expected
    assert mujoco.mjtSensor(model.sensor_type[0]) == mujoco.mjtSensor.mjSENS_CONTACT
