"""The seed's Cartesian impedance controller (seeds/002 §8.1, §9.2-§9.4), in the base frame.

One control step, from the joint state (q, v) to the commanded arm torques:

- error e = [x_d - x ; R vec(Q^-1 Q_d)], with Q^-1 Q_d flipped to the hemisphere of
  non-negative scalar part, so the error is the short way round;
- tau_task = J^T (K e - D xdot), xdot = J v;
- tau_ns = N (K_ns (q_d_ns - q) - D_ns v), N = I - J^T (J^T)^+, where
  (J^T)^+ = (J J^T + lambda^2 I)^-1 J is the damped pseudo-inverse;
- tau = tau_task + tau_ns + C(q, v) v + g(q): unlike the real Panda, MuJoCo does not
  compensate Coriolis and gravity for us;
- saturation to the Panda's torque-rate limit (1000 N m/s) and torque limits;
- then one step of the reference filter (§9.4): lerp of the position and slerp of the
  orientation towards the target set-point, by ``filter_param`` per step.

Speed: a 1 kHz loop leaves no room for scipy's ``Rotation`` (its single-rotation operations
cost 30-160 us each in scipy 1.17 here), so the loop uses Pinocchio's Eigen quaternion for the
same algebra and keeps numpy calls few, on preallocated buffers. The tests check the error
against scipy's ``Rotation`` as the oracle. Kinematics and dynamics come from Pinocchio.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from scipy.linalg import lapack

from baobab.robots.panda.errors import GainsError
from baobab.robots.panda.model import ARM_DOF, TORQUE_LIMITS, TORQUE_RATE_LIMIT, PandaModel


@dataclass(frozen=True)
class ImpedanceGains:
    """Stiffness, damping ratio and reference filter of the impedance controller.

    Damping per axis is ``D = 2 * damping_ratio * sqrt(K)`` (the Franka example's formula,
    unit apparent mass).

    Attributes:
        translational_stiffness: K along x, y, z (N/m).
        rotational_stiffness: K about x, y, z (N m/rad).
        damping_ratio: zeta of the Cartesian damping (-).
        nullspace_stiffness: K_ns of the joint-space posture task (N m/rad).
        nullspace_damping_ratio: zeta of the posture task, D_ns = 2 zeta sqrt(K_ns) (-).
        filter_param: share of the distance to the target the reference covers per step (-).
        pseudo_inverse_damping: lambda of the damped pseudo-inverse (-).
    """

    translational_stiffness: float = 3000.0
    rotational_stiffness: float = 300.0
    damping_ratio: float = 1.0
    nullspace_stiffness: float = 10.0
    nullspace_damping_ratio: float = 1.0
    filter_param: float = 0.05
    pseudo_inverse_damping: float = 0.01

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not (math.isfinite(value) and value >= 0.0):
                raise GainsError(f"impedance gain {name} must be finite and >= 0, got {value}")
        if self.pseudo_inverse_damping <= 0.0:
            raise GainsError("pseudo_inverse_damping must be > 0 (it keeps J J^T invertible)")
        if not 0.0 < self.filter_param <= 1.0:
            raise GainsError(f"filter_param must be in (0, 1], got {self.filter_param}")

    @property
    def stiffness(self) -> np.ndarray:
        """Diagonal of the 6x6 Cartesian stiffness (N/m x3, N m/rad x3)."""
        return np.repeat([self.translational_stiffness, self.rotational_stiffness], 3)

    @property
    def damping(self) -> np.ndarray:
        """Diagonal of the 6x6 Cartesian damping (N s/m x3, N m s/rad x3)."""
        return 2.0 * self.damping_ratio * np.sqrt(self.stiffness)

    @property
    def nullspace_damping(self) -> float:
        """D_ns (N m s/rad)."""
        return 2.0 * self.nullspace_damping_ratio * math.sqrt(self.nullspace_stiffness)


class CartesianImpedanceController:
    """Torque controller for the Panda arm; all poses are in the base (link0) frame.

    Call :meth:`reset` once with the measured state, then :meth:`compute_torque` every
    ``period`` seconds. :meth:`set_target` moves the set-point; the reference the law tracks
    follows it through the filter.

    Args:
        model: the Pinocchio model (arm + fingers, 9 dofs).
        gains: stiffness, damping and filter settings.
        period: control period (s); sets the torque-rate bound per step.
        torque_limits: per-joint bound on the commanded torque (N m).
        torque_rate_limit: bound on the torque change (N m/s).
    """

    def __init__(
        self,
        model: PandaModel,
        gains: ImpedanceGains | None = None,
        *,
        period: float = 0.001,
        torque_limits: np.ndarray = TORQUE_LIMITS,
        torque_rate_limit: float = TORQUE_RATE_LIMIT,
    ) -> None:
        self.model = model
        self.period = period
        nq = model.nq
        arm = np.arange(nq) < ARM_DOF
        self._arm = arm
        # Finger entries get zero limits: the controller never drives the fingers.
        self._torque_limits = np.zeros(nq)
        self._torque_limits[:ARM_DOF] = torque_limits
        self._negative_torque_limits = -self._torque_limits
        self._max_torque_step = torque_rate_limit * period
        self._error_and_twist = np.zeros(12)
        self._error = self._error_and_twist[:6]
        self._position_error = self._error_and_twist[:3]
        self._rotation_error = self._error_and_twist[3:6]
        self._twist = self._error_and_twist[6:]
        self._previous_torque = np.zeros(nq)
        self._arm_torque = self._previous_torque[:ARM_DOF]
        self._nullspace_target = np.zeros(nq)
        self._position = np.zeros(3)
        self._rotation = np.eye(3)
        self._position_ref = np.zeros(3)
        self._position_target = np.zeros(3)
        self._quat_ref = pin.Quaternion(1.0, 0.0, 0.0, 0.0)
        self._quat_target = pin.Quaternion(1.0, 0.0, 0.0, 0.0)
        self.set_gains(gains or ImpedanceGains())

    def set_gains(self, gains: ImpedanceGains) -> None:
        """Switch to new gains from the next step on."""
        self.gains = gains
        self._stiffness_damping = np.hstack([np.diag(gains.stiffness), -np.diag(gains.damping)])
        self._nullspace_stiffness = np.where(self._arm, gains.nullspace_stiffness, 0.0)
        self._nullspace_damping = np.where(self._arm, gains.nullspace_damping, 0.0)
        self._alpha = gains.filter_param
        self._pinv_damping = gains.pseudo_inverse_damping**2 * np.eye(6)

    def reset(self, q: np.ndarray) -> None:
        """Hold the TCP where it is at configuration ``q`` (9 values, rad and m).

        Target and reference become the current TCP pose, the nullspace posture becomes the
        current arm configuration, and the torque-rate limiter starts from gravity
        compensation so the first step does not sag.
        """
        position, rotation = self.model.tcp_pose(q)
        self._position[:] = position
        self._rotation[:] = rotation
        self.hold(position, _quaternion_xyzw(rotation))
        self._nullspace_target[:ARM_DOF] = q[:ARM_DOF]
        self._previous_torque[:ARM_DOF] = self.model.gravity_torques(q)[:ARM_DOF]
        self._error[:] = 0.0

    def set_target(self, position: np.ndarray, quaternion: np.ndarray) -> None:
        """New set-point: position (m) and quaternion x, y, z, w in the base frame."""
        self._position_target[:] = position
        self._quat_target = _pin_quaternion(quaternion)

    def hold(self, position: np.ndarray, quaternion: np.ndarray) -> None:
        """Set target and filtered reference to the same pose: no filter transient."""
        self.set_target(position, quaternion)
        self._position_ref[:] = position
        self._quat_ref = pin.Quaternion(self._quat_target)

    def set_nullspace_target(self, q_arm: np.ndarray) -> None:
        """Joint posture (7 values, rad) the nullspace task pulls towards."""
        self._nullspace_target[:ARM_DOF] = q_arm

    @property
    def target(self) -> tuple[np.ndarray, np.ndarray]:
        """The set-point: position (m) and quaternion x, y, z, w."""
        return self._position_target.copy(), self._quat_target.coeffs().copy()

    @property
    def reference(self) -> tuple[np.ndarray, np.ndarray]:
        """The filtered reference the law tracks: position (m) and quaternion x, y, z, w."""
        return self._position_ref.copy(), self._quat_ref.coeffs().copy()

    @property
    def tcp(self) -> tuple[np.ndarray, np.ndarray]:
        """TCP position (m) and rotation matrix measured at the last step."""
        return self._position.copy(), self._rotation.copy()

    @property
    def error(self) -> np.ndarray:
        """The last 6D error [e_p (m); e_o] the law acted on (e_o = sin(angle/2) * axis)."""
        return self._error.copy()

    def target_error(self) -> tuple[float, float]:
        """Distance (m) and angle (rad) from the last measured TCP pose to the set-point."""
        distance = float(np.linalg.norm(self._position_target - self._position))
        current = pin.Quaternion(self._rotation)
        return distance, float(current.angularDistance(self._quat_target))

    def compute_torque(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """One control step: arm torques (7, N m) for state ``q``, ``v`` (9 values each).

        Updates the filtered reference afterwards. The returned array is an internal buffer,
        overwritten by the next call.
        """
        model, data, frame = self.model.model, self.model.data, self.model.tcp_frame
        pin.computeJointJacobians(model, data, q)
        placement = pin.updateFramePlacement(model, data, frame)
        # 6 x 9; the finger columns are zero (the TCP is on the hand), so the whole law runs
        # on 9-vectors and the finger entries drop out in the saturation.
        jacobian = pin.getFrameJacobian(model, data, frame, pin.LOCAL_WORLD_ALIGNED)
        jacobian_t = jacobian.T
        bias = pin.nonLinearEffects(model, data, q, v)
        # Copies: Pinocchio's SE3 hands out views of its own storage that die with it.
        position, rotation = self._position, self._rotation
        position[:] = placement.translation
        rotation[:] = placement.rotation

        # _error_and_twist = [e_p, e_o, xdot]: one product with [K | -D] gives the wrench.
        np.subtract(self._position_ref, position, out=self._position_error)
        # R vec(Q^-1 Q_d) = vec(Q_d Q^-1): rotating the vector part by Q is conjugation.
        quat_error = (self._quat_ref * pin.Quaternion(rotation).conjugate()).coeffs()
        self._rotation_error[:] = quat_error[:3] if quat_error[3] >= 0.0 else -quat_error[:3]
        np.dot(jacobian, v, out=self._twist)
        wrench = np.dot(self._stiffness_damping, self._error_and_twist)

        posture = self._nullspace_stiffness * (self._nullspace_target - q)
        posture -= self._nullspace_damping * v
        # N posture = posture - J^T (J J^T + lambda^2 I)^-1 J posture: one 6x6 Cholesky solve.
        gram = np.dot(jacobian, jacobian_t)
        gram += self._pinv_damping
        wrench -= lapack.dposv(gram, jacobian @ posture)[1]
        torque = np.dot(jacobian_t, wrench)
        torque += posture
        torque += bias

        previous = self._previous_torque
        np.minimum(torque, previous + self._max_torque_step, out=torque)
        np.maximum(torque, previous - self._max_torque_step, out=torque)
        np.minimum(torque, self._torque_limits, out=previous)
        np.maximum(previous, self._negative_torque_limits, out=previous)

        self._position_ref += self._alpha * (self._position_target - self._position_ref)
        self._quat_ref = self._quat_ref.slerp(self._alpha, self._quat_target)
        return self._arm_torque


def _pin_quaternion(quaternion_xyzw: np.ndarray) -> pin.Quaternion:
    x, y, z, w = (float(c) for c in quaternion_xyzw)
    quaternion = pin.Quaternion(w, x, y, z)
    quaternion.normalize()
    return quaternion


def _quaternion_xyzw(rotation: np.ndarray) -> np.ndarray:
    return np.asarray(pin.Quaternion(rotation).coeffs()).copy()
