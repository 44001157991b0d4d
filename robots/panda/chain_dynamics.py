"""The Panda's forward kinematics, TCP Jacobian and bias torques as one compiled kernel.

The controller's model of the robot is Pinocchio's, parsed from ``panda.xml``
(:class:`~baobab.robots.panda.model.PandaModel`), and Pinocchio stays the reference: the tests
check all three results against it (``tests/test_panda_impedance_kernel.py``).

Why compiled: the 1 kHz control step runs inside MuJoCo's own step
(:mod:`baobab.robots.panda.native_loop`), in compiled code that holds no GIL and cannot call
Pinocchio's Python bindings; and from Python, asking Pinocchio for the joint Jacobians, the TCP
placement and the nonlinear effects cost three Python-to-C++ crossings per step (~5 us, most
of it in the crossings). :func:`chain_parameters` copies the model's joint placements, axes
and inertias once into a record, and :func:`evaluate_chain` runs the same algorithms on it:
forward kinematics, the TCP Jacobian in the base-aligned frame at the TCP (Pinocchio's
``LOCAL_WORLD_ALIGNED``) and the recursive Newton-Euler bias ``C(q, v) v + g(q)`` (Pinocchio's
``nonLinearEffects``), in a third of the time of the three calls.

The chain's joints are Pinocchio's joints 1..n in order (parents before children), one degree
of freedom each, revolute or prismatic about a fixed axis. Spatial vectors are (linear,
angular) pairs expressed in a joint's frame, as in Pinocchio.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import pinocchio as pin

from baobab.robots.panda.errors import PandaModelError
from baobab.robots.panda.model import ARM_DOF, FINGER_JOINTS
from baobab.sim.records import Record

CHAIN_JOINTS = ARM_DOF + len(FINGER_JOINTS)
"""Degrees of freedom of the chain: the seven arm joints, then the two fingers."""

CHAIN = np.dtype(
    [
        # The model, copied from Pinocchio by chain_parameters.
        ("parent", np.int64, CHAIN_JOINTS),  # index of the parent joint, -1 for the base
        ("revolute", np.int64, CHAIN_JOINTS),  # 1 revolute, 0 prismatic
        ("axis_index", np.int64, CHAIN_JOINTS),  # the joint frame's axis it moves along: 0..2
        ("axis", np.float64, (CHAIN_JOINTS, 3)),  # that axis as a unit vector
        ("placement_rotation", np.float64, (CHAIN_JOINTS, 3, 3)),  # joint frame in its parent's
        ("placement_translation", np.float64, (CHAIN_JOINTS, 3)),  # at q = 0 (m)
        ("mass", np.float64, CHAIN_JOINTS),  # kg
        ("com", np.float64, (CHAIN_JOINTS, 3)),  # centre of mass in the joint frame (m)
        ("inertia", np.float64, (CHAIN_JOINTS, 3, 3)),  # rotational inertia about it (kg m^2)
        ("gravity", np.float64, 3),  # in the base frame (m/s^2)
        ("tcp_joint", np.int64),  # the joint the TCP moves with
        ("tcp_placement_rotation", np.float64, (3, 3)),  # TCP frame in that joint's frame
        ("tcp_placement_translation", np.float64, 3),  # m
        # Results of evaluate_chain.
        ("rotation", np.float64, (CHAIN_JOINTS, 3, 3)),  # joint frames in the base frame
        ("position", np.float64, (CHAIN_JOINTS, 3)),  # m
        ("tcp_rotation", np.float64, (3, 3)),  # TCP frame in the base frame
        ("tcp_position", np.float64, 3),  # m
        ("jacobian", np.float64, (6, ARM_DOF)),  # TCP Jacobian, linear rows first
        ("bias", np.float64, CHAIN_JOINTS),  # C(q, v) v + g(q) (N m, N)
        # Workspace of the Newton-Euler recursion.
        ("local_rotation", np.float64, (CHAIN_JOINTS, 3, 3)),  # joint frame in its parent's
        ("local_translation", np.float64, (CHAIN_JOINTS, 3)),
        ("velocity", np.float64, (CHAIN_JOINTS, 6)),  # spatial, in the joint frame
        ("acceleration", np.float64, (CHAIN_JOINTS, 6)),  # spatial, gravity as base motion
        ("force", np.float64, (CHAIN_JOINTS, 6)),  # spatial, in the joint frame
    ]
)
"""The chain's model and the kernel's results, as one record. All fields are 8 bytes wide, so
a one-element array of it can travel to a kernel as a flat float64 buffer (``.view(float)``),
which numba dispatches faster than a structured array."""

_REVOLUTE = {"JointModelRX": 0, "JointModelRY": 1, "JointModelRZ": 2}
_PRISMATIC = {"JointModelPX": 0, "JointModelPY": 1, "JointModelPZ": 2}


def chain_parameters(model: pin.Model, tcp_frame: int) -> np.ndarray:
    """A one-element :data:`CHAIN` array holding ``model``'s chain and its TCP frame.

    Raises:
        PandaModelError: if the model does not have :data:`CHAIN_JOINTS` one-axis joints.
    """
    if model.njoints - 1 != CHAIN_JOINTS or model.nv != CHAIN_JOINTS:
        raise PandaModelError(
            f"the controller expects {CHAIN_JOINTS} one-dof joints, got {model.njoints - 1}"
        )
    chain = np.zeros(1, dtype=CHAIN)
    record = chain[0]
    for index in range(CHAIN_JOINTS):
        joint = index + 1  # Pinocchio's joint 0 is the universe
        kind = model.joints[joint].shortname()
        if kind in _REVOLUTE:
            record["revolute"][index] = 1
            record["axis_index"][index] = _REVOLUTE[kind]
        elif kind in _PRISMATIC:
            record["axis_index"][index] = _PRISMATIC[kind]
        else:
            raise PandaModelError(f"joint {model.names[joint]!r} has unsupported type {kind}")
        record["axis"][index, record["axis_index"][index]] = 1.0
        record["parent"][index] = model.parents[joint] - 1
        placement = model.jointPlacements[joint]
        record["placement_rotation"][index] = placement.rotation
        record["placement_translation"][index] = placement.translation
        inertia = model.inertias[joint]
        record["mass"][index] = inertia.mass
        record["com"][index] = inertia.lever
        record["inertia"][index] = inertia.inertia
    record["gravity"] = model.gravity.linear
    frame = model.frames[tcp_frame]
    record["tcp_joint"] = frame.parentJoint - 1
    record["tcp_placement_rotation"] = frame.placement.rotation
    record["tcp_placement_translation"] = frame.placement.translation
    return chain


@numba.njit(cache=True, nogil=True, inline="always")
def _cross(
    a0: float, a1: float, a2: float, b0: float, b1: float, b2: float
) -> tuple[float, float, float]:  # pragma: no cover - compiled
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


Motion = tuple[float, float, float, float, float, float]
"""A spatial vector: linear (m0, m1, m2), then angular (n0, n1, n2) part."""


@numba.njit(cache=True, nogil=True, inline="always")
def _inertia_times(
    mass: float, com: np.ndarray, inertia: np.ndarray, motion: Motion
) -> Motion:  # pragma: no cover - compiled
    """Spatial inertia times motion (m; n): (mass (m - com x n), I_c n + com x linear)."""
    m0, m1, m2, n0, n1, n2 = motion
    k0, k1, k2 = _cross(com[0], com[1], com[2], n0, n1, n2)
    l0, l1, l2 = mass * (m0 - k0), mass * (m1 - k1), mass * (m2 - k2)
    h0, h1, h2 = _cross(com[0], com[1], com[2], l0, l1, l2)
    h0 += inertia[0, 0] * n0 + inertia[0, 1] * n1 + inertia[0, 2] * n2
    h1 += inertia[1, 0] * n0 + inertia[1, 1] * n1 + inertia[1, 2] * n2
    h2 += inertia[2, 0] * n0 + inertia[2, 1] * n1 + inertia[2, 2] * n2
    return l0, l1, l2, h0, h1, h2


@numba.njit(cache=True, nogil=True, error_model="numpy")
def evaluate_chain_buffer(
    q: np.ndarray, v: np.ndarray, buffer: np.ndarray
) -> None:  # pragma: no cover - compiled
    """:func:`evaluate_chain` on a one-element :data:`CHAIN` array viewed as float64."""
    evaluate_chain(q, v, buffer.view(CHAIN)[0])


@numba.njit(cache=True, nogil=True, error_model="numpy")
def evaluate_chain(q: np.ndarray, v: np.ndarray, record: Record) -> None:  # pragma: no cover
    """Forward kinematics, TCP Jacobian and bias torques at ``q``, ``v`` (9 values each).

    Writes the result fields of ``record``, a :data:`CHAIN` record. The Jacobian columns are
    the first ``ARM_DOF`` joints, the TCP's support (the controller checks it).
    """
    n = CHAIN_JOINTS
    local_rotation, local_translation = record.local_rotation, record.local_translation
    rotation, position = record.rotation, record.position
    velocity, acceleration, force = record.velocity, record.acceleration, record.force
    axis = record.axis

    # Forward pass: placements, then spatial velocity and acceleration of each joint frame.
    for i in range(n):
        a0, a1, a2 = axis[i, 0], axis[i, 1], axis[i, 2]
        placement_r = record.placement_rotation[i]
        placement_p = record.placement_translation[i]
        r, p = local_rotation[i], local_translation[i]
        revolute = record.revolute[i] == 1
        if revolute:  # R = placement R @ rot(axis, q): two columns turn, the axis's stays
            s, c = math.sin(q[i]), math.cos(q[i])
            k = record.axis_index[i]
            first, second = (k + 1) % 3, (k + 2) % 3
            for row in range(3):
                x, y = placement_r[row, first], placement_r[row, second]
                r[row, k] = placement_r[row, k]
                r[row, first] = c * x + s * y
                r[row, second] = c * y - s * x
                p[row] = placement_p[row]
        else:  # R = placement R, p = placement p + placement R @ (axis q)
            k = record.axis_index[i]
            for row in range(3):
                r[row, 0], r[row, 1], r[row, 2] = (
                    placement_r[row, 0],
                    placement_r[row, 1],
                    placement_r[row, 2],
                )
                p[row] = placement_p[row] + placement_r[row, k] * q[i]

        parent = record.parent[i]
        if parent < 0:
            for row in range(3):
                position[i, row] = p[row]
                for col in range(3):
                    rotation[i, row, col] = r[row, col]
            # The base is still; gravity enters as an upward acceleration of the base.
            pv0 = pv1 = pv2 = pw0 = pw1 = pw2 = 0.0
            pa0, pa1, pa2 = -record.gravity[0], -record.gravity[1], -record.gravity[2]
            pb0 = pb1 = pb2 = 0.0
        else:
            for row in range(3):
                value = position[parent, row]
                for k in range(3):
                    value += rotation[parent, row, k] * p[k]
                position[i, row] = value
                for col in range(3):
                    value = 0.0
                    for k in range(3):
                        value += rotation[parent, row, k] * r[k, col]
                    rotation[i, row, col] = value
            pv0, pv1, pv2 = velocity[parent, 0], velocity[parent, 1], velocity[parent, 2]
            pw0, pw1, pw2 = velocity[parent, 3], velocity[parent, 4], velocity[parent, 5]
            pa0, pa1, pa2 = (
                acceleration[parent, 0],
                acceleration[parent, 1],
                acceleration[parent, 2],
            )
            pb0, pb1, pb2 = (
                acceleration[parent, 3],
                acceleration[parent, 4],
                acceleration[parent, 5],
            )

        # The parent's motion seen at this joint's origin, in this joint's frame:
        # linear R^T (v + w x p), angular R^T w.
        c0, c1, c2 = _cross(pw0, pw1, pw2, p[0], p[1], p[2])
        d0, d1, d2 = _cross(pb0, pb1, pb2, p[0], p[1], p[2])
        lin0, lin1, lin2 = pv0 + c0, pv1 + c1, pv2 + c2
        acc0, acc1, acc2 = pa0 + d0, pa1 + d1, pa2 + d2
        for k in range(3):
            velocity[i, k] = r[0, k] * lin0 + r[1, k] * lin1 + r[2, k] * lin2
            velocity[i, 3 + k] = r[0, k] * pw0 + r[1, k] * pw1 + r[2, k] * pw2
            acceleration[i, k] = r[0, k] * acc0 + r[1, k] * acc1 + r[2, k] * acc2
            acceleration[i, 3 + k] = r[0, k] * pb0 + r[1, k] * pb1 + r[2, k] * pb2
        # Plus the joint's own motion S qd, and the velocity-product term v x (S qd).
        s0, s1, s2 = a0 * v[i], a1 * v[i], a2 * v[i]
        v0, v1, v2 = velocity[i, 0], velocity[i, 1], velocity[i, 2]
        w0, w1, w2 = velocity[i, 3], velocity[i, 4], velocity[i, 5]
        if revolute:
            w0, w1, w2 = w0 + s0, w1 + s1, w2 + s2
            velocity[i, 3], velocity[i, 4], velocity[i, 5] = w0, w1, w2
            e0, e1, e2 = _cross(v0, v1, v2, s0, s1, s2)
            f0, f1, f2 = _cross(w0, w1, w2, s0, s1, s2)
            acceleration[i, 3] += f0
            acceleration[i, 4] += f1
            acceleration[i, 5] += f2
        else:
            v0, v1, v2 = v0 + s0, v1 + s1, v2 + s2
            velocity[i, 0], velocity[i, 1], velocity[i, 2] = v0, v1, v2
            e0, e1, e2 = _cross(w0, w1, w2, s0, s1, s2)
        acceleration[i, 0] += e0
        acceleration[i, 1] += e1
        acceleration[i, 2] += e2

        # f = I a + v x* (I v), v x* (l, h) = (w x l, w x h + v x l).
        mass, com, inertia = record.mass[i], record.com[i], record.inertia[i]
        a = acceleration[i]
        motion = (a[0], a[1], a[2], a[3], a[4], a[5])
        l0, l1, l2, h0, h1, h2 = _inertia_times(mass, com, inertia, motion)
        m0, m1, m2, k0, k1, k2 = _inertia_times(mass, com, inertia, (v0, v1, v2, w0, w1, w2))
        x0, x1, x2 = _cross(w0, w1, w2, m0, m1, m2)
        y0, y1, y2 = _cross(w0, w1, w2, k0, k1, k2)
        z0, z1, z2 = _cross(v0, v1, v2, m0, m1, m2)
        force[i, 0], force[i, 1], force[i, 2] = l0 + x0, l1 + x1, l2 + x2
        force[i, 3], force[i, 4], force[i, 5] = h0 + y0 + z0, h1 + y1 + z1, h2 + y2 + z2

    # Backward pass: joint torques S^T f, and each joint's force carried to its parent.
    bias = record.bias
    for i in range(n - 1, -1, -1):
        a0, a1, a2 = axis[i, 0], axis[i, 1], axis[i, 2]
        offset = 3 if record.revolute[i] == 1 else 0
        bias[i] = a0 * force[i, offset] + a1 * force[i, offset + 1] + a2 * force[i, offset + 2]
        parent = record.parent[i]
        if parent < 0:
            continue
        r, p = local_rotation[i], local_translation[i]
        l0 = r[0, 0] * force[i, 0] + r[0, 1] * force[i, 1] + r[0, 2] * force[i, 2]
        l1 = r[1, 0] * force[i, 0] + r[1, 1] * force[i, 1] + r[1, 2] * force[i, 2]
        l2 = r[2, 0] * force[i, 0] + r[2, 1] * force[i, 1] + r[2, 2] * force[i, 2]
        h0 = r[0, 0] * force[i, 3] + r[0, 1] * force[i, 4] + r[0, 2] * force[i, 5]
        h1 = r[1, 0] * force[i, 3] + r[1, 1] * force[i, 4] + r[1, 2] * force[i, 5]
        h2 = r[2, 0] * force[i, 3] + r[2, 1] * force[i, 4] + r[2, 2] * force[i, 5]
        k0, k1, k2 = _cross(p[0], p[1], p[2], l0, l1, l2)
        force[parent, 0] += l0
        force[parent, 1] += l1
        force[parent, 2] += l2
        force[parent, 3] += h0 + k0
        force[parent, 4] += h1 + k1
        force[parent, 5] += h2 + k2

    # The TCP, and its Jacobian: a revolute column is (w x (p_tcp - p_joint); w), w the axis
    # in the base frame (a column of the joint's rotation); a prismatic one is (w; 0).
    joint = record.tcp_joint
    tcp_r, tcp_p = record.tcp_rotation, record.tcp_position
    placement_r, placement_p = record.tcp_placement_rotation, record.tcp_placement_translation
    for row in range(3):
        value = position[joint, row]
        for k in range(3):
            value += rotation[joint, row, k] * placement_p[k]
        tcp_p[row] = value
        for col in range(3):
            value = 0.0
            for k in range(3):
                value += rotation[joint, row, k] * placement_r[k, col]
            tcp_r[row, col] = value
    jacobian = record.jacobian
    jacobian[:, :] = 0.0
    while joint >= 0:
        if joint < ARM_DOF:
            k = record.axis_index[joint]
            g0, g1, g2 = rotation[joint, 0, k], rotation[joint, 1, k], rotation[joint, 2, k]
            if record.revolute[joint] == 1:
                u0, u1, u2 = _cross(
                    g0,
                    g1,
                    g2,
                    tcp_p[0] - position[joint, 0],
                    tcp_p[1] - position[joint, 1],
                    tcp_p[2] - position[joint, 2],
                )
                jacobian[0, joint], jacobian[1, joint], jacobian[2, joint] = u0, u1, u2
                jacobian[3, joint], jacobian[4, joint], jacobian[5, joint] = g0, g1, g2
            else:
                jacobian[0, joint], jacobian[1, joint], jacobian[2, joint] = g0, g1, g2
        joint = record.parent[joint]
