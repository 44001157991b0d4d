"""Nav2's tracking errors, compiled: how far the robot sits off its path, every control cycle.

:func:`track` is :func:`baobab.nav.feedback.path_tracking` (the reference it is tested against,
``tests/test_tracking_kernel.py``, bit for bit) as a numba function, so that the controller's
compiled cycle (:func:`baobab.nav.rpp_kernel.rpp_step`) returns the errors with the command
instead of Python walking the segments around the closest pose on every cycle.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(cache=True, nogil=True)
def track(
    poses: np.ndarray, closest: int, x: float, y: float, yaw: float
) -> tuple[float, float, int]:  # pragma: no cover - compiled
    """The tracking errors of the robot at ``(x, y, yaw)`` (m, rad) against the ``(N, 3)``
    path ``poses``, pose ``closest`` being the one nearest to the robot.

    Returns:
        ``(position_error, heading_error, index)`` as
        :class:`~baobab.nav.feedback.PathTracking` has them (m, rad, segment index).
    """
    count = poses.shape[0]
    if count == 0:
        return 0.0, 0.0, 0
    closest = min(max(closest, 0), count - 1)
    first = max(closest - 1, 0)
    found = False
    best_gap, best_cross, best_start, best_dx, best_dy = 0.0, 0.0, 0, 0.0, 0.0
    for start in range(first, min(closest, count - 2) + 1):
        ax, ay = poses[start, 0], poses[start, 1]
        dx, dy = poses[start + 1, 0] - ax, poses[start + 1, 1] - ay
        length = math.hypot(dx, dy)
        if length < 1e-9:
            continue
        along = min(max(((x - ax) * dx + (y - ay) * dy) / length, 0.0), length)
        gap = math.hypot(x - (ax + dx * along / length), y - (ay + dy * along / length))
        if not found or gap < best_gap:
            found = True
            best_gap = gap
            best_cross = (dx * (y - ay) - dy * (x - ax)) / length
            best_start, best_dx, best_dy = start, dx, dy
    if not found:
        ax, ay, heading = poses[closest, 0], poses[closest, 1], poses[closest, 2]
        cross = math.cos(heading) * (y - ay) - math.sin(heading) * (x - ax)
        return cross, _wrap(heading - yaw), closest
    return best_cross, _wrap(math.atan2(best_dy, best_dx) - yaw), best_start


@numba.njit(cache=True, nogil=True, inline="always")
def _wrap(angle: float) -> float:  # pragma: no cover - compiled
    """:func:`baobab.nav.path.wrap_angle`: ``angle`` (rad) wrapped to ``[-pi, pi)``."""
    return (angle + math.pi) % (2 * math.pi) - math.pi
