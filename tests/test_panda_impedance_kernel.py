"""The compiled impedance step against the previous numpy implementation, kept here as the
reference, its chain dynamics against Pinocchio, and its quaternion helpers against scipy."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from scipy.linalg import lapack
from scipy.spatial.transform import Rotation, Slerp

from baobab.robots.panda.chain_dynamics import (
    CHAIN,
    chain_parameters,
    evaluate_chain_buffer,
)
from baobab.robots.panda.errors import PandaModelError
from baobab.robots.panda.impedance import CartesianImpedanceController, ImpedanceGains
from baobab.robots.panda.impedance_law import store_pose, tracking_error
from baobab.robots.panda.model import (
    ARM_DOF,
    HOME_CONFIGURATION,
    LEFT_FINGER_BODY,
    TORQUE_LIMITS,
    TORQUE_RATE_LIMIT,
    PandaModel,
)
from baobab.robots.panda.quaternion import (
    matrix_to_quaternion,
    multiply_by_conjugate,
    rotation_to_quaternion,
    slerp_towards,
)

HOME = np.r_[HOME_CONFIGURATION, 0.04, 0.04]


class _NumpyReference:
    """The controller as it was before the kernel: Pinocchio + numpy + Eigen quaternions."""

    def __init__(
        self,
        model: PandaModel,
        gains: ImpedanceGains,
        *,
        period: float = 0.001,
        torque_limits: np.ndarray = TORQUE_LIMITS,
        torque_rate_limit: float = TORQUE_RATE_LIMIT,
    ) -> None:
        self.model = model
        nq = model.nq
        arm = np.arange(nq) < ARM_DOF
        self._torque_limits = np.zeros(nq)
        self._torque_limits[:ARM_DOF] = torque_limits
        self._max_torque_step = torque_rate_limit * period
        self._error_and_twist = np.zeros(12)
        self.previous_torque = np.zeros(nq)
        self.nullspace_target = np.zeros(nq)
        self.position = np.zeros(3)
        self.rotation = np.eye(3)
        self.position_ref = np.zeros(3)
        self.position_target = np.zeros(3)
        self.quat_ref = pin.Quaternion(1.0, 0.0, 0.0, 0.0)
        self.quat_target = pin.Quaternion(1.0, 0.0, 0.0, 0.0)
        self._stiffness_damping = np.hstack([np.diag(gains.stiffness), -np.diag(gains.damping)])
        self._nullspace_stiffness = np.where(arm, gains.nullspace_stiffness, 0.0)
        self._nullspace_damping = np.where(arm, gains.nullspace_damping, 0.0)
        self._alpha = gains.filter_param
        self._pinv_damping = gains.pseudo_inverse_damping**2 * np.eye(6)

    @property
    def error(self) -> np.ndarray:
        return self._error_and_twist[:6].copy()

    def set_target(self, position: np.ndarray, quaternion: np.ndarray) -> None:
        self.position_target[:] = position
        x, y, z, w = (float(c) for c in quaternion)
        self.quat_target = pin.Quaternion(w, x, y, z)
        self.quat_target.normalize()

    def hold(self, position: np.ndarray, quaternion: np.ndarray) -> None:
        self.set_target(position, quaternion)
        self.position_ref[:] = position
        self.quat_ref = pin.Quaternion(self.quat_target)

    def target_error(self) -> tuple[float, float]:
        distance = float(np.linalg.norm(self.position_target - self.position))
        current = pin.Quaternion(self.rotation)
        return distance, float(current.angularDistance(self.quat_target))

    def compute_torque(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        model, data, frame = self.model.model, self.model.data, self.model.tcp_frame
        pin.computeJointJacobians(model, data, q)
        placement = pin.updateFramePlacement(model, data, frame)
        jacobian = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
        jacobian_t = jacobian.T
        bias = pin.nonLinearEffects(model, data, q, v)
        self.position[:] = placement.translation
        self.rotation[:] = placement.rotation
        error = self._error_and_twist
        np.subtract(self.position_ref, self.position, out=error[:3])
        quat_error = (self.quat_ref * pin.Quaternion(self.rotation).conjugate()).coeffs()
        error[3:6] = quat_error[:3] if quat_error[3] >= 0.0 else -quat_error[:3]
        np.dot(jacobian, v, out=error[6:])
        wrench = np.dot(self._stiffness_damping, error)
        posture = self._nullspace_stiffness * (self.nullspace_target - q)
        posture -= self._nullspace_damping * v
        gram = np.dot(jacobian, jacobian_t)
        gram += self._pinv_damping
        wrench -= lapack.dposv(gram, jacobian @ posture)[1]
        torque = np.dot(jacobian_t, wrench)
        torque += posture
        torque += bias
        previous = self.previous_torque
        np.minimum(torque, previous + self._max_torque_step, out=torque)
        np.maximum(torque, previous - self._max_torque_step, out=torque)
        np.minimum(torque, self._torque_limits, out=previous)
        np.maximum(previous, -self._torque_limits, out=previous)
        self.position_ref += self._alpha * (self.position_target - self.position_ref)
        self.quat_ref = self.quat_ref.slerp(self._alpha, self.quat_target)
        return previous[:ARM_DOF]


def _random_gains(rng: np.random.Generator) -> ImpedanceGains:
    return ImpedanceGains(
        translational_stiffness=rng.uniform(100.0, 5000.0),
        rotational_stiffness=rng.uniform(10.0, 500.0),
        damping_ratio=rng.uniform(0.3, 1.5),
        nullspace_stiffness=rng.uniform(0.0, 50.0),
        nullspace_damping_ratio=rng.uniform(0.3, 1.5),
        filter_param=rng.uniform(0.01, 1.0),
        pseudo_inverse_damping=rng.uniform(0.001, 0.2),
    )


def _random_state(model: PandaModel, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    low, high = model.model.lowerPositionLimit, model.model.upperPositionLimit
    return rng.uniform(low, high), rng.normal(0.0, 1.0, model.nq)


@pytest.mark.parametrize("saturated", [False, True])
def test_kernel_matches_the_numpy_implementation_on_random_states(saturated: bool) -> None:
    rng = np.random.default_rng(11 + saturated)
    limits = {} if saturated else {"torque_limits": np.full(7, 1e6), "torque_rate_limit": 1e9}
    fast_model, slow_model = PandaModel(), PandaModel()
    limited = beyond_limit = 0
    for _ in range(40):
        gains = _random_gains(rng)
        fast = CartesianImpedanceController(fast_model, gains, **limits)  # type: ignore[arg-type]
        slow = _NumpyReference(slow_model, gains, **limits)  # type: ignore[arg-type]
        q0, _ = _random_state(fast_model, rng)
        fast.reset(q0)
        slow.hold(*fast.target)
        slow.nullspace_target[:ARM_DOF] = q0[:ARM_DOF]
        slow.previous_torque[:ARM_DOF] = fast_model.gravity_torques(q0)[:ARM_DOF]
        # A set-point ~0.2 m / ~1.6 rad away, its quaternion in either sign, unnormalised.
        position, quaternion = fast.target
        rotation = Rotation.from_rotvec(rng.normal(0.0, 1.0, 3)) * Rotation.from_quat(quaternion)
        goal = (position + rng.normal(0.0, 0.1, 3), rng.choice([-2.0, 0.5]) * rotation.as_quat())
        for controller in (fast, slow):
            controller.set_target(*goal)
        for _ in range(5):
            q, v = _random_state(fast_model, rng)
            previous = slow.previous_torque[:ARM_DOF].copy()
            torque = fast.compute_torque(q, v).copy()
            expected = slow.compute_torque(q, v).copy()
            np.testing.assert_allclose(torque, expected, rtol=0.0, atol=1e-9)
            np.testing.assert_allclose(fast.error, slow.error, rtol=0.0, atol=1e-12)
            reference = fast.reference
            np.testing.assert_allclose(reference[0], slow.position_ref, rtol=0.0, atol=1e-12)
            np.testing.assert_allclose(reference[1], slow.quat_ref.coeffs(), rtol=0, atol=1e-12)
            np.testing.assert_allclose(fast.target[1], slow.quat_target.coeffs(), atol=1e-15)
            np.testing.assert_allclose(fast.target_error(), slow.target_error(), atol=1e-12)
            # The kernel's own forward kinematics: Pinocchio's up to rounding.
            np.testing.assert_allclose(fast.tcp[1], slow.rotation, rtol=0.0, atol=1e-14)
            rate_limited = np.isclose(np.abs(torque - previous), 0.001 * TORQUE_RATE_LIMIT)
            limited += int(np.any(rate_limited | (np.abs(torque) == TORQUE_LIMITS)))
            beyond_limit += int(np.any(np.abs(torque) > TORQUE_LIMITS))
    # Both cases ran: the saturated controller was limited, the other went past the limits.
    assert (limited > 100 and beyond_limit == 0) if saturated else beyond_limit > 20


def test_chain_kernel_is_pinocchios_kinematics_jacobian_and_bias() -> None:
    """Forward kinematics, TCP Jacobian (LOCAL_WORLD_ALIGNED) and nonLinearEffects, with a
    tilted gravity so that every axis of the bias recursion is exercised."""
    model = PandaModel(gravity=np.array([1.5, -0.8, -9.6]))
    pin_model, pin_data, frame = model.model, model.data, model.tcp_frame
    chain = chain_parameters(pin_model, frame)
    record = chain[0]
    rng = np.random.default_rng(21)
    for _ in range(50):
        q, v = _random_state(model, rng)
        v *= 3.0  # up to ~9 rad/s: Coriolis terms of the size of gravity's
        evaluate_chain_buffer(q, v, chain.view(np.float64))
        pin.framesForwardKinematics(pin_model, pin_data, q)
        placement = pin_data.oMf[frame]
        jacobian = pin.computeFrameJacobian(pin_model, pin_data, q, frame, pin.LOCAL_WORLD_ALIGNED)
        bias = pin.nonLinearEffects(pin_model, pin_data, q, v)
        np.testing.assert_allclose(record["tcp_position"], placement.translation, atol=1e-14)
        np.testing.assert_allclose(record["tcp_rotation"], placement.rotation, atol=1e-14)
        np.testing.assert_allclose(record["jacobian"], jacobian[:, :ARM_DOF], atol=1e-14)
        np.testing.assert_allclose(record["bias"], bias, rtol=1e-12, atol=1e-11)
        for joint in range(1, pin_model.njoints):
            oMi = pin_data.oMi[joint]
            np.testing.assert_allclose(record["position"][joint - 1], oMi.translation, atol=1e-14)
    assert CHAIN.itemsize % 8 == 0  # the record travels as a float64 buffer


def test_chain_refuses_a_model_of_another_shape() -> None:
    reduced = pin.buildReducedModel(PandaModel().model, [9], HOME)
    with pytest.raises(PandaModelError, match="9 one-dof joints"):
        chain_parameters(reduced, reduced.getFrameId("tcp"))


def test_rotation_to_quaternion_matches_scipy() -> None:
    rotations = Rotation.random(200, random_state=3)
    # Include the branches of a non-positive trace: half-turns about each axis.
    rotations = Rotation.concatenate([rotations, Rotation.from_rotvec(np.pi * np.eye(3))])
    out = np.empty(4)
    for rotation in rotations:
        rotation_to_quaternion(rotation.as_matrix(), out)
        expected = rotation.as_quat(canonical=True)
        np.testing.assert_allclose(out * np.sign(out @ expected), expected, atol=1e-12)


def test_matrix_to_quaternion_is_scipys_from_matrix() -> None:
    rotations = Rotation.concatenate(
        [Rotation.random(200, random_state=4), Rotation.from_rotvec(np.pi * np.eye(3))]
    )
    out = np.empty(4)
    for rotation in rotations:
        matrix = rotation.as_matrix()
        matrix_to_quaternion(matrix, out)
        np.testing.assert_allclose(out, Rotation.from_matrix(matrix).as_quat(), atol=1e-15)


def test_product_with_the_conjugate_is_scipys_composition() -> None:
    first, second = Rotation.random(100, random_state=6), Rotation.random(100, random_state=9)
    out = np.empty(4)
    for a, b in zip(first, second, strict=True):
        multiply_by_conjugate(a.as_quat(), b.as_quat(), out)
        np.testing.assert_allclose(out, (a * b.inv()).as_quat(), atol=1e-15)


def test_slerp_matches_scipy_and_goes_the_short_way() -> None:
    rng = np.random.default_rng(5)
    for _ in range(100):
        start, goal = Rotation.random(2, random_state=rng)
        t = rng.uniform(0.0, 1.0)
        quaternion = start.as_quat()
        # The goal's other sign: slerp must still take the short way round.
        slerp_towards(quaternion, -goal.as_quat(), t)
        expected = Slerp([0.0, 1.0], Rotation.concatenate([start, goal]))(t)
        assert (Rotation.from_quat(quaternion).inv() * expected).magnitude() < 1e-9
    same = Rotation.random(random_state=1).as_quat()
    moved = same.copy()
    slerp_towards(moved, same, 0.3)
    np.testing.assert_allclose(moved, same, atol=1e-15)


def test_tracking_error_and_stored_pose() -> None:
    rng = np.random.default_rng(8)
    row = np.empty(7)
    for _ in range(50):
        current, goal = Rotation.random(2, random_state=rng)
        position, goal_position = rng.normal(size=3), rng.normal(size=3)
        store_pose(row, goal_position, 3.0 * goal.as_quat())
        np.testing.assert_allclose(row[3:], goal.as_quat(), atol=1e-15)
        distance, angle = tracking_error(position, current.as_matrix(), row)
        assert distance == pytest.approx(np.linalg.norm(goal_position - position), abs=1e-12)
        assert angle == pytest.approx((current.inv() * goal).magnitude(), abs=1e-9)


def test_controller_refuses_a_tcp_the_fingers_move() -> None:
    model = PandaModel()
    model.tcp_frame = model.model.getFrameId(LEFT_FINGER_BODY)
    with pytest.raises(PandaModelError, match="first 7 joints"):
        CartesianImpedanceController(model)
