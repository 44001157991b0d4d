"""The Panda description: Panda figures, MuJoCo/Pinocchio agreement, and the table scene."""

from __future__ import annotations

import mujoco
import numpy as np
import pinocchio as pin
import pytest
from scipy.spatial.transform import Rotation

from baobab.robots.panda.errors import PandaSceneError
from baobab.robots.panda.model import (
    ARM_JOINTS,
    FINGER_JOINTS,
    HOME_CONFIGURATION,
    PANDA_XML,
    TCP_SITE,
    TORQUE_LIMITS,
    PandaModel,
)
from baobab.robots.panda.scene import (
    CUBE_REGION,
    PREFIX,
    TABLE_HEIGHT,
    build_panda_sim,
    cube_pose,
    panda_table_spec,
)
from baobab.sim.errors import BaobabError

JOINT_RANGES = np.array(
    [
        [-2.8973, 2.8973],
        [-1.7628, 1.7628],
        [-2.8973, 2.8973],
        [-3.0718, -0.0698],
        [-2.8973, 2.8973],
        [-0.0175, 3.7525],
        [-2.8973, 2.8973],
    ]
)


@pytest.fixture(scope="module")
def mj() -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = mujoco.MjModel.from_xml_path(str(PANDA_XML))
    return model, mujoco.MjData(model)


def _random_states(model: mujoco.MjModel, count: int, seed: int) -> list[tuple[np.ndarray, ...]]:
    rng = np.random.default_rng(seed)
    low, high = model.jnt_range[:, 0], model.jnt_range[:, 1]
    return [(rng.uniform(low, high), rng.normal(0.0, 1.0, model.nv)) for _ in range(count)]


def test_mjcf_carries_the_panda_figures(mj: tuple[mujoco.MjModel, mujoco.MjData]) -> None:
    model, _ = mj
    arm_ranges = np.array([model.joint(name).range for name in ARM_JOINTS])
    np.testing.assert_allclose(arm_ranges, JOINT_RANGES)
    for name in FINGER_JOINTS:
        np.testing.assert_allclose(model.joint(name).range, [0.0, 0.04])
    torque_ranges = np.array([model.actuator(name).ctrlrange for name in ARM_JOINTS])
    np.testing.assert_allclose(torque_ranges, np.c_[-TORQUE_LIMITS, TORQUE_LIMITS])
    assert model.actuator(ARM_JOINTS[0]).trntype == mujoco.mjtTrn.mjTRN_JOINT
    np.testing.assert_allclose([model.joint(name).armature for name in ARM_JOINTS], 0.1)
    assert model.body_subtreemass[model.body("link0").id] == pytest.approx(17.45, abs=0.01)
    assert model.nmesh == 0


def test_ready_pose_puts_the_tcp_ahead_of_the_base_pointing_down() -> None:
    model = PandaModel()
    position, rotation = model.tcp_pose(np.r_[HOME_CONFIGURATION, 0.04, 0.04])
    np.testing.assert_allclose(position, [0.307, 0.0, 0.487], atol=1e-3)
    np.testing.assert_allclose(rotation, np.diag([1.0, -1.0, -1.0]), atol=1e-6)


def test_pinocchio_agrees_with_mujoco_at_50_configurations(
    mj: tuple[mujoco.MjModel, mujoco.MjData],
) -> None:
    model, data = mj
    pin_model = PandaModel()
    assert pin_model.joint_names == (*ARM_JOINTS, *FINGER_JOINTS)
    site = model.site(TCP_SITE).id
    jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    mass = np.zeros((model.nv, model.nv))
    for q, v in _random_states(model, 50, seed=7):
        data.qpos[:], data.qvel[:] = q, v
        mujoco.mj_forward(model, data)
        mujoco.mj_jacSite(model, data, jacp, jacr, site)
        mujoco.mj_fullM(model, data, mass)
        position, rotation = pin_model.tcp_pose(q)
        np.testing.assert_allclose(position, data.site(site).xpos, atol=1e-9)
        np.testing.assert_allclose(rotation.ravel(), data.site(site).xmat, atol=1e-9)
        np.testing.assert_allclose(pin_model.tcp_jacobian(q), np.vstack([jacp, jacr]), atol=1e-9)
        np.testing.assert_allclose(pin_model.mass_matrix(q), mass, atol=1e-9)
        np.testing.assert_allclose(pin_model.nonlinear_effects(q, v), data.qfrc_bias, atol=1e-9)


def test_jacobian_matches_finite_differences_of_forward_kinematics() -> None:
    model = PandaModel()
    rng = np.random.default_rng(3)
    step = 1e-6
    for _ in range(10):
        q = rng.uniform(model.model.lowerPositionLimit, model.model.upperPositionLimit)
        jacobian = model.tcp_jacobian(q)
        for joint in range(model.nq):
            dq = np.zeros(model.nq)
            dq[joint] = step
            p_plus, r_plus = model.tcp_pose(q + dq)
            p_minus, r_minus = model.tcp_pose(q - dq)
            linear = (p_plus - p_minus) / (2 * step)
            angular = Rotation.from_matrix(r_plus @ r_minus.T).as_rotvec() / (2 * step)
            np.testing.assert_allclose(jacobian[:3, joint], linear, atol=1e-7)
            np.testing.assert_allclose(jacobian[3:, joint], angular, atol=1e-7)


def test_scene_model_agrees_with_pinocchio_through_the_base_transform() -> None:
    sim, arm = build_panda_sim(seed=0)
    data = sim.data
    joints = [data.joint(PREFIX + name) for name in (*ARM_JOINTS, *FINGER_JOINTS)]
    dofs = np.array(
        [int(sim.model.joint(PREFIX + n).dofadr[0]) for n in (*ARM_JOINTS, *FINGER_JOINTS)]
    )
    for q, v in _random_states(mujoco.MjModel.from_xml_path(str(PANDA_XML)), 10, seed=5):
        for joint, qi, vi in zip(joints, q, v, strict=True):
            joint.qpos, joint.qvel = qi, vi
        sim.forward()
        position, rotation = arm.pin_model.tcp_pose(q)
        world = arm.base_position + arm.base_rotation.apply(position)
        np.testing.assert_allclose(world, data.site(PREFIX + TCP_SITE).xpos, atol=1e-9)
        world_rotation = arm.base_rotation.as_matrix() @ rotation
        np.testing.assert_allclose(
            world_rotation.ravel(), data.site(PREFIX + TCP_SITE).xmat, atol=1e-9
        )
        bias = arm.pin_model.nonlinear_effects(q, v)
        np.testing.assert_allclose(bias, data.qfrc_bias[dofs], atol=1e-9)


def test_scene_keeps_its_own_solver_options() -> None:
    model = panda_table_spec().compile()
    assert model.opt.timestep == pytest.approx(0.001)
    assert model.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    assert model.opt.cone == mujoco.mjtCone.mjCONE_ELLIPTIC
    # impratio 400 instead of the no-slip solver (cheaper, see test_panda_physics), and sleep.
    assert model.opt.impratio == pytest.approx(400.0)
    assert model.opt.noslip_iterations == 0
    assert model.opt.enableflags & mujoco.mjtEnableBit.mjENBL_SLEEP


def test_ready_pose_touches_nothing() -> None:
    sim, _ = build_panda_sim(seed=0)
    model, data = sim.model, sim.data
    robot_bodies = {
        model.body(i).id for i in range(model.nbody) if model.body(i).name.startswith(PREFIX)
    }
    for contact in data.contact[: data.ncon]:
        bodies = {model.geom_bodyid[contact.geom1], model.geom_bodyid[contact.geom2]}
        assert not bodies & robot_bodies


def test_cube_positions_are_seeded_and_on_the_table() -> None:
    positions = [cube_pose(build_panda_sim(seed=seed)[0]).position for seed in (0, 0, 1)]
    assert positions[0] == positions[1]
    assert positions[0] != positions[2]
    (x_low, x_high), (y_low, y_high) = CUBE_REGION
    for x, y, z in positions:
        assert x_low <= x <= x_high and y_low <= y <= y_high
        assert z == pytest.approx(TABLE_HEIGHT + 0.025)
    sim, _ = build_panda_sim(cube_xy=(0.5, -0.2), cube_yaw=0.3)
    assert cube_pose(sim).position[:2] == pytest.approx((0.5, -0.2))
    assert cube_pose(sim).rotation.as_euler("ZYX")[0] == pytest.approx(0.3)


@pytest.mark.parametrize("kwargs", [{"cube_xy": (2.0, 0.0)}, {"cube_mass": 0.0}])
def test_scene_rejects_impossible_requests(kwargs: dict[str, object]) -> None:
    with pytest.raises(PandaSceneError) as raised:
        build_panda_sim(**kwargs)  # type: ignore[arg-type]
    assert isinstance(raised.value, ValueError) and isinstance(raised.value, BaobabError)


def test_pinocchio_drops_the_tendon_but_keeps_armature_and_limits() -> None:
    model = pin.buildModelFromMJCF(str(PANDA_XML))
    assert model.nq == model.nv == 9
    np.testing.assert_allclose(model.armature[:7], 0.1)
    np.testing.assert_allclose(model.lowerPositionLimit[:7], JOINT_RANGES[:, 0])
    np.testing.assert_allclose(model.upperPositionLimit[:7], JOINT_RANGES[:, 1])
