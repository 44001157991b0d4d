"""Quaternion algebra for the 1 kHz loop and per-tick queries, compiled with numba.

scipy's ``Rotation`` is the project's quaternion library, but one of its single-rotation
operations costs 35-250 us here (scipy 1.17), and it cannot run inside a numba kernel. The few
operations the control loop and the pose queries need are therefore written out here, each
following a reference implementation so that results agree to the last bits:

- :func:`rotation_to_quaternion`, :func:`multiply_by_conjugate`, :func:`slerp_towards`:
  Eigen's formulas, which ``pinocchio.Quaternion`` runs;
- :func:`matrix_to_quaternion`: scipy's ``Rotation.from_matrix`` (same sign convention).

Quaternions are x, y, z, w. The tests check every function against scipy.
"""

from __future__ import annotations

import math

import numba
import numpy as np

_ONE_MINUS_EPSILON = 1.0 - np.finfo(np.float64).eps


@numba.njit(cache=True, nogil=True, error_model="numpy")
def rotation_to_quaternion(rotation: np.ndarray, out: np.ndarray) -> None:  # pragma: no cover
    """Write the unit quaternion x, y, z, w of a 3x3 rotation matrix into ``out`` (4,).

    Eigen's branch on the trace (Shepperd's method), so the result matches
    ``pinocchio.Quaternion(rotation)`` to the last bits.
    """
    trace = rotation[0, 0] + rotation[1, 1] + rotation[2, 2]
    if trace > 0.0:
        t = math.sqrt(trace + 1.0)
        out[3] = 0.5 * t
        t = 0.5 / t
        out[0] = (rotation[2, 1] - rotation[1, 2]) * t
        out[1] = (rotation[0, 2] - rotation[2, 0]) * t
        out[2] = (rotation[1, 0] - rotation[0, 1]) * t
        return
    i = 0
    if rotation[1, 1] > rotation[0, 0]:
        i = 1
    if rotation[2, 2] > rotation[i, i]:
        i = 2
    j = (i + 1) % 3
    k = (j + 1) % 3
    t = math.sqrt(rotation[i, i] - rotation[j, j] - rotation[k, k] + 1.0)
    out[i] = 0.5 * t
    t = 0.5 / t
    out[3] = (rotation[k, j] - rotation[j, k]) * t
    out[j] = (rotation[j, i] + rotation[i, j]) * t
    out[k] = (rotation[k, i] + rotation[i, k]) * t


@numba.njit(cache=True, nogil=True, inline="always")
def multiply_by_conjugate(
    a: np.ndarray, b: np.ndarray, out: np.ndarray
) -> None:  # pragma: no cover - compiled
    """out = a * conj(b), quaternions x, y, z, w (Hamilton product)."""
    ax, ay, az, aw = a[0], a[1], a[2], a[3]
    bx, by, bz, bw = -b[0], -b[1], -b[2], b[3]
    out[0] = aw * bx + ax * bw + ay * bz - az * by
    out[1] = aw * by + ay * bw + az * bx - ax * bz
    out[2] = aw * bz + az * bw + ax * by - ay * bx
    out[3] = aw * bw - ax * bx - ay * by - az * bz


@numba.njit(cache=True, nogil=True, error_model="numpy")
def slerp_towards(quaternion: np.ndarray, goal: np.ndarray, t: float) -> None:  # pragma: no cover
    """Replace ``quaternion`` (x, y, z, w) by the slerp a share ``t`` of the way to ``goal``.

    Eigen's ``QuaternionBase::slerp``: the short way round, linear blending (not renormalised)
    when the two are within machine precision of each other.
    """
    d = (
        quaternion[0] * goal[0]
        + quaternion[1] * goal[1]
        + quaternion[2] * goal[2]
        + quaternion[3] * goal[3]
    )
    abs_d = abs(d)
    if abs_d >= _ONE_MINUS_EPSILON:
        scale0 = 1.0 - t
        scale1 = t
    else:
        theta = math.acos(abs_d)
        sin_theta = math.sin(theta)
        scale0 = math.sin((1.0 - t) * theta) / sin_theta
        scale1 = math.sin(t * theta) / sin_theta
    if d < 0.0:
        scale1 = -scale1
    for c in range(4):
        quaternion[c] = scale0 * quaternion[c] + scale1 * goal[c]


@numba.njit(cache=True, nogil=True, error_model="numpy")
def matrix_to_quaternion(rotation: np.ndarray, out: np.ndarray) -> None:  # pragma: no cover
    """Write the unit quaternion of a 3x3 rotation matrix into ``out`` (4,), as scipy does.

    scipy's ``Rotation.from_matrix`` for an orthogonal matrix: the largest of |x|, |y|, |z|,
    |w| is computed first and comes out positive.
    """
    trace = rotation[0, 0] + rotation[1, 1] + rotation[2, 2]
    choice = 0
    largest = rotation[0, 0]
    for candidate, value in ((1, rotation[1, 1]), (2, rotation[2, 2]), (3, trace)):
        if value > largest:
            choice, largest = candidate, value
    if choice == 3:
        out[0] = rotation[2, 1] - rotation[1, 2]
        out[1] = rotation[0, 2] - rotation[2, 0]
        out[2] = rotation[1, 0] - rotation[0, 1]
        out[3] = 1.0 + trace
    else:
        i = choice
        j = (i + 1) % 3
        k = (j + 1) % 3
        out[i] = 1.0 - trace + 2.0 * rotation[i, i]
        out[j] = rotation[j, i] + rotation[i, j]
        out[k] = rotation[k, i] + rotation[i, k]
        out[3] = rotation[k, j] - rotation[j, k]
    norm = math.sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3])
    for c in range(4):
        out[c] /= norm


@numba.njit(cache=True, nogil=True, error_model="numpy")
def transform_pose(
    frame_rotation: np.ndarray,
    frame_position: np.ndarray,
    position: np.ndarray,
    rotation: np.ndarray,
    out: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """Express a pose given in a frame in that frame's parent, into ``out`` (7,).

    ``out[:3]`` = ``frame_rotation @ position + frame_position`` and ``out[3:]`` = the
    quaternion x, y, z, w of ``frame_rotation @ rotation`` (:func:`matrix_to_quaternion`).
    """
    composed = np.empty((3, 3))
    for r in range(3):
        value = frame_position[r]
        for k in range(3):
            value += frame_rotation[r, k] * position[k]
        out[r] = value
        for c in range(3):
            total = 0.0
            for k in range(3):
                total += frame_rotation[r, k] * rotation[k, c]
            composed[r, c] = total
    matrix_to_quaternion(composed, out[3:])
