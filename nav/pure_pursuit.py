"""Regulated Pure Pursuit: Nav2's path-following controller, scaled to the TurtleBot3 Burger.

Per control cycle (:meth:`RegulatedPurePursuit.compute_velocity`):

1. Prune the poses the robot has passed and express the rest in the robot frame, up to the
   costmap's half extent.
2. Pick the carrot: the path point at the lookahead distance (interpolated on the segment that
   crosses the lookahead circle); curvature ``2 y / (x^2 + y^2)``.
3. Near the goal, rotate in place to the goal's yaw; if the carrot is more than
   ``rotate_to_heading_min_angle`` off the heading, rotate in place towards it; otherwise drive
   at ``desired_linear_vel`` regulated down by curvature (below
   ``regulated_linear_scaling_min_radius``), by proximity to obstacles (the cost under the
   robot turned back into a distance) and on the approach to the goal, then ``w = v k``.
4. Project the command ahead up to the carrot (at most
   ``max_allowed_time_to_collision_up_to_carrot``); a projected collision raises
   :class:`~baobab.nav.errors.CollisionAheadError` (Nav2: NO_VALID_CONTROL).

Nav2's defaults are kept except where the Burger's limits demand otherwise: 0.22 m/s,
2.84 rad/s, and ``regulated_linear_scaling_min_speed`` scaled like the top speed (0.25 m/s of
0.5 m/s becomes 0.11 m/s of 0.22 m/s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from baobab.nav.costmap import FREE_SPACE, MAX_NON_OBSTACLE, NO_INFORMATION, Costmap2D
from baobab.nav.errors import CollisionAheadError, FollowPathError, NavigationError
from baobab.nav.footprint import in_collision
from baobab.nav.path import Path
from baobab.sim.world import Pose2D


@dataclass(frozen=True)
class RegulatedPurePursuitParams:
    """Controller settings (m, s, rad): Nav2's defaults scaled to the Burger."""

    desired_linear_vel: float = 0.22
    max_angular_vel: float = 2.84
    lookahead_dist: float = 0.6
    min_lookahead_dist: float = 0.3
    max_lookahead_dist: float = 0.9
    lookahead_time: float = 1.5
    use_velocity_scaled_lookahead_dist: bool = False
    use_interpolation: bool = True
    use_rotate_to_heading: bool = True
    rotate_to_heading_min_angle: float = 0.785
    rotate_to_heading_angular_vel: float = 1.8
    max_angular_accel: float = 3.2
    use_regulated_linear_velocity_scaling: bool = True
    regulated_linear_scaling_min_radius: float = 0.9
    regulated_linear_scaling_min_speed: float = 0.11
    use_cost_regulated_linear_velocity_scaling: bool = True
    cost_scaling_dist: float = 0.6
    cost_scaling_gain: float = 1.0
    inflation_cost_scaling_factor: float = 3.0
    min_approach_linear_velocity: float = 0.05
    approach_velocity_scaling_dist: float = 0.6
    use_collision_detection: bool = True
    max_allowed_time_to_collision_up_to_carrot: float = 1.0
    goal_dist_tol: float = 0.25
    controller_frequency: float = 20.0
    max_robot_pose_search_dist: float | None = None


class RegulatedPurePursuit:
    """Nav2's ``RegulatedPurePursuitController`` for a differential-drive robot.

    The controller remembers how far along the current path the robot got, so passed poses
    stay pruned; passing a different ``Path`` object (or calling :meth:`reset`) starts over.

    Attributes:
        last_carrot: map-frame ``(x, y)`` of the last carrot, for display.
        closest_index: index in the path of the pose nearest to the robot.
    """

    def __init__(self, params: RegulatedPurePursuitParams | None = None) -> None:
        self.params = params or RegulatedPurePursuitParams()
        self._path: Path | None = None
        self._along = np.zeros(1)
        self.closest_index = 0
        self.last_carrot: tuple[float, float] | None = None

    def reset(self) -> None:
        """Forget the current path and its pruning."""
        self._path = None
        self.closest_index = 0
        self.last_carrot = None

    def compute_velocity(
        self,
        pose: Pose2D,
        velocity: tuple[float, float],
        path: Path,
        costmap: Costmap2D,
    ) -> tuple[float, float]:
        """The command ``(v, w)`` (m/s, rad/s) that follows ``path`` from ``pose``.

        Args:
            pose: the robot's map-frame pose.
            velocity: the robot's current ``(linear, angular)`` speed (m/s, rad/s).
            path: the global plan, in the map frame.
            costmap: the (local) costmap for regulation and collision checks.

        Raises:
            NavigationError: INVALID_PATH for an empty path or none of it near the robot.
            CollisionAheadError: the projected motion up to the carrot collides.
        """
        p = self.params
        local = self._transform_plan(pose, path, costmap)
        lookahead = self._lookahead_distance(velocity[0])
        carrot = self._carrot(local, lookahead)
        cos_yaw, sin_yaw = math.cos(pose.yaw), math.sin(pose.yaw)
        self.last_carrot = (
            pose.x + cos_yaw * carrot[0] - sin_yaw * carrot[1],
            pose.y + sin_yaw * carrot[0] + cos_yaw * carrot[1],
        )
        carrot_dist = math.hypot(carrot[0], carrot[1])
        angle_to_path = math.atan2(carrot[1], carrot[0])
        if p.use_rotate_to_heading and carrot_dist < p.goal_dist_tol:
            linear, angular = self._rotate_to(float(local[-1, 2]), velocity[1])
        elif p.use_rotate_to_heading and abs(angle_to_path) > p.rotate_to_heading_min_angle:
            linear, angular = self._rotate_to(angle_to_path, velocity[1])
        else:
            curvature = 2.0 * carrot[1] / carrot_dist**2 if carrot_dist**2 > 0.001 else 0.0
            linear = self._regulated_speed(curvature, costmap.cost(pose.x, pose.y), local, costmap)
            angular = linear * curvature
        angular = _clamp(angular, -p.max_angular_vel, p.max_angular_vel)
        if p.use_collision_detection and self._collision_imminent(
            pose, linear, angular, carrot_dist, costmap
        ):
            raise CollisionAheadError(
                f"projected motion ({linear:.2f} m/s, {angular:.2f} rad/s) from "
                f"({pose.x:.2f}, {pose.y:.2f}) collides before the carrot"
            )
        return linear, angular

    def _transform_plan(self, pose: Pose2D, path: Path, costmap: Costmap2D) -> np.ndarray:
        """Unpassed poses within the costmap's half extent, in the robot frame (x, y, yaw)."""
        if len(path) == 0:
            raise NavigationError(FollowPathError.INVALID_PATH, "the path has no poses")
        if path is not self._path:
            self._path = path
            self.closest_index = 0
            self._along = path.cumulative_lengths
        extent = max(costmap.size_x, costmap.size_y) * costmap.resolution / 2
        search_dist = self.params.max_robot_pose_search_dist or extent
        self.closest_index, local = _transform_kernel(
            path.poses,
            self._along,
            self.closest_index,
            pose.x,
            pose.y,
            pose.yaw,
            search_dist,
            extent,
        )
        if len(local) == 0:
            raise NavigationError(
                FollowPathError.INVALID_PATH,
                f"no path pose within {extent:.2f} m of ({pose.x:.2f}, {pose.y:.2f})",
            )
        return local

    def _lookahead_distance(self, speed: float) -> float:
        p = self.params
        if not p.use_velocity_scaled_lookahead_dist:
            return p.lookahead_dist
        return _clamp(abs(speed) * p.lookahead_time, p.min_lookahead_dist, p.max_lookahead_dist)

    def _carrot(self, local: np.ndarray, lookahead: float) -> tuple[float, float]:
        """The point of the path at the lookahead distance from the robot (the origin)."""
        index = _first_beyond(local, lookahead)
        if index < 0:
            return float(local[-1, 0]), float(local[-1, 1])
        if index == 0 or not self.params.use_interpolation:
            return float(local[index, 0]), float(local[index, 1])
        return _circle_segment_intersection(local[index - 1, :2], local[index, :2], lookahead)

    def _rotate_to(self, angle: float, angular_speed: float) -> tuple[float, float]:
        """Rotate in place towards ``angle`` (rad), within the acceleration and stopping limits."""
        p = self.params
        sign = 1.0 if angle > 0.0 else -1.0
        dt = 1.0 / p.controller_frequency
        angular = sign * p.rotate_to_heading_angular_vel
        angular = _clamp(
            angular,
            angular_speed - p.max_angular_accel * dt,
            angular_speed + p.max_angular_accel * dt,
        )
        stop_speed = math.sqrt(2.0 * p.max_angular_accel * abs(angle))
        if abs(angular) > stop_speed:
            angular = sign * stop_speed
        return 0.0, angular

    def _regulated_speed(
        self, curvature: float, pose_cost: int, local: np.ndarray, costmap: Costmap2D
    ) -> float:
        """Desired speed lowered for curvature, nearby obstacles and the goal approach."""
        p = self.params
        speed = p.desired_linear_vel
        curvature_speed, cost_speed = speed, speed
        if p.use_regulated_linear_velocity_scaling and curvature != 0.0:
            radius = abs(1.0 / curvature)
            if radius < p.regulated_linear_scaling_min_radius:
                curvature_speed = speed * radius / p.regulated_linear_scaling_min_radius
        if p.use_cost_regulated_linear_velocity_scaling and pose_cost not in (
            NO_INFORMATION,
            FREE_SPACE,
        ):
            # Invert the inflation formula: the distance to the nearest obstacle.
            distance = (-1.0 / p.inflation_cost_scaling_factor) * math.log(
                pose_cost / MAX_NON_OBSTACLE
            ) + costmap.inscribed_radius
            if distance < p.cost_scaling_dist:
                cost_speed = speed * p.cost_scaling_gain * distance / p.cost_scaling_dist
        speed = max(min(curvature_speed, cost_speed), p.regulated_linear_scaling_min_speed)
        # Approach: once the remaining path is short, scale with the distance to its end.
        steps = local[1:, :2] - local[:-1, :2]  # np.diff's result, without its overhead
        remaining = float(np.hypot(steps[:, 0], steps[:, 1]).sum())
        if remaining < p.approach_velocity_scaling_dist:
            scaling = math.hypot(local[-1, 0], local[-1, 1]) / p.approach_velocity_scaling_dist
            speed = min(speed, max(speed * scaling, p.min_approach_linear_velocity))
        return _clamp(speed, 0.0, p.desired_linear_vel)

    def _collision_imminent(
        self, pose: Pose2D, linear: float, angular: float, carrot_dist: float, costmap: Costmap2D
    ) -> bool:
        """Nav2's projection: step the command ahead until the carrot or the time limit."""
        if in_collision(costmap, pose.x, pose.y):
            return True
        if abs(linear) < 0.01:
            # A circular robot turning in place sweeps no new cells.
            return False
        dt = costmap.resolution / abs(linear)
        x, y, yaw = pose.x, pose.y, pose.yaw
        i = 1
        while i * dt < self.params.max_allowed_time_to_collision_up_to_carrot:
            i += 1
            x += dt * linear * math.cos(yaw)
            y += dt * linear * math.sin(yaw)
            yaw += dt * angular
            if math.hypot(x - pose.x, y - pose.y) > carrot_dist:
                break
            if in_collision(costmap, x, y):
                return True
        return False


@numba.njit(cache=True, nogil=True)
def _first_beyond(local: np.ndarray, distance: float) -> int:  # pragma: no cover - compiled
    """Index of the first row of ``local`` at least ``distance`` (m) from the origin, or -1."""
    for index in range(local.shape[0]):
        if math.hypot(local[index, 0], local[index, 1]) >= distance:
            return index
    return -1


@numba.njit(cache=True, nogil=True)
def _transform_kernel(
    poses: np.ndarray,
    along: np.ndarray,
    begin: int,
    x: float,
    y: float,
    yaw: float,
    search_dist: float,
    extent: float,
) -> tuple[int, np.ndarray]:  # pragma: no cover - compiled
    """The closest pose and the robot-frame poses after it, up to the first beyond ``extent``.

    The closest pose is searched from ``begin`` over ``search_dist`` (m) of path length
    (``along`` holds the cumulative length at each pose); the first of equally close poses
    wins. The returned ``(N, 3)`` rows are ``x, y`` (m) in the robot frame and the heading
    relative to the robot's, wrapped to ``[-pi, pi)``.
    """
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


def _clamp(value: float, low: float, high: float) -> float:
    """``value`` limited to ``[low, high]`` (``np.clip`` costs microseconds on scalars)."""
    return float(min(max(value, low), high))


def _circle_segment_intersection(
    p1: np.ndarray, p2: np.ndarray, radius: float
) -> tuple[float, float]:
    """Where segment ``p1 -> p2`` (``p1`` inside, ``p2`` outside) leaves the origin's circle."""
    x1, y1 = float(p1[0]), float(p1[1])
    x2, y2 = float(p2[0]), float(p2[1])
    dx, dy = x2 - x1, y2 - y1
    dr2 = dx * dx + dy * dy
    cross = x1 * y2 - x2 * y1
    root = math.sqrt(max(radius * radius * dr2 - cross * cross, 0.0))
    sign = math.copysign(1.0, (x2 * x2 + y2 * y2) - (x1 * x1 + y1 * y1))
    return (
        (cross * dy + sign * dx * root) / dr2,
        (-cross * dx + sign * dy * root) / dr2,
    )
