"""A base's ground truth from its free joint, compiled: pose and body velocity in one call.

:meth:`~baobab.robots.diff_drive.base.DiffDriveBase.pose` and ``body_velocity`` read the
chassis' free joint once per physics state: the position, the yaw of the rotation matrix of
the orientation quaternion (MuJoCo's own ``mju_quat2Mat``), the forward speed and the yaw rate.
From Python that is a call through the bindings, a list of the matrix and another of the
velocity, each slow when the physics has just run and the caches are cold; :func:`ground_truth`
is one compiled call that calls MuJoCo by symbol. :func:`ground_truth_reference` is the Python
it replaces, and ``tests/test_ground_truth_kernel.py`` compares the two bit for bit.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import cast

import mujoco
import numba
import numpy as np
from numba import types

from baobab.sim.mujoco_native import pointer

quat_to_mat = cast(
    Callable[[int, int], None],
    types.ExternalFunction("mju_quat2Mat", types.void(types.intp, types.intp)),
)
"""``mju_quat2Mat(res, quat)``: the row-major rotation matrix of a quaternion ``w, x, y, z``
(addresses of float64 arrays)."""

GroundTruth = tuple[float, float, float, float, float]
"""``(x, y, yaw, forward speed, yaw rate)``: m, m, rad, m/s, rad/s."""


@numba.njit(cache=True, nogil=True)
def ground_truth(qpos_address: int, qvel_address: int) -> GroundTruth:  # pragma: no cover
    """The ground truth of a free joint whose 7 positions (x, y, z, quaternion w, x, y, z) and
    6 velocities (linear in the world frame, angular in the body frame) start at these
    addresses (float64)."""
    qpos = numba.carray(pointer(qpos_address), (7,), np.float64)
    qvel = numba.carray(pointer(qvel_address), (6,), np.float64)
    r = np.empty(9)
    quat_to_mat(r.ctypes.data, qpos_address + 3 * 8)
    forward = r[0] * qvel[0] + r[3] * qvel[1] + r[6] * qvel[2]
    yaw_rate = r[6] * qvel[3] + r[7] * qvel[4] + r[8] * qvel[5]
    return qpos[0], qpos[1], math.atan2(r[3], r[0]), forward, yaw_rate


def ground_truth_reference(qpos: np.ndarray, qvel: np.ndarray) -> GroundTruth:
    """:func:`ground_truth` in Python, from the free joint's ``qpos`` (7) and ``qvel`` (6)."""
    rotation = np.empty(9)
    mujoco.mju_quat2Mat(rotation, qpos[3:7])
    r = rotation.tolist()
    x, y = float(qpos[0]), float(qpos[1])
    vx, vy, vz, wx, wy, wz = qvel.tolist()
    # Free joint: linear velocity in the world frame, angular velocity in the body frame.
    forward = r[0] * vx + r[3] * vy + r[6] * vz
    return x, y, math.atan2(r[3], r[0]), forward, r[6] * wx + r[7] * wy + r[8] * wz
