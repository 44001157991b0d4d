"""The arm's compiled 1 kHz loop inside MuJoCo's step: it controls the MjData it is attached to,
once per physics time, and nothing else; it stops with its server; it counts table contacts."""

from __future__ import annotations

import gc

import mujoco
import numpy as np
import pytest

from baobab.robots.panda.arm_server import ArmServer
from baobab.robots.panda.errors import PandaSceneError
from baobab.robots.panda.model import ARM_JOINTS, HOME_CONFIGURATION, TCP_SITE
from baobab.robots.panda.native_loop import USERDATA_SLOTS
from baobab.robots.panda.pose import Pose
from baobab.robots.panda.scene import (
    PREFIX,
    ROBOT_CONTACT_SENSOR,
    build_panda_sim,
    panda_table_spec,
)
from baobab.sim.simulation import Simulation
from baobab.sim.tasks import TaskStatus

STATE = mujoco.mjtState.mjSTATE_INTEGRATION


def _tcp(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    mujoco.mj_kinematics(model, data)
    return data.site(PREFIX + TCP_SITE).xpos.copy()


def test_plain_mj_step_runs_the_control_and_the_tasks() -> None:
    """No Simulation callbacks: MuJoCo's own multi-step call drives the arm to its goal."""
    sim, arm = build_panda_sim(seed=0)
    model, data = sim.model, sim.data
    goal = arm.tcp_pose().translated(dx=0.05, dz=-0.05)
    handle = arm.move_to(goal, 0.8)
    mujoco.mj_step(model, data, 2000)
    assert handle.status is TaskStatus.SUCCEEDED
    assert np.linalg.norm(_tcp(model, data) - goal.position_array) < 0.005
    assert handle.feedback["remaining_time"] == 0.0


def test_a_state_copied_into_another_mjdata_is_not_controlled() -> None:
    sim, arm = build_panda_sim(seed=0)
    model, data = sim.model, sim.data
    arm.move_to(arm.tcp_pose().translated(dz=-0.1), 0.8)
    sim.step_for(0.1)
    state = np.empty(mujoco.mj_stateSize(model, STATE))
    mujoco.mj_getState(model, data, state, STATE)  # userdata included
    copy = mujoco.MjData(model)
    mujoco.mj_setState(model, copy, state, STATE)
    reference, ctrl = arm.controller.reference, copy.ctrl.copy()
    mujoco.mj_step(model, copy, 200)
    np.testing.assert_array_equal(copy.ctrl, ctrl)  # no control step wrote the torques
    for now, then in zip(arm.controller.reference, reference, strict=True):
        np.testing.assert_array_equal(now, then)  # nor moved the reference
    sim.step_for(0.01)
    assert not np.array_equal(arm.controller.reference[0], reference[0])


def test_a_forward_and_the_step_at_the_same_time_are_one_control_step() -> None:
    """The reference filter moves 5 % of the way per control step, however often the model is
    evaluated at one time."""
    sims = [build_panda_sim(seed=0) for _ in range(2)]
    for _, arm in sims:
        position, quaternion = arm.controller.target
        arm.controller.set_target(position + [0.1, 0.0, 0.0], quaternion)
    edited, _ = sims[0]
    for _ in range(5):
        edited.forward()
    for sim, _ in sims:
        sim.step_for(0.003)
    (first, _), (second, _) = (arm.controller.reference for _, arm in sims)
    np.testing.assert_array_equal(first, second)
    start = sims[0][1].controller.target[0] - [0.1, 0.0, 0.0]
    assert first[0] - start[0] == pytest.approx(0.1 * (1 - 0.95**3))


def test_a_finer_physics_step_runs_the_control_every_other_step() -> None:
    spec = panda_table_spec()
    spec.option.timestep = 0.0005
    sim = Simulation(spec.compile())
    for name, angle in zip(ARM_JOINTS, HOME_CONFIGURATION, strict=True):
        sim.data.joint(PREFIX + name).qpos = angle
    arm = ArmServer(sim, prefix=PREFIX)
    assert arm.period == pytest.approx(0.001)
    position, quaternion = arm.controller.target
    arm.controller.set_target(position + [0.1, 0.0, 0.0], quaternion)
    sim.step_for(0.004)  # 8 physics steps, 4 control steps
    assert arm.controller.reference[0][0] - position[0] == pytest.approx(0.1 * (1 - 0.95**4))


def test_the_loop_stops_when_its_server_is_collected() -> None:
    sim, arm = build_panda_sim(seed=0)
    model, data = sim.model, sim.data
    assert data.userdata[0] != 0.0
    del sim, arm
    gc.collect()
    np.testing.assert_array_equal(data.userdata, np.zeros(USERDATA_SLOTS))
    start = _tcp(model, data)
    mujoco.mj_step(model, data, 200)
    assert _tcp(model, data)[2] < start[2] - 0.05


def test_the_model_must_reserve_the_loops_userdata_and_step_once_per_step() -> None:
    spec = panda_table_spec()
    spec.nuserdata = 0
    with pytest.raises(PandaSceneError, match="nuserdata"):
        ArmServer(Simulation(spec.compile()), prefix=PREFIX)
    spec = panda_table_spec()
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_RK4
    with pytest.raises(PandaSceneError, match="RK4"):
        ArmServer(Simulation(spec.compile()), prefix=PREFIX)


def test_contact_steps_count_the_control_steps_that_touch_the_table() -> None:
    """The loop reads the contact sensor inside the step, after the collision pass: the count
    of the state being stepped. A callback before the step sees the previous state's."""
    sim, arm = build_panda_sim(seed=0, cube_xy=(0.6, -0.25))
    sensor = sim.model.sensor(ROBOT_CONTACT_SENSOR).adr[0]
    seen: list[bool] = []
    sim.every(sim.physics_dt, lambda _t: seen.append(sim.data.sensordata[sensor] > 0), name="c")
    handle = arm.move_to(Pose.top_down((0.31, 0.0, 0.35)), 2.0)  # into the table top
    while not handle.status.done:
        sim.step_for(0.01)
    last_state = sim.data.sensordata[sensor] > 0
    assert not seen[0] and sum(seen) > 50
    assert arm.contact_steps == sum(seen[1:]) + last_state
