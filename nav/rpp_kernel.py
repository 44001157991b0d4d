"""The compiled control step of Regulated Pure Pursuit (numba).

One call of :func:`rpp_step` does a whole control cycle of
:class:`~baobab.nav.pure_pursuit.RegulatedPurePursuit`: prune and transform the plan, pick the
carrot, choose rotate-in-place or the regulated speed, clamp, and project the motion ahead for
collisions. Compiled because the cycle walks the plan pose by pose and steps the projected
motion cell by cell: in Python that was hundreds of small float operations, the controller's
largest cost per cycle. The tests compare it with a plain Python controller
(``tests/test_rpp_kernel.py``), which does the same float operations and so gives the same bits.

The kernel reads three records (:mod:`baobab.sim.records`): the settings
(:data:`RPP_SETTINGS`, from :meth:`~baobab.nav.pure_pursuit.RegulatedPurePursuitParams.pack`),
the local costmap's geometry (:data:`~baobab.nav.costmap.GRID`) and the cycle's robot state
and results (:data:`CYCLE`).
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
from baobab.sim.records import Record

OK = 0
"""A command was computed."""
NO_POSE_NEAR = 1
"""No path pose lies within the costmap's half extent of the robot."""
COLLISION_AHEAD = 2
"""The projected motion up to the carrot collides."""

RPP_SETTINGS = np.dtype(
    [
        ("desired_linear_vel", np.float64),  # m/s
        ("max_angular_vel", np.float64),  # rad/s
        ("lookahead_dist", np.float64),  # m
        ("min_lookahead_dist", np.float64),  # m
        ("max_lookahead_dist", np.float64),  # m
        ("lookahead_time", np.float64),  # s
        ("use_velocity_scaled_lookahead_dist", np.bool_),
        ("use_interpolation", np.bool_),
        ("use_rotate_to_heading", np.bool_),
        ("rotate_to_heading_min_angle", np.float64),  # rad
        ("rotate_to_heading_angular_vel", np.float64),  # rad/s
        ("max_angular_accel", np.float64),  # rad/s^2
        ("use_regulated_linear_velocity_scaling", np.bool_),
        ("regulated_linear_scaling_min_radius", np.float64),  # m
        ("regulated_linear_scaling_min_speed", np.float64),  # m/s
        ("use_cost_regulated_linear_velocity_scaling", np.bool_),
        ("cost_scaling_dist", np.float64),  # m
        ("cost_scaling_gain", np.float64),
        ("inflation_cost_scaling_factor", np.float64),  # 1/m
        ("min_approach_linear_velocity", np.float64),  # m/s
        ("approach_velocity_scaling_dist", np.float64),  # m
        ("use_collision_detection", np.bool_),
        ("max_allowed_time_to_collision_up_to_carrot", np.float64),  # s
        ("goal_dist_tol", np.float64),  # m
        ("controller_frequency", np.float64),  # Hz
        ("max_robot_pose_search_dist", np.float64),  # m; NaN: the costmap's half extent
    ],
    align=True,
)
"""The controller's settings, one field per
:class:`~baobab.nav.pure_pursuit.RegulatedPurePursuitParams` field of the same name."""

CYCLE = np.dtype(
    [
        # In: where the search for the closest pose starts, and the robot's state.
        ("begin", np.int64),  # index of the pose found closest last cycle
        ("x", np.float64),  # map frame (m)
        ("y", np.float64),  # m
        ("yaw", np.float64),  # rad
        ("linear_speed", np.float64),  # m/s
        ("angular_speed", np.float64),  # rad/s
        # Out.
        ("closest", np.int64),  # index of the pose closest to the robot
        ("linear", np.float64),  # the command (m/s)
        ("angular", np.float64),  # rad/s
        ("carrot_x", np.float64),  # the carrot, map frame (m)
        ("carrot_y", np.float64),  # m
        ("extent", np.float64),  # the costmap's half extent (m)
    ],
    align=True,
)
"""One control cycle's robot state (written by the caller) and results (written by
:func:`rpp_step`)."""


@numba.njit(cache=True, nogil=True, inline="always")
def _clamp(value: float, low: float, high: float) -> float:  # pragma: no cover - compiled
    return min(max(value, low), high)


@numba.njit(cache=True, nogil=True)
def _cost(cells: np.ndarray, grid: Record, x: float, y: float) -> int:  # pragma: no cover
    """``Costmap2D.cost(x, y)``: NO_INFORMATION off the grid."""
    ix = math.floor((x - grid.origin_x) / grid.resolution)
    iy = math.floor((y - grid.origin_y) / grid.resolution)
    if 0 <= ix < cells.shape[1] and 0 <= iy < cells.shape[0]:
        return int(cells[iy, ix])
    return NO_INFORMATION


@numba.njit(cache=True, nogil=True)
def _rotate_to(angle: float, angular_speed: float, s: Record) -> float:  # pragma: no cover
    """Angular speed (rad/s) of a rotation in place towards ``angle`` (rad)."""
    sign = 1.0 if angle > 0.0 else -1.0
    dt = 1.0 / s.controller_frequency
    angular = _clamp(
        sign * s.rotate_to_heading_angular_vel,
        angular_speed - s.max_angular_accel * dt,
        angular_speed + s.max_angular_accel * dt,
    )
    stop_speed = math.sqrt(2.0 * s.max_angular_accel * abs(angle))
    if abs(angular) > stop_speed:
        angular = sign * stop_speed
    return angular


@numba.njit(cache=True, nogil=True)
def _local_plan(
    poses: np.ndarray, along: np.ndarray, search_dist: float, c: Record
) -> np.ndarray:  # pragma: no cover - compiled
    """The closest pose (searched over ``search_dist`` m of path from ``c.begin``, written to
    ``c.closest``) and the poses after it within ``c.extent``, in the robot frame (N, 3)."""
    x, y, yaw = c.x, c.y, c.yaw
    n = poses.shape[0]
    begin = c.begin
    limit = along[begin] + search_dist
    closest, best = begin, math.inf
    k = begin
    while k < n and (k == begin or along[k] <= limit):
        distance = math.hypot(poses[k, 0] - x, poses[k, 1] - y)
        if distance < best:
            closest, best = k, distance
        k += 1
    c.closest = closest
    end = closest
    while end < n and math.hypot(poses[end, 0] - x, poses[end, 1] - y) <= c.extent:
        end += 1
    cos_yaw, sin_yaw = math.cos(yaw), math.sin(yaw)
    local = np.empty((end - closest, 3))
    for i in range(end - closest):
        dx, dy = poses[closest + i, 0] - x, poses[closest + i, 1] - y
        local[i, 0] = cos_yaw * dx + sin_yaw * dy
        local[i, 1] = -sin_yaw * dx + cos_yaw * dy
        local[i, 2] = (poses[closest + i, 2] - yaw + math.pi) % (2 * math.pi) - math.pi
    return local


@numba.njit(cache=True, nogil=True)
def _carrot(
    local: np.ndarray, lookahead: float, s: Record
) -> tuple[float, float]:  # pragma: no cover - compiled
    """The robot-frame point at ``lookahead`` (m) along the local plan, interpolated on the
    segment that crosses the lookahead circle; the plan's end if it is all nearer."""
    last = local.shape[0] - 1
    index = -1
    for i in range(last + 1):
        if math.hypot(local[i, 0], local[i, 1]) >= lookahead:
            index = i
            break
    if index < 0:
        return local[last, 0], local[last, 1]
    if index == 0 or not s.use_interpolation:
        return local[index, 0], local[index, 1]
    x1, y1 = local[index - 1, 0], local[index - 1, 1]
    x2, y2 = local[index, 0], local[index, 1]
    dx, dy = x2 - x1, y2 - y1
    dr2 = dx * dx + dy * dy
    cross = x1 * y2 - x2 * y1
    root = math.sqrt(max(lookahead * lookahead * dr2 - cross * cross, 0.0))
    sign = math.copysign(1.0, (x2 * x2 + y2 * y2) - (x1 * x1 + y1 * y1))
    return (cross * dy + sign * dx * root) / dr2, (-cross * dx + sign * dy * root) / dr2


@numba.njit(cache=True, nogil=True)
def _regulated_speed(
    curvature: float, pose_cost: int, local: np.ndarray, grid: Record, s: Record
) -> float:  # pragma: no cover - compiled
    """``desired_linear_vel`` (m/s) slowed by the curvature, by the cost under the robot turned
    back into an obstacle distance, and on the approach to the plan's end."""
    speed = s.desired_linear_vel
    curvature_speed, cost_speed = speed, speed
    if s.use_regulated_linear_velocity_scaling and curvature != 0.0:
        radius = abs(1.0 / curvature)
        if radius < s.regulated_linear_scaling_min_radius:
            curvature_speed = speed * radius / s.regulated_linear_scaling_min_radius
    if s.use_cost_regulated_linear_velocity_scaling and pose_cost not in (
        NO_INFORMATION,
        FREE_SPACE,
    ):
        # Invert the inflation formula: the distance to the nearest obstacle.
        distance = (-1.0 / s.inflation_cost_scaling_factor) * math.log(
            pose_cost / MAX_NON_OBSTACLE
        ) + grid.inscribed_radius
        if distance < s.cost_scaling_dist:
            cost_speed = speed * s.cost_scaling_gain * distance / s.cost_scaling_dist
    speed = max(min(curvature_speed, cost_speed), s.regulated_linear_scaling_min_speed)
    last = local.shape[0] - 1
    remaining = 0.0
    for i in range(last):
        remaining += math.hypot(local[i + 1, 0] - local[i, 0], local[i + 1, 1] - local[i, 1])
    if remaining < s.approach_velocity_scaling_dist:
        scaling = math.hypot(local[last, 0], local[last, 1]) / s.approach_velocity_scaling_dist
        speed = min(speed, max(speed * scaling, s.min_approach_linear_velocity))
    return _clamp(speed, 0.0, s.desired_linear_vel)


@numba.njit(cache=True, nogil=True)
def _collision_ahead(
    cells: np.ndarray, grid: Record, carrot_dist: float, s: Record, c: Record
) -> bool:  # pragma: no cover - compiled
    """Nav2's projection: step the command ahead until the carrot or the time limit."""
    cost = _cost(cells, grid, c.x, c.y)
    if cost != NO_INFORMATION and cost >= INSCRIBED_INFLATED_OBSTACLE:
        return True
    linear, angular = c.linear, c.angular
    if abs(linear) < 0.01:
        # A circular robot turning in place sweeps no new cells.
        return False
    dt = grid.resolution / abs(linear)
    px, py, pyaw = c.x, c.y, c.yaw
    i = 1
    while i * dt < s.max_allowed_time_to_collision_up_to_carrot:
        i += 1
        px += dt * linear * math.cos(pyaw)
        py += dt * linear * math.sin(pyaw)
        pyaw += dt * angular
        if math.hypot(px - c.x, py - c.y) > carrot_dist:
            break
        cost = _cost(cells, grid, px, py)
        if cost != NO_INFORMATION and cost >= INSCRIBED_INFLATED_OBSTACLE:
            return True
    return False


@numba.njit(cache=True, nogil=True)
def rpp_step(
    poses: np.ndarray,
    along: np.ndarray,
    cells: np.ndarray,
    grid: np.ndarray,
    settings: np.ndarray,
    cycle: np.ndarray,
) -> int:  # pragma: no cover - compiled
    """One Regulated Pure Pursuit cycle.

    Args:
        poses: ``(N, 3)`` map-frame path poses (m, m, rad), N >= 1.
        along: ``(N,)`` cumulative path length (m) at each pose.
        cells: the local costmap's ``uint8`` cells, ``[row, col]``.
        grid: the local costmap's :data:`~baobab.nav.costmap.GRID` record.
        settings: an :data:`RPP_SETTINGS` record.
        cycle: a :data:`CYCLE` record: reads the robot state, writes the results.

    Returns:
        :data:`OK`, :data:`NO_POSE_NEAR` or :data:`COLLISION_AHEAD`.
    """
    g, s, c = grid[0], settings[0], cycle[0]
    c.extent = max(cells.shape[0], cells.shape[1]) * g.resolution / 2
    search_dist = s.max_robot_pose_search_dist
    if math.isnan(search_dist):
        search_dist = c.extent
    local = _local_plan(poses, along, search_dist, c)
    if local.shape[0] == 0:
        return NO_POSE_NEAR
    last = local.shape[0] - 1

    if s.use_velocity_scaled_lookahead_dist:
        lookahead = _clamp(
            abs(c.linear_speed) * s.lookahead_time, s.min_lookahead_dist, s.max_lookahead_dist
        )
    else:
        lookahead = s.lookahead_dist
    carrot_x, carrot_y = _carrot(local, lookahead, s)
    cos_yaw, sin_yaw = math.cos(c.yaw), math.sin(c.yaw)
    c.carrot_x = c.x + cos_yaw * carrot_x - sin_yaw * carrot_y
    c.carrot_y = c.y + sin_yaw * carrot_x + cos_yaw * carrot_y
    carrot_dist = math.hypot(carrot_x, carrot_y)
    angle_to_path = math.atan2(carrot_y, carrot_x)

    # Rotate in place or drive at the regulated speed.
    if s.use_rotate_to_heading and carrot_dist < s.goal_dist_tol:
        linear, angular = 0.0, _rotate_to(local[last, 2], c.angular_speed, s)
    elif s.use_rotate_to_heading and abs(angle_to_path) > s.rotate_to_heading_min_angle:
        linear, angular = 0.0, _rotate_to(angle_to_path, c.angular_speed, s)
    else:
        square = carrot_dist * carrot_dist
        curvature = 2.0 * carrot_y / square if square > 0.001 else 0.0
        linear = _regulated_speed(curvature, _cost(cells, g, c.x, c.y), local, g, s)
        angular = linear * curvature
    c.linear = linear
    c.angular = _clamp(angular, -s.max_angular_vel, s.max_angular_vel)
    if s.use_collision_detection and _collision_ahead(cells, g, carrot_dist, s, c):
        return COLLISION_AHEAD
    return OK
