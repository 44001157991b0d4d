"""The compiled control step of Regulated Pure Pursuit (numba).

One call of :func:`rpp_step` does a whole control cycle of
:class:`~baobab.nav.pure_pursuit.RegulatedPurePursuit`: prune and transform the plan, pick the
carrot, choose rotate-in-place or the regulated speed, clamp, and project the motion ahead for
collisions; and it measures the controller server's tracking errors against the pose it found
closest (:mod:`baobab.nav.tracking_kernel`). Compiled because the cycle walks the plan pose by
pose and steps the projected motion cell by cell: in Python that was hundreds of small float
operations, the controller's largest cost per cycle. The tests compare it with a plain Python
controller (``tests/test_rpp_kernel.py``), which does the same float operations and so gives
the same bits.

The kernel reads two records (:mod:`baobab.sim.records`): the settings (:data:`RPP_SETTINGS`,
from :meth:`~baobab.nav.pure_pursuit.RegulatedPurePursuitParams.pack`) and the local costmap's
geometry (:data:`~baobab.nav.costmap.GRID`, in :class:`~baobab.nav.costmap.CostmapArrays` with
the cells and the footprint's outline); it returns a :class:`PursuitStep`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from baobab.nav.costmap import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    MAX_NON_OBSTACLE,
    NO_INFORMATION,
    CostmapArrays,
)
from baobab.nav.footprint_kernel import footprint_collides
from baobab.nav.tracking_kernel import track
from baobab.sim.records import Record

OK = 0
"""A command was computed."""
NO_POSE_NEAR = 1
"""No path pose lies within the costmap's half extent of the robot."""
COLLISION_AHEAD = 2
"""The projected motion up to the carrot collides."""

Pose = tuple[float, float, float]
"""A map-frame pose ``(x, y, yaw)`` (m, m, rad)."""

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


class PursuitStep(NamedTuple):
    """What one :func:`rpp_step` found."""

    status: int
    """:data:`OK`, :data:`NO_POSE_NEAR` or :data:`COLLISION_AHEAD`."""
    closest: int
    """Index of the path pose closest to the robot."""
    linear: float
    """The command (m/s); 0 unless ``status`` is :data:`OK` or :data:`COLLISION_AHEAD`."""
    angular: float
    """rad/s."""
    carrot_x: float
    """The carrot, map frame (m)."""
    carrot_y: float
    """m."""
    extent: float
    """The costmap's half extent (m)."""
    position_error: float
    """Nav2's tracking errors against the path near ``closest``
    (:func:`~baobab.nav.tracking_kernel.track`): the signed distance (m) off the path..."""
    heading_error: float
    """... the path's direction minus the robot's heading (rad) ..."""
    tracking_index: int
    """... and the index of the path segment they refer to."""


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
    poses: np.ndarray, along: np.ndarray, begin: int, pose: Pose, search_dist: float, extent: float
) -> tuple[int, np.ndarray]:  # pragma: no cover - compiled
    """The pose closest to ``pose`` (searched over ``search_dist`` m of path from ``begin``) and
    the poses after it within ``extent`` (m), in the robot frame (N, 3)."""
    x, y, yaw = pose
    n = poses.shape[0]
    limit = along[begin] + search_dist
    closest, best = begin, math.inf
    k = begin
    while k < n and (k == begin or along[k] <= limit):
        distance = math.hypot(poses[k, 0] - x, poses[k, 1] - y)
        if distance < best:
            closest, best = k, distance
        k += 1
    end = closest
    while end < n and math.hypot(poses[end, 0] - x, poses[end, 1] - y) <= extent:
        end += 1
    cos_yaw, sin_yaw = math.cos(yaw), math.sin(yaw)
    local = np.empty((end - closest, 3))
    for i in range(end - closest):
        dx, dy = poses[closest + i, 0] - x, poses[closest + i, 1] - y
        local[i, 0] = cos_yaw * dx + sin_yaw * dy
        local[i, 1] = -sin_yaw * dx + cos_yaw * dy
        local[i, 2] = (poses[closest + i, 2] - yaw + math.pi) % (2 * math.pi) - math.pi
    return closest, local


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
def _in_collision(
    cells: np.ndarray, grid: Record, outline: np.ndarray, x: float, y: float, yaw: float
) -> bool:  # pragma: no cover - compiled
    """Nav2's ``inCollision``: a circular robot's centre on an inscribed cell, a polygon's
    outline on a lethal one (unknown space is free, as off the grid)."""
    if outline.shape[0] > 0:
        return footprint_collides(cells, grid, outline, x, y, yaw, False)
    cost = _cost(cells, grid, x, y)
    return cost != NO_INFORMATION and cost >= INSCRIBED_INFLATED_OBSTACLE


@numba.njit(cache=True, nogil=True)
def _collision_ahead(
    cells: np.ndarray,
    grid: Record,
    outline: np.ndarray,
    pose: Pose,
    command: tuple[float, float],
    reach: float,
    s: Record,
) -> bool:  # pragma: no cover - compiled
    """Nav2's projection: step ``command`` (m/s, rad/s) ahead from ``pose`` until it is
    ``reach`` (m, the carrot's distance) away or the time limit passes.

    A step moves the robot one cell; turning in place, a polygon's farthest vertex one cell
    (``2 sin(res / 2 / r_max) / w``, Nav2's step).
    """
    x, y, yaw = pose
    if _in_collision(cells, grid, outline, x, y, yaw):
        return True
    linear, angular = command
    if abs(linear) < 0.01:
        if outline.shape[0] == 0 or abs(angular) <= 0.01:
            # A circular robot turning in place sweeps no new cells.
            return False
        farthest = 0.0
        for k in range(outline.shape[0]):
            farthest = max(farthest, math.hypot(outline[k, 0], outline[k, 1]))
        dt = 2.0 * math.sin(grid.resolution / 2 / farthest) / abs(angular)
    else:
        dt = grid.resolution / abs(linear)
    px, py, pyaw = x, y, yaw
    i = 1
    while i * dt < s.max_allowed_time_to_collision_up_to_carrot:
        i += 1
        px += dt * linear * math.cos(pyaw)
        py += dt * linear * math.sin(pyaw)
        pyaw += dt * angular
        if math.hypot(px - x, py - y) > reach:
            break
        if _in_collision(cells, grid, outline, px, py, pyaw):
            return True
    return False


@numba.njit(cache=True, nogil=True)
def rpp_step(
    poses: np.ndarray,
    along: np.ndarray,
    begin: int,
    pose: Pose,
    velocity: tuple[float, float],
    costmap: CostmapArrays,
    settings: np.ndarray,
) -> PursuitStep:  # pragma: no cover - compiled
    """One Regulated Pure Pursuit cycle.

    Args:
        poses: ``(N, 3)`` map-frame path poses (m, m, rad), N >= 1.
        along: ``(N,)`` cumulative path length (m) at each pose.
        begin: index of the pose found closest last cycle (the search starts there).
        pose: the robot's map-frame pose ``(x, y, yaw)`` (m, m, rad).
        velocity: the robot's ``(linear, angular)`` speed (m/s, rad/s).
        costmap: the local costmap's cells, geometry and footprint outline.
        settings: an :data:`RPP_SETTINGS` record.
    """
    cells, outline = costmap.cells, costmap.outline
    g, s = costmap.grid[0], settings[0]
    x, y, yaw = pose
    extent = max(cells.shape[0], cells.shape[1]) * g.resolution / 2
    search_dist = s.max_robot_pose_search_dist
    if math.isnan(search_dist):
        search_dist = extent
    closest, local = _local_plan(poses, along, begin, pose, search_dist, extent)
    off_path, off_heading, segment = track(poses, closest, x, y, yaw)
    if local.shape[0] == 0:
        nan = math.nan
        return PursuitStep(
            NO_POSE_NEAR, closest, 0.0, 0.0, nan, nan, extent, off_path, off_heading, segment
        )
    last = local.shape[0] - 1

    if s.use_velocity_scaled_lookahead_dist:
        lookahead = _clamp(
            abs(velocity[0]) * s.lookahead_time, s.min_lookahead_dist, s.max_lookahead_dist
        )
    else:
        lookahead = s.lookahead_dist
    carrot_x, carrot_y = _carrot(local, lookahead, s)
    cos_yaw, sin_yaw = math.cos(yaw), math.sin(yaw)
    map_x = x + cos_yaw * carrot_x - sin_yaw * carrot_y
    map_y = y + sin_yaw * carrot_x + cos_yaw * carrot_y
    carrot_dist = math.hypot(carrot_x, carrot_y)
    angle_to_path = math.atan2(carrot_y, carrot_x)

    # Rotate in place or drive at the regulated speed.
    if s.use_rotate_to_heading and carrot_dist < s.goal_dist_tol:
        linear, angular = 0.0, _rotate_to(local[last, 2], velocity[1], s)
    elif s.use_rotate_to_heading and abs(angle_to_path) > s.rotate_to_heading_min_angle:
        linear, angular = 0.0, _rotate_to(angle_to_path, velocity[1], s)
    else:
        square = carrot_dist * carrot_dist
        curvature = 2.0 * carrot_y / square if square > 0.001 else 0.0
        linear = _regulated_speed(curvature, _cost(cells, g, x, y), local, g, s)
        angular = linear * curvature
    angular = _clamp(angular, -s.max_angular_vel, s.max_angular_vel)
    status = OK
    if s.use_collision_detection and _collision_ahead(
        cells, g, outline, pose, (linear, angular), carrot_dist, s
    ):
        status = COLLISION_AHEAD
    return PursuitStep(
        status, closest, linear, angular, map_x, map_y, extent, off_path, off_heading, segment
    )
