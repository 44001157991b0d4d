"""The compiled control step of Regulated Pure Pursuit (numba), bit for bit the Python it replaced.

One call of :func:`rpp_step` does a whole control cycle of
:class:`~baobab.nav.pure_pursuit.RegulatedPurePursuit`: prune and transform the plan, pick the
carrot, choose rotate-in-place or the regulated speed, clamp, and project the motion ahead for
collisions. The float operations are the ones the Python version did, in the same order, so
results are identical to the last bit. Three Python details are reproduced on purpose:

- :func:`python_hypot` is CPython's ``math.hypot`` (``vector_norm`` in
  ``Modules/mathmodule.c``), which rounds differently from the C library's ``hypot`` that
  numba and numpy call;
- ``x ** 2`` in Python calls the C library's ``pow``, which LLVM would turn into ``x * x``
  for a constant exponent (they differ in the last bit now and then), so the exponent comes
  in at run time from the settings array;
- ``numpy.sum`` adds pairwise with eight accumulators (:func:`pairwise_sum`).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from baobab.nav.costmap import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    MAX_NON_OBSTACLE,
    NO_INFORMATION,
)
from baobab.sim.float_semantics import pairwise_sum, py_max, py_min, python_hypot

OK = 0
"""A command was computed."""
NO_POSE_NEAR = 1
"""No path pose lies within the costmap's half extent of the robot."""
COLLISION_AHEAD = 2
"""The projected motion up to the carrot collides."""

# Indices into the settings array (:func:`baobab.nav.pure_pursuit.settings_array`).
DESIRED_LINEAR_VEL = 0
MAX_ANGULAR_VEL = 1
LOOKAHEAD_DIST = 2
MIN_LOOKAHEAD_DIST = 3
MAX_LOOKAHEAD_DIST = 4
LOOKAHEAD_TIME = 5
USE_VELOCITY_SCALED_LOOKAHEAD_DIST = 6
USE_INTERPOLATION = 7
USE_ROTATE_TO_HEADING = 8
ROTATE_TO_HEADING_MIN_ANGLE = 9
ROTATE_TO_HEADING_ANGULAR_VEL = 10
MAX_ANGULAR_ACCEL = 11
USE_REGULATED_LINEAR_VELOCITY_SCALING = 12
REGULATED_LINEAR_SCALING_MIN_RADIUS = 13
REGULATED_LINEAR_SCALING_MIN_SPEED = 14
USE_COST_REGULATED_LINEAR_VELOCITY_SCALING = 15
COST_SCALING_DIST = 16
COST_SCALING_GAIN = 17
INFLATION_COST_SCALING_FACTOR = 18
MIN_APPROACH_LINEAR_VELOCITY = 19
APPROACH_VELOCITY_SCALING_DIST = 20
USE_COLLISION_DETECTION = 21
MAX_ALLOWED_TIME_TO_COLLISION_UP_TO_CARROT = 22
GOAL_DIST_TOL = 23
CONTROLLER_FREQUENCY = 24
MAX_ROBOT_POSE_SEARCH_DIST = 25
"""NaN stands for "the costmap's half extent"."""
SQUARE_EXPONENT = 26
"""2.0, read at run time so that ``d ** 2`` stays a ``pow`` call."""
SETTINGS_SIZE = 27

# Indices into the output array of :func:`rpp_step`.
OUT_CLOSEST = 0
OUT_LINEAR = 1
OUT_ANGULAR = 2
OUT_CARROT_X = 3
OUT_CARROT_Y = 4
OUT_EXTENT = 5
OUT_SIZE = 6


@numba.njit(cache=True, nogil=True, inline="always")
def _clamp(value: float, low: float, high: float) -> float:  # pragma: no cover - compiled
    return py_min(py_max(value, low), high)


@numba.njit(cache=True, nogil=True)
def _cost(
    grid: np.ndarray, origin_x: float, origin_y: float, resolution: float, x: float, y: float
) -> int:  # pragma: no cover - compiled
    """``Costmap2D.cost(x, y)``: NO_INFORMATION off the grid."""
    ix = math.floor((x - origin_x) / resolution)
    iy = math.floor((y - origin_y) / resolution)
    if 0 <= ix < grid.shape[1] and 0 <= iy < grid.shape[0]:
        return int(grid[iy, ix])
    return NO_INFORMATION


@numba.njit(cache=True, nogil=True)
def _rotate_to(angle: float, angular_speed: float, s: np.ndarray) -> float:  # pragma: no cover
    """Angular speed (rad/s) of a rotation in place towards ``angle`` (rad)."""
    sign = 1.0 if angle > 0.0 else -1.0
    dt = 1.0 / s[CONTROLLER_FREQUENCY]
    angular = sign * s[ROTATE_TO_HEADING_ANGULAR_VEL]
    angular = _clamp(
        angular,
        angular_speed - s[MAX_ANGULAR_ACCEL] * dt,
        angular_speed + s[MAX_ANGULAR_ACCEL] * dt,
    )
    stop_speed = math.sqrt(2.0 * s[MAX_ANGULAR_ACCEL] * abs(angle))
    if abs(angular) > stop_speed:
        angular = sign * stop_speed
    return angular


@numba.njit(cache=True, nogil=True)
def rpp_step(
    poses: np.ndarray,
    along: np.ndarray,
    begin: int,
    x: float,
    y: float,
    yaw: float,
    linear_speed: float,
    angular_speed: float,
    grid: np.ndarray,
    origin_x: float,
    origin_y: float,
    resolution: float,
    inscribed_radius: float,
    s: np.ndarray,
    out: np.ndarray,
) -> int:  # pragma: no cover - compiled
    """One Regulated Pure Pursuit cycle.

    Args:
        poses: ``(N, 3)`` map-frame path poses (m, m, rad), N >= 1.
        along: ``(N,)`` cumulative path length (m) at each pose.
        begin: index of the pose found closest last cycle (the search starts there).
        x: robot map-frame x (m).
        y: robot map-frame y (m).
        yaw: robot heading (rad).
        linear_speed: robot forward speed (m/s).
        angular_speed: robot turn rate (rad/s).
        grid: the local costmap's ``uint8`` cells, ``[row, col]``.
        origin_x: the costmap's lower-left corner x (m).
        origin_y: the costmap's lower-left corner y (m).
        resolution: the costmap's cell side (m).
        inscribed_radius: the inflation's inscribed radius (m).
        s: the settings (indices above).
        out: receives closest index, command, map-frame carrot and half extent (``OUT_*``).

    Returns:
        :data:`OK`, :data:`NO_POSE_NEAR` or :data:`COLLISION_AHEAD`.
    """
    height, width = grid.shape
    extent = max(width, height) * resolution / 2
    out[OUT_EXTENT] = extent
    search_dist = s[MAX_ROBOT_POSE_SEARCH_DIST]
    if math.isnan(search_dist):
        search_dist = extent

    # 1. The closest pose (searched over search_dist of path) and the poses after it within
    # the extent, in the robot frame.
    n = poses.shape[0]
    limit = along[begin] + search_dist
    closest, best = begin, math.inf
    k = begin
    while k < n and (k == begin or along[k] <= limit):
        distance = math.hypot(poses[k, 0] - x, poses[k, 1] - y)
        if distance < best:
            closest, best = k, distance
        k += 1
    out[OUT_CLOSEST] = closest
    end = closest
    while end < n and math.hypot(poses[end, 0] - x, poses[end, 1] - y) <= extent:
        end += 1
    count = end - closest
    if count == 0:
        return NO_POSE_NEAR
    cos_yaw, sin_yaw = math.cos(yaw), math.sin(yaw)
    local = np.empty((count, 3))
    for i in range(count):
        dx, dy = poses[closest + i, 0] - x, poses[closest + i, 1] - y
        local[i, 0] = cos_yaw * dx + sin_yaw * dy
        local[i, 1] = -sin_yaw * dx + cos_yaw * dy
        local[i, 2] = (poses[closest + i, 2] - yaw + math.pi) % (2 * math.pi) - math.pi
    last = count - 1

    # 2. The carrot at the lookahead distance.
    if s[USE_VELOCITY_SCALED_LOOKAHEAD_DIST] != 0.0:
        lookahead = _clamp(
            abs(linear_speed) * s[LOOKAHEAD_TIME], s[MIN_LOOKAHEAD_DIST], s[MAX_LOOKAHEAD_DIST]
        )
    else:
        lookahead = s[LOOKAHEAD_DIST]
    index = -1
    for i in range(count):
        if math.hypot(local[i, 0], local[i, 1]) >= lookahead:
            index = i
            break
    if index < 0:
        carrot_x, carrot_y = local[last, 0], local[last, 1]
    elif index == 0 or s[USE_INTERPOLATION] == 0.0:
        carrot_x, carrot_y = local[index, 0], local[index, 1]
    else:
        x1, y1 = local[index - 1, 0], local[index - 1, 1]
        x2, y2 = local[index, 0], local[index, 1]
        dx, dy = x2 - x1, y2 - y1
        dr2 = dx * dx + dy * dy
        cross = x1 * y2 - x2 * y1
        root = math.sqrt(py_max(lookahead * lookahead * dr2 - cross * cross, 0.0))
        sign = math.copysign(1.0, (x2 * x2 + y2 * y2) - (x1 * x1 + y1 * y1))
        carrot_x = (cross * dy + sign * dx * root) / dr2
        carrot_y = (-cross * dx + sign * dy * root) / dr2
    out[OUT_CARROT_X] = x + cos_yaw * carrot_x - sin_yaw * carrot_y
    out[OUT_CARROT_Y] = y + sin_yaw * carrot_x + cos_yaw * carrot_y
    carrot_dist = python_hypot(carrot_x, carrot_y)
    angle_to_path = math.atan2(carrot_y, carrot_x)

    # 3. Rotate in place or drive at the regulated speed.
    rotate = s[USE_ROTATE_TO_HEADING] != 0.0
    if rotate and carrot_dist < s[GOAL_DIST_TOL]:
        linear, angular = 0.0, _rotate_to(local[last, 2], angular_speed, s)
    elif rotate and abs(angle_to_path) > s[ROTATE_TO_HEADING_MIN_ANGLE]:
        linear, angular = 0.0, _rotate_to(angle_to_path, angular_speed, s)
    else:
        square = carrot_dist ** s[SQUARE_EXPONENT]
        curvature = 2.0 * carrot_y / square if square > 0.001 else 0.0
        speed = s[DESIRED_LINEAR_VEL]
        curvature_speed, cost_speed = speed, speed
        if s[USE_REGULATED_LINEAR_VELOCITY_SCALING] != 0.0 and curvature != 0.0:
            radius = abs(1.0 / curvature)
            if radius < s[REGULATED_LINEAR_SCALING_MIN_RADIUS]:
                curvature_speed = speed * radius / s[REGULATED_LINEAR_SCALING_MIN_RADIUS]
        pose_cost = _cost(grid, origin_x, origin_y, resolution, x, y)
        if s[USE_COST_REGULATED_LINEAR_VELOCITY_SCALING] != 0.0 and pose_cost not in (
            NO_INFORMATION,
            FREE_SPACE,
        ):
            # Invert the inflation formula: the distance to the nearest obstacle.
            distance = (-1.0 / s[INFLATION_COST_SCALING_FACTOR]) * math.log(
                pose_cost / MAX_NON_OBSTACLE
            ) + inscribed_radius
            if distance < s[COST_SCALING_DIST]:
                cost_speed = speed * s[COST_SCALING_GAIN] * distance / s[COST_SCALING_DIST]
        speed = py_max(py_min(curvature_speed, cost_speed), s[REGULATED_LINEAR_SCALING_MIN_SPEED])
        # Approach: once the remaining path is short, scale with the distance to its end.
        steps = np.empty(last)
        for i in range(last):
            steps[i] = math.hypot(local[i + 1, 0] - local[i, 0], local[i + 1, 1] - local[i, 1])
        remaining = pairwise_sum(steps, 0, last) if last > 0 else 0.0
        if remaining < s[APPROACH_VELOCITY_SCALING_DIST]:
            scaling = (
                python_hypot(local[last, 0], local[last, 1]) / s[APPROACH_VELOCITY_SCALING_DIST]
            )
            speed = py_min(speed, py_max(speed * scaling, s[MIN_APPROACH_LINEAR_VELOCITY]))
        linear = _clamp(speed, 0.0, s[DESIRED_LINEAR_VEL])
        angular = linear * curvature
    angular = _clamp(angular, -s[MAX_ANGULAR_VEL], s[MAX_ANGULAR_VEL])
    out[OUT_LINEAR] = linear
    out[OUT_ANGULAR] = angular

    # 4. Nav2's projection: step the command ahead until the carrot or the time limit.
    if s[USE_COLLISION_DETECTION] == 0.0:
        return OK
    cost = _cost(grid, origin_x, origin_y, resolution, x, y)
    if cost != NO_INFORMATION and cost >= INSCRIBED_INFLATED_OBSTACLE:
        return COLLISION_AHEAD
    if abs(linear) < 0.01:
        # A circular robot turning in place sweeps no new cells.
        return OK
    dt = resolution / abs(linear)
    px, py, pyaw = x, y, yaw
    i = 1
    while i * dt < s[MAX_ALLOWED_TIME_TO_COLLISION_UP_TO_CARROT]:
        i += 1
        px += dt * linear * math.cos(pyaw)
        py += dt * linear * math.sin(pyaw)
        pyaw += dt * angular
        if python_hypot(px - x, py - y) > carrot_dist:
            break
        cost = _cost(grid, origin_x, origin_y, resolution, px, py)
        if cost != NO_INFORMATION and cost >= INSCRIBED_INFLATED_OBSTACLE:
            return COLLISION_AHEAD
    return OK
