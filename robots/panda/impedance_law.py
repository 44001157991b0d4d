"""The impedance law's arithmetic as compiled kernels (numba), on preallocated records.

:func:`control_step` is one whole control step of
:class:`~baobab.robots.panda.impedance.CartesianImpedanceController` in one call: the chain's
kinematics and bias torques (:func:`~baobab.robots.panda.chain_dynamics.evaluate_chain`),
then the seed's error, the task and nullspace torques, the saturation and the reference
filter (:func:`impedance_law`).

Why compiled: the step runs 1000 times a simulated second, inside MuJoCo's own step
(:mod:`baobab.robots.panda.native_loop`). In numpy the law alone took ~35 Python-to-C calls
and 70-80 us a step, and the three Pinocchio calls before it ~5 us; here the whole step is
one call. The tests check it against that numpy law on Pinocchio
(``tests/test_panda_impedance_kernel.py``).

Quaternions are x, y, z, w as at the public boundaries; the quaternion algebra comes from
:mod:`baobab.robots.panda.quaternion`.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from baobab.robots.panda.chain_dynamics import CHAIN, evaluate_chain
from baobab.robots.panda.model import ARM_DOF
from baobab.robots.panda.quaternion import (
    multiply_by_conjugate,
    rotation_to_quaternion,
    slerp_towards,
)
from baobab.sim.records import Record

POSE_SIZE = 7
"""A pose as one row: x, y, z (m), then the quaternion qx, qy, qz, qw."""

CONTROLLER_STATE = np.dtype(
    [
        # Gains and limits, set by the controller's set_gains / constructor.
        ("stiffness", np.float64, 6),  # diagonal of K: N/m x3, N m/rad x3
        ("damping", np.float64, 6),  # diagonal of D: N s/m x3, N m s/rad x3
        ("nullspace_stiffness", np.float64, ARM_DOF),  # K_ns, N m/rad
        ("nullspace_damping", np.float64, ARM_DOF),  # D_ns, N m s/rad
        ("gram_damping", np.float64),  # lambda^2 of the damped pseudo-inverse
        ("torque_limits", np.float64, ARM_DOF),  # |tau| bound, N m
        ("max_torque_step", np.float64),  # bound on a torque's change in one step, N m
        ("filter_param", np.float64),  # share of the way to the target per step
        # Set-points.
        ("nullspace_target", np.float64, ARM_DOF),  # posture, rad
        ("reference", np.float64, POSE_SIZE),  # filtered reference pose
        ("target", np.float64, POSE_SIZE),  # set-point pose
        # Results of the last step.
        ("torque", np.float64, ARM_DOF),  # commanded torque, N m (the rate limit's memory)
        ("error", np.float64, 6),  # [e_p (m); e_o = sin(angle/2) axis]
        ("position", np.float64, 3),  # measured TCP position, m
        ("rotation", np.float64, (3, 3)),  # measured TCP rotation
        ("tracking", np.float64, 2),  # distance (m) and angle (rad) to the target
        ("tracking_stale", np.float64),  # 1 when the target moved since "tracking" was taken
    ]
)
"""Everything the law reads and writes besides the chain's results, as one record (all fields
8 bytes wide)."""

CONTROLLER = np.dtype([("chain", CHAIN), ("state", CONTROLLER_STATE)])
"""The controller's whole memory: the robot model with its per-step results, and the law's
state. A kernel call with one argument instead of twenty (numba's dispatch costs ~0.1-0.2 us
per argument, and more for a structured array than for a plain one, so the kernels take the
record's memory as a flat float64 buffer and view it as this record again at no cost)."""


@numba.njit(cache=True, nogil=True, error_model="numpy")
def store_pose(
    destination: np.ndarray, position: np.ndarray, quaternion: np.ndarray
) -> None:  # pragma: no cover
    """Write position (3,) and the normalised quaternion (4,) into a pose row (7,).

    A zero quaternion is stored as it is, as Eigen's ``normalize`` leaves it.
    """
    for c in range(3):
        destination[c] = position[c]
    norm = math.sqrt(
        quaternion[0] * quaternion[0]
        + quaternion[1] * quaternion[1]
        + quaternion[2] * quaternion[2]
        + quaternion[3] * quaternion[3]
    )
    scale = 1.0 / norm if norm > 0.0 else 1.0
    for c in range(4):
        destination[3 + c] = quaternion[c] * scale


@numba.njit(cache=True, nogil=True, error_model="numpy")
def tracking_error(
    position: np.ndarray, rotation: np.ndarray, target: np.ndarray
) -> tuple[float, float]:  # pragma: no cover - compiled
    """Distance (m) and angle (rad) from a TCP pose (position, 3x3 rotation) to a pose row."""
    distance = math.sqrt(
        (target[0] - position[0]) ** 2
        + (target[1] - position[1]) ** 2
        + (target[2] - position[2]) ** 2
    )
    current = np.empty(4)
    rotation_to_quaternion(rotation, current)
    difference = np.empty(4)
    multiply_by_conjugate(current, target[3:], difference)
    vector_norm = math.sqrt(difference[0] ** 2 + difference[1] ** 2 + difference[2] ** 2)
    return distance, 2.0 * math.atan2(vector_norm, abs(difference[3]))


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _cholesky_solve_in_place(matrix: np.ndarray, rhs: np.ndarray) -> None:  # pragma: no cover
    """Solve matrix x = rhs for symmetric positive definite ``matrix`` (lower triangle used).

    ``matrix`` is overwritten by its Cholesky factor L, ``rhs`` by x (LAPACK's dposv).
    """
    size = rhs.shape[0]
    for j in range(size):
        diagonal = matrix[j, j]
        for k in range(j):
            diagonal -= matrix[j, k] * matrix[j, k]
        diagonal = math.sqrt(diagonal)
        matrix[j, j] = diagonal
        for i in range(j + 1, size):
            value = matrix[i, j]
            for k in range(j):
                value -= matrix[i, k] * matrix[j, k]
            matrix[i, j] = value / diagonal
    for i in range(size):
        value = rhs[i]
        for k in range(i):
            value -= matrix[i, k] * rhs[k]
        rhs[i] = value / matrix[i, i]
    for i in range(size - 1, -1, -1):
        value = rhs[i]
        for k in range(i + 1, size):
            value -= matrix[k, i] * rhs[k]
        rhs[i] = value / matrix[i, i]


@numba.njit(cache=True, nogil=True, error_model="numpy")
def control_step_buffer(
    q: np.ndarray, v: np.ndarray, buffer: np.ndarray
) -> None:  # pragma: no cover - compiled
    """:func:`control_step` on a one-element :data:`CONTROLLER` array viewed as float64."""
    control_step(q, v, buffer.view(CONTROLLER)[0])


@numba.njit(cache=True, nogil=True, error_model="numpy")
def control_step(q: np.ndarray, v: np.ndarray, controller: Record) -> None:  # pragma: no cover
    """One control step on a :data:`CONTROLLER` record, from the joint state (9 values each).

    Evaluates the chain at ``q``, ``v``, then runs :func:`impedance_law`.
    """
    evaluate_chain(q, v, controller.chain)
    impedance_law(q, v, controller.chain, controller.state)


@numba.njit(cache=True, nogil=True, error_model="numpy")
def impedance_law(
    q: np.ndarray, v: np.ndarray, chain: Record, record: Record
) -> None:  # pragma: no cover - compiled
    """The seed's Cartesian impedance law for one step, in the base frame.

    The arm is the first ``ARM_DOF`` joints; only they move the TCP.

    Args:
        q: joint positions (nv,), rad and m.
        v: joint velocities (nv,), rad/s and m/s.
        chain: a :data:`~baobab.robots.panda.chain_dynamics.CHAIN` record, evaluated at
            ``q``, ``v``: reads the TCP Jacobian (6, ARM_DOF; linear rows first, in the
            base-aligned frame at the TCP), the bias C(q, v) v + g(q) (N m) and the TCP pose.
        record: a :data:`CONTROLLER_STATE` record. Reads the gains, limits and set-points and
            the previous torque; writes the torque, error, measured pose and tracking error,
            and advances the reference by one filter step.
    """
    jacobian, bias = chain.jacobian, chain.bias
    tcp_translation, tcp_rotation = chain.tcp_position, chain.tcp_rotation
    n = ARM_DOF
    torque, error = record.torque, record.error
    measured_position, measured_rotation = record.position, record.rotation
    reference, target = record.reference, record.target
    max_torque_step, torque_limits = record.max_torque_step, record.torque_limits
    for r in range(3):
        measured_position[r] = tcp_translation[r]
        for c in range(3):
            measured_rotation[r, c] = tcp_rotation[r, c]

    # e = [x_d - x ; R vec(Q^-1 Q_d)] = [x_d - x ; vec(Q_d Q^-1)], short way round.
    for r in range(3):
        error[r] = reference[r] - measured_position[r]
    current = np.empty(4)
    rotation_to_quaternion(measured_rotation, current)
    difference = np.empty(4)
    multiply_by_conjugate(reference[3:], current, difference)
    sign = 1.0 if difference[3] >= 0.0 else -1.0
    for r in range(3):
        error[3 + r] = sign * difference[r]

    # wrench = K e - D J v, then minus (J J^T + lambda^2 I)^-1 J posture so that J^T wrench
    # + posture = J^T (K e - D xdot) + N posture with N = I - J^T (J^T)^+.
    posture = np.empty(n)
    stiffness_ns, damping_ns = record.nullspace_stiffness, record.nullspace_damping
    for j in range(n):
        posture[j] = stiffness_ns[j] * (record.nullspace_target[j] - q[j]) - damping_ns[j] * v[j]
    wrench = np.empty(6)
    rhs = np.empty(6)
    for r in range(6):
        twist = 0.0
        projected = 0.0
        for j in range(n):
            twist += jacobian[r, j] * v[j]
            projected += jacobian[r, j] * posture[j]
        wrench[r] = record.stiffness[r] * error[r] - record.damping[r] * twist
        rhs[r] = projected
    gram = np.empty((6, 6))
    for r in range(6):
        for c in range(r + 1):
            total = 0.0
            for j in range(n):
                total += jacobian[r, j] * jacobian[c, j]
            gram[r, c] = total
    for r in range(6):
        gram[r, r] += record.gram_damping
    _cholesky_solve_in_place(gram, rhs)
    for r in range(6):
        wrench[r] -= rhs[r]

    # tau = J^T wrench + posture + C v + g, then rate limit, then torque limit.
    for j in range(n):
        value = 0.0
        for r in range(6):
            value += jacobian[r, j] * wrench[r]
        value += posture[j]
        value += bias[j]
        previous = torque[j]
        # Comparisons that keep a NaN, as numpy's minimum/maximum do.
        if value > previous + max_torque_step:
            value = previous + max_torque_step
        if value < previous - max_torque_step:
            value = previous - max_torque_step
        if value > torque_limits[j]:
            value = torque_limits[j]
        if value < -torque_limits[j]:
            value = -torque_limits[j]
        torque[j] = value

    # Reference filter (seed §9.4): lerp of the position, slerp of the orientation.
    alpha = record.filter_param
    for r in range(3):
        reference[r] += alpha * (target[r] - reference[r])
    slerp_towards(reference[3:], target[3:], alpha)

    distance, angle = tracking_error(measured_position, measured_rotation, target)
    record.tracking[0] = distance
    record.tracking[1] = angle
    record.tracking_stale = 0.0
