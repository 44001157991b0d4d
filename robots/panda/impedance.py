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

Speed: a step is one compiled kernel, :func:`~baobab.robots.panda.impedance_law.control_step`,
on one preallocated record: the forward kinematics, TCP Jacobian and bias torques of the
Pinocchio model (evaluated by :mod:`~baobab.robots.panda.chain_dynamics`), then the law. That
is ~4 us, against ~9 us with three Pinocchio calls before the kernel, 70-80 us for the law in
numpy (~35 Python-to-C calls) and 30-160 us for a single scipy ``Rotation`` operation. The
tests check the kernel against Pinocchio, the numpy implementation and scipy's ``Rotation``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from baobab.robots.panda.chain_dynamics import chain_parameters
from baobab.robots.panda.errors import GainsError, PandaModelError
from baobab.robots.panda.impedance_law import (
    CONTROLLER,
    CONTROLLER_STATE,
    control_step_buffer,
    store_pose,
    tracking_error,
)
from baobab.robots.panda.model import ARM_DOF, TORQUE_LIMITS, TORQUE_RATE_LIMIT, PandaModel
from baobab.robots.panda.quaternion import rotation_to_quaternion


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
        _check_tcp_moves_with_the_arm_only(model.model, model.tcp_frame)
        self._record = np.zeros(1, dtype=CONTROLLER)
        self._record["chain"] = chain_parameters(model.model, model.tcp_frame)
        self.buffer = self._record.view(np.float64)
        """The controller's memory as the flat float64 array the compiled kernels take."""
        # The law's state, and views of its fields for the Python side.
        self._state = self._record["state"]
        fields = {name: self._state[name][0] for name in CONTROLLER_STATE.names or ()}
        self._fields = fields
        self._reference, self._target = fields["reference"], fields["target"]
        self._reference[6] = self._target[6] = 1.0
        self._rotation = fields["rotation"]
        self._rotation[:] = np.eye(3)
        self._tracking_stale = self._state["tracking_stale"]  # shape (1,): a view
        self._tracking_stale[0] = 1.0
        self._state["torque_limits"] = torque_limits
        self._state["max_torque_step"] = torque_rate_limit * period
        self.set_gains(gains or ImpedanceGains())

    def set_gains(self, gains: ImpedanceGains) -> None:
        """Switch to new gains from the next step on."""
        self.gains = gains
        state = self._state
        state["stiffness"] = gains.stiffness
        state["damping"] = gains.damping
        state["nullspace_stiffness"] = gains.nullspace_stiffness
        state["nullspace_damping"] = gains.nullspace_damping
        state["gram_damping"] = gains.pseudo_inverse_damping**2
        state["filter_param"] = gains.filter_param

    def reset(self, q: np.ndarray) -> None:
        """Hold the TCP where it is at configuration ``q`` (9 values, rad and m).

        Target and reference become the current TCP pose, the nullspace posture becomes the
        current arm configuration, and the torque-rate limiter starts from gravity
        compensation so the first step does not sag.
        """
        position, rotation = self.model.tcp_pose(q)
        fields = self._fields
        fields["position"][:] = position
        fields["rotation"][:] = rotation
        self.hold(position, _quaternion_xyzw(rotation))
        fields["nullspace_target"][:] = q[:ARM_DOF]
        fields["torque"][:] = self.model.gravity_torques(q)[:ARM_DOF]
        fields["error"][:] = 0.0

    def set_target(self, position: np.ndarray, quaternion: np.ndarray) -> None:
        """New set-point: position (m) and quaternion x, y, z, w in the base frame."""
        store_pose(self._target, position, quaternion)
        self._tracking_stale[0] = 1.0

    def hold(self, position: np.ndarray, quaternion: np.ndarray) -> None:
        """Set target and filtered reference to the same pose: no filter transient."""
        self.set_target(position, quaternion)
        self._reference[:] = self._target

    def set_nullspace_target(self, q_arm: np.ndarray) -> None:
        """Joint posture (7 values, rad) the nullspace task pulls towards."""
        self._fields["nullspace_target"][:] = q_arm

    @property
    def target(self) -> tuple[np.ndarray, np.ndarray]:
        """The set-point: position (m) and quaternion x, y, z, w."""
        return self._target[:3].copy(), self._target[3:].copy()

    @property
    def reference(self) -> tuple[np.ndarray, np.ndarray]:
        """The filtered reference the law tracks: position (m) and quaternion x, y, z, w."""
        return self._reference[:3].copy(), self._reference[3:].copy()

    @property
    def tcp(self) -> tuple[np.ndarray, np.ndarray]:
        """TCP position (m) and rotation matrix measured at the last step."""
        return self._fields["position"].copy(), self._rotation.copy()

    @property
    def measured_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """:attr:`tcp` without the copies: views the next step overwrites."""
        return self._fields["position"], self._rotation

    @property
    def target_position(self) -> np.ndarray:
        """The set-point position (m): a view the next set-point overwrites."""
        return self._target[:3]

    @property
    def error(self) -> np.ndarray:
        """The last 6D error [e_p (m); e_o] the law acted on (e_o = sin(angle/2) * axis)."""
        return self._fields["error"].copy()

    def target_error(self) -> tuple[float, float]:
        """Distance (m) and angle (rad) from the last measured TCP pose to the set-point."""
        tracking = self._fields["tracking"]
        if self._tracking_stale[0]:  # the step computed it, but the target moved since
            tracking[:] = tracking_error(self._fields["position"], self._rotation, self._target)
            self._tracking_stale[0] = 0.0
        return float(tracking[0]), float(tracking[1])

    def compute_torque(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """One control step: arm torques (7, N m) for state ``q``, ``v`` (9 float64 each).

        Updates the filtered reference afterwards. The returned array is an internal buffer,
        overwritten by the next call.
        """
        control_step_buffer(q, v, self.buffer)
        return self._fields["torque"]


def _check_tcp_moves_with_the_arm_only(model: pin.Model, frame: int) -> None:
    """The kernel's Jacobian uses the first ARM_DOF columns: they must be the TCP's support."""
    support = model.supports[model.frames[frame].parentJoint]
    columns = sorted(model.joints[joint].idx_v for joint in support if joint > 0)
    if columns != list(range(ARM_DOF)):
        raise PandaModelError(
            f"the TCP must move with the first {ARM_DOF} joints only, got columns {columns}"
        )


def _quaternion_xyzw(rotation: np.ndarray) -> np.ndarray:
    quaternion = np.empty(4)
    rotation_to_quaternion(rotation, quaternion)
    return quaternion
