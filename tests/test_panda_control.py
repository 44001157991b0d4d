"""The Cartesian impedance controller and the arm server's tasks, on the simulated Panda."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from baobab.robots.panda.arm_server import ArmErrorCode, ArmServer
from baobab.robots.panda.errors import GainsError, GripperCommandError, TrajectoryGoalError
from baobab.robots.panda.impedance import CartesianImpedanceController, ImpedanceGains
from baobab.robots.panda.model import (
    ARM_JOINTS,
    FINGER_JOINTS,
    HOME_CONFIGURATION,
    PANDA_XML,
    TCP_SITE,
    PandaModel,
)
from baobab.robots.panda.pose import Pose
from baobab.robots.panda.scene import PREFIX, build_panda_sim
from baobab.robots.panda.trajectory import TimeScaling
from baobab.sim.simulation import Simulation
from baobab.sim.tasks import TaskHandle, TaskStatus

HOME = np.r_[HOME_CONFIGURATION, 0.04, 0.04]


def _run(sim: Simulation, handle: TaskHandle, limit: float = 10.0) -> list[dict[str, float]]:
    """Step until ``handle`` ends; return the feedback seen every 2 ms."""
    seen = []
    end = sim.time + limit
    while not handle.status.done and sim.time < end:
        sim.step_for(0.002)
        seen.append(dict(handle.feedback))
    assert handle.status.done
    return seen


def _hand_position(sim: Simulation) -> np.ndarray:
    return sim.data.site(PREFIX + TCP_SITE).xpos.copy()


def test_orientation_error_is_the_seeds_quaternion_error_in_the_base_frame() -> None:
    controller = CartesianImpedanceController(PandaModel())
    q = HOME + np.r_[0.2, -0.1, 0.3, 0.2, -0.4, 0.1, 0.5, 0.0, 0.0]
    controller.reset(q)
    position, rotation = controller.model.tcp_pose(q)
    current = Rotation.from_matrix(rotation)
    desired = Rotation.from_rotvec([0.3, -0.5, 0.9]) * current
    for sign in (1.0, -1.0):  # both quaternions of the same orientation give the same error
        controller.hold(position + [0.01, -0.02, 0.03], sign * desired.as_quat())
        controller.compute_torque(q, np.zeros(9))
        q_error = (current.inv() * desired).as_quat(canonical=True)
        expected = rotation @ q_error[:3]
        np.testing.assert_allclose(controller.error[:3], [0.01, -0.02, 0.03], atol=1e-12)
        np.testing.assert_allclose(controller.error[3:], expected, atol=1e-12)


def test_torque_is_the_seeds_law_plus_coriolis_and_gravity() -> None:
    """Checked against an independent numpy implementation on MuJoCo's J and qfrc_bias."""
    gains = ImpedanceGains(nullspace_stiffness=25.0)
    controller = CartesianImpedanceController(
        PandaModel(), gains, torque_limits=np.full(7, 1e6), torque_rate_limit=1e9
    )
    model = mujoco.MjModel.from_xml_path(str(PANDA_XML))
    data = mujoco.MjData(model)
    rng = np.random.default_rng(2)
    q = HOME + np.r_[rng.normal(0.0, 0.2, 7), 0.0, 0.0]
    v = np.r_[rng.normal(0.0, 0.5, 7), 0.0, 0.0]
    controller.reset(HOME)
    target_position = controller.target[0] + [0.02, 0.01, -0.03]
    target = Rotation.from_rotvec([0.1, 0.0, -0.2]) * Rotation.from_quat(controller.target[1])
    controller.hold(target_position, target.as_quat())
    torque = controller.compute_torque(q, v).copy()

    data.qpos[:], data.qvel[:] = q, v
    mujoco.mj_forward(model, data)
    jacp, jacr = np.zeros((3, 9)), np.zeros((3, 9))
    mujoco.mj_jacSite(model, data, jacp, jacr, model.site(TCP_SITE).id)
    jacobian = np.vstack([jacp, jacr])[:, :7]
    site = data.site(TCP_SITE)
    current = Rotation.from_matrix(site.xmat.reshape(3, 3))
    error = np.r_[
        target_position - site.xpos,
        current.as_matrix() @ (current.inv() * target).as_quat(canonical=True)[:3],
    ]
    stiffness = np.diag(gains.stiffness)
    damping = np.diag(gains.damping)
    pinv_t = np.linalg.solve(jacobian @ jacobian.T + 1e-4 * np.eye(6), jacobian)
    nullspace = np.eye(7) - jacobian.T @ pinv_t
    posture = 25.0 * (HOME[:7] - q[:7]) - gains.nullspace_damping * v[:7]
    expected = (
        jacobian.T @ (stiffness @ error - damping @ jacobian @ v[:7])
        + nullspace @ posture
        + data.qfrc_bias[:7]
    )
    np.testing.assert_allclose(torque, expected, atol=1e-9)


def test_torques_respect_the_limits_and_the_rate_limit() -> None:
    controller = CartesianImpedanceController(PandaModel())
    controller.reset(HOME)
    gravity = controller.model.gravity_torques(HOME)[:7]
    controller.set_target(controller.target[0] + [0.5, 0.5, -0.5], controller.target[1])
    previous = gravity
    for _ in range(200):
        torque = controller.compute_torque(HOME, np.zeros(9)).copy()
        assert np.all(np.abs(torque - previous) <= 1.0 + 1e-12)  # 1000 N m/s at 1 kHz
        assert np.all(np.abs(torque) <= [87, 87, 87, 87, 12, 12, 12])
        previous = torque
    assert np.abs(torque).max() == pytest.approx(87.0) or np.abs(torque[4:]).max() == 12.0


def test_reference_filter_moves_five_percent_per_step() -> None:
    controller = CartesianImpedanceController(PandaModel())
    controller.reset(HOME)
    start_position, start_quaternion = controller.target
    goal = Rotation.from_rotvec([0.0, 0.0, 0.6]) * Rotation.from_quat(start_quaternion)
    controller.set_target(start_position + [0.1, 0.0, 0.0], goal.as_quat())
    for step in range(1, 41):
        controller.compute_torque(HOME, np.zeros(9))
        position, quaternion = controller.reference
        assert position[0] - start_position[0] == pytest.approx(0.1 * (1 - 0.95**step))
        remaining = (Rotation.from_quat(quaternion).inv() * goal).magnitude()
        assert remaining == pytest.approx(0.6 * 0.95**step)


def test_invalid_gains_are_rejected() -> None:
    for bad in (
        {"translational_stiffness": -1.0},
        {"filter_param": 0.0},
        {"damping_ratio": np.nan},
    ):
        with pytest.raises(GainsError):
            ImpedanceGains(**bad)


def test_holds_the_ready_pose_without_drift() -> None:
    sim, _ = build_panda_sim(seed=0)
    start = _hand_position(sim)
    sim.step_for(1.0)
    assert np.linalg.norm(_hand_position(sim) - start) < 1e-4


def test_push_on_the_hand_gives_way_and_recovers() -> None:
    sim, arm = build_panda_sim(seed=0)
    sim.step_for(0.2)
    rest = _hand_position(sim)
    push = sim.data.body(PREFIX + "hand").xfrc_applied
    push[:3] = [20.0, 0.0, 0.0]
    sim.step_for(0.5)
    pushed = _hand_position(sim)
    push[:3] = 0.0
    sim.step_for(1.0)
    displacement = pushed - rest
    # Compliant along the push (about F / K = 6.7 mm), and back afterwards.
    assert displacement[0] > 0.005
    assert np.linalg.norm(displacement) < 0.015
    assert np.linalg.norm(_hand_position(sim) - rest) < 0.01
    assert arm.tcp_pose().distance_to(Pose(tuple(rest), arm.tcp_pose().quaternion))[0] < 0.002


def test_tracking_error_along_a_trajectory_stays_small() -> None:
    sim, arm = build_panda_sim(seed=0)
    start = arm.tcp_pose()
    goal = Pose.from_rotation(
        start.position_array + [0.05, 0.2, -0.1], Rotation.from_euler("z", 0.3) * start.rotation
    )
    handle = arm.move_to(goal, 2.0)
    feedback = _run(sim, handle)
    assert handle.status is TaskStatus.SUCCEEDED
    assert max(f["position_error"] for f in feedback) < 0.01
    assert max(f["orientation_error"] for f in feedback) < 0.05
    # The first 2 ms ran control steps at t = 0 and t = 1 ms.
    assert feedback[0]["remaining_time"] == pytest.approx(2.0 - 0.001)
    assert sim.time < 2.5
    distance, angle = arm.tcp_pose().distance_to(goal)
    assert distance < 0.005 and angle < 0.02


def test_seed_goal_format_and_linear_scaling_work_through_the_server() -> None:
    sim, arm = build_panda_sim(seed=0)
    start = arm.tcp_pose()
    goal = [1.5, start.position[0] + 0.1, start.position[1], start.position[2], *start.quaternion]
    handle = arm.execute_goal(goal, TimeScaling.LINEAR)
    _run(sim, handle)
    assert handle.status is TaskStatus.SUCCEEDED
    with pytest.raises(TrajectoryGoalError):
        arm.execute_goal([0.0, *start.position, *start.quaternion])
    with pytest.raises(ValueError):
        arm.move_to(start, -1.0)
    with pytest.raises(TrajectoryGoalError, match="limit"):
        arm.move_to(start, 1e6)


def test_cancel_holds_the_current_pose() -> None:
    sim, arm = build_panda_sim(seed=0)
    handle = arm.move_to(arm.tcp_pose().translated(dy=0.3), 3.0)
    sim.step_for(1.0)
    handle.cancel()
    assert handle.status is TaskStatus.CANCELED
    held = _hand_position(sim)
    sim.step_for(1.0)
    assert np.linalg.norm(_hand_position(sim) - held) < 0.005
    assert not arm.busy


def test_a_new_goal_preempts_the_running_one() -> None:
    sim, arm = build_panda_sim(seed=0)
    first = arm.move_to(arm.tcp_pose().translated(dy=0.2), 2.0)
    sim.step_for(0.5)
    second = arm.move_to(arm.tcp_pose().translated(dz=-0.1), 1.0)
    assert first.status is TaskStatus.CANCELED
    _run(sim, second)
    assert second.status is TaskStatus.SUCCEEDED


def test_unreachable_goal_fails_at_once() -> None:
    _, arm = build_panda_sim(seed=0)
    handle = arm.move_to(Pose((1.5, 0.0, 0.8)), 2.0)
    assert handle.status is TaskStatus.FAILED
    assert handle.outcome is not None
    assert handle.outcome.error_code == ArmErrorCode.GOAL_UNREACHABLE
    assert "reach" in handle.outcome.error_msg


def test_a_blocked_motion_fails_and_holds() -> None:
    sim, arm = build_panda_sim(seed=0, cube_xy=(0.6, -0.25))
    # Into the table top: the fingers hit it and the arm cannot follow.
    handle = arm.move_to(Pose.top_down((0.31, 0.0, 0.35)), 2.0)
    _run(sim, handle)
    assert handle.status is TaskStatus.FAILED
    assert handle.outcome is not None
    assert handle.outcome.error_name in ("TRACKING_LOST", "GOAL_NOT_REACHED")
    assert not arm.busy


def test_gripper_opens_closes_and_reports_an_empty_grasp() -> None:
    sim, arm = build_panda_sim(seed=0)
    close = arm.gripper("close", require_object=True)
    _run(sim, close)
    assert close.status is TaskStatus.FAILED
    assert close.outcome is not None and close.outcome.error_code == ArmErrorCode.GRASP_FAILED
    assert arm.hand.width < 0.001
    open_ = arm.gripper("open")
    _run(sim, open_)
    assert open_.status is TaskStatus.SUCCEEDED
    assert arm.hand.width == pytest.approx(0.08, abs=0.001)
    close = arm.gripper("close")
    _run(sim, close)
    assert close.status is TaskStatus.SUCCEEDED and close.feedback["grasped_object"] is None
    with pytest.raises(GripperCommandError):
        arm.gripper("squeeze")  # type: ignore[arg-type]


def test_grasp_detection_finds_the_cube_between_the_fingers() -> None:
    sim, arm = build_panda_sim(seed=0, cube_xy=(0.45, -0.1))
    grasp = Pose.top_down((0.45, -0.1, 0.525))
    for pose, duration in ((grasp.translated(dz=0.1), 1.5), (grasp, 1.0)):
        handle = arm.move_to(pose, duration)
        _run(sim, handle)
        assert handle.status is TaskStatus.SUCCEEDED
    close = arm.gripper("close", require_object=True)
    _run(sim, close)
    assert close.status is TaskStatus.SUCCEEDED
    assert close.feedback["grasped_object"] == "cube"
    assert arm.hand.width == pytest.approx(0.05, abs=0.002)
    assert arm.hand.is_grasping()


def test_server_runs_at_one_kilohertz_on_the_scene() -> None:
    sim, arm = build_panda_sim(seed=0)
    assert sim.physics_dt == pytest.approx(0.001)
    assert arm.period == pytest.approx(0.001)
    assert isinstance(arm, ArmServer)
    joints = [sim.model.joint(PREFIX + n) for n in (*ARM_JOINTS, *FINGER_JOINTS)]
    assert len(joints) == 9


def test_runs_are_deterministic() -> None:
    def run() -> list[float]:
        sim, arm = build_panda_sim(seed=4)
        handle = arm.move_to(arm.tcp_pose().translated(dx=0.1, dz=-0.2), 0.8)
        _run(sim, handle)
        return [sim.time, *sim.data.qpos.tolist()]

    assert run() == run()


def test_tcp_pose_is_the_measured_site_pose_with_scipys_quaternion() -> None:
    sim, arm = build_panda_sim(seed=0)
    handle = arm.move_to(arm.tcp_pose().translated(dx=0.1, dy=-0.1), 0.8)
    site = sim.data.site(PREFIX + TCP_SITE)
    while not handle.status.done:
        sim.step_for(0.05)
        # The last control step and mj_step's kinematics saw the same state.
        pose = arm.tcp_pose()
        np.testing.assert_allclose(pose.position, site.xpos, atol=1e-12)
        expected = Rotation.from_matrix(site.xmat.reshape(3, 3)).as_quat()
        np.testing.assert_allclose(pose.quaternion, expected, atol=1e-12)
