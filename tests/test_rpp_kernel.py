"""The compiled pure pursuit step against a plain Python controller, bit for bit.

``ReferencePurePursuit`` below is the controller written plainly in Python with the kernel's
float operations in the kernel's order (the C library's ``hypot``, as numpy and numba call it;
path lengths added one segment after another), so the two must agree to the last bit. Random
paths, poses, speeds, costmaps and settings must give identical commands, carrots, pruning
and errors.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from baobab.nav.costmap import FREE_SPACE, MAX_NON_OBSTACLE, NO_INFORMATION, Costmap2D
from baobab.nav.errors import CollisionAheadError, FollowPathError, NavigationError
from baobab.nav.footprint import in_collision
from baobab.nav.path import Path
from baobab.nav.pure_pursuit import RegulatedPurePursuit, RegulatedPurePursuitParams
from baobab.sim.world import Pose2D


def _hypot(x: float, y: float) -> float:
    """The C library's ``hypot`` (CPython's own ``math.hypot`` rounds differently)."""
    return float(np.hypot(x, y))


def _clamp(value: float, low: float, high: float) -> float:
    return float(min(max(value, low), high))


class ReferencePurePursuit:
    """The Python controller as it was before the kernel (same float operations)."""

    def __init__(self, params: RegulatedPurePursuitParams) -> None:
        self.params = params
        self._path: Path | None = None
        self.closest_index = 0
        self.last_carrot: tuple[float, float] | None = None

    def compute_velocity(
        self, pose: Pose2D, velocity: tuple[float, float], path: Path, costmap: Costmap2D
    ) -> tuple[float, float]:
        p = self.params
        local = self._transform_plan(pose, path, costmap)
        lookahead = p.lookahead_dist
        if p.use_velocity_scaled_lookahead_dist:
            lookahead = _clamp(
                abs(velocity[0]) * p.lookahead_time, p.min_lookahead_dist, p.max_lookahead_dist
            )
        carrot = self._carrot(local, lookahead)
        cos_yaw, sin_yaw = math.cos(pose.yaw), math.sin(pose.yaw)
        self.last_carrot = (
            pose.x + cos_yaw * carrot[0] - sin_yaw * carrot[1],
            pose.y + sin_yaw * carrot[0] + cos_yaw * carrot[1],
        )
        carrot_dist = _hypot(carrot[0], carrot[1])
        angle_to_path = math.atan2(carrot[1], carrot[0])
        if p.use_rotate_to_heading and carrot_dist < p.goal_dist_tol:
            linear, angular = self._rotate_to(float(local[-1, 2]), velocity[1])
        elif p.use_rotate_to_heading and abs(angle_to_path) > p.rotate_to_heading_min_angle:
            linear, angular = self._rotate_to(angle_to_path, velocity[1])
        else:
            square = carrot_dist * carrot_dist
            curvature = 2.0 * carrot[1] / square if square > 0.001 else 0.0
            linear = self._regulated_speed(curvature, costmap.cost(pose.x, pose.y), local, costmap)
            angular = linear * curvature
        angular = _clamp(angular, -p.max_angular_vel, p.max_angular_vel)
        if p.use_collision_detection and self._collision_imminent(
            pose, linear, angular, carrot_dist, costmap
        ):
            raise CollisionAheadError("collides")
        return linear, angular

    def _transform_plan(self, pose: Pose2D, path: Path, costmap: Costmap2D) -> np.ndarray:
        if path is not self._path:
            self._path = path
            self.closest_index = 0
        along = path.cumulative_lengths
        extent = max(costmap.size_x, costmap.size_y) * costmap.resolution / 2
        search_dist = self.params.max_robot_pose_search_dist or extent
        poses, x, y, n = path.poses, pose.x, pose.y, len(path)
        begin = self.closest_index
        limit = along[begin] + search_dist
        closest, best = begin, math.inf
        k = begin
        while k < n and (k == begin or along[k] <= limit):
            distance = _hypot(poses[k, 0] - x, poses[k, 1] - y)
            if distance < best:
                closest, best = k, distance
            k += 1
        end = closest
        while end < n and _hypot(poses[end, 0] - x, poses[end, 1] - y) <= extent:
            end += 1
        self.closest_index = closest
        cos_yaw, sin_yaw = math.cos(pose.yaw), math.sin(pose.yaw)
        local = np.empty((end - closest, 3))
        for i in range(end - closest):
            dx, dy = float(poses[closest + i, 0]) - x, float(poses[closest + i, 1]) - y
            local[i, 0] = cos_yaw * dx + sin_yaw * dy
            local[i, 1] = -sin_yaw * dx + cos_yaw * dy
            local[i, 2] = (float(poses[closest + i, 2]) - pose.yaw + math.pi) % (
                2 * math.pi
            ) - math.pi
        if len(local) == 0:
            raise NavigationError(FollowPathError.INVALID_PATH, "no pose near")
        return local

    def _carrot(self, local: np.ndarray, lookahead: float) -> tuple[float, float]:
        index = -1
        for i in range(len(local)):
            if _hypot(local[i, 0], local[i, 1]) >= lookahead:
                index = i
                break
        if index < 0:
            return float(local[-1, 0]), float(local[-1, 1])
        if index == 0 or not self.params.use_interpolation:
            return float(local[index, 0]), float(local[index, 1])
        x1, y1 = float(local[index - 1, 0]), float(local[index - 1, 1])
        x2, y2 = float(local[index, 0]), float(local[index, 1])
        dx, dy = x2 - x1, y2 - y1
        dr2 = dx * dx + dy * dy
        cross = x1 * y2 - x2 * y1
        root = math.sqrt(max(lookahead * lookahead * dr2 - cross * cross, 0.0))
        sign = math.copysign(1.0, (x2 * x2 + y2 * y2) - (x1 * x1 + y1 * y1))
        return (cross * dy + sign * dx * root) / dr2, (-cross * dx + sign * dy * root) / dr2

    def _rotate_to(self, angle: float, angular_speed: float) -> tuple[float, float]:
        p = self.params
        sign = 1.0 if angle > 0.0 else -1.0
        dt = 1.0 / p.controller_frequency
        angular = _clamp(
            sign * p.rotate_to_heading_angular_vel,
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
            distance = (-1.0 / p.inflation_cost_scaling_factor) * math.log(
                pose_cost / MAX_NON_OBSTACLE
            ) + costmap.inscribed_radius
            if distance < p.cost_scaling_dist:
                cost_speed = speed * p.cost_scaling_gain * distance / p.cost_scaling_dist
        speed = max(min(curvature_speed, cost_speed), p.regulated_linear_scaling_min_speed)
        remaining = 0.0
        for i in range(len(local) - 1):
            remaining += _hypot(local[i + 1, 0] - local[i, 0], local[i + 1, 1] - local[i, 1])
        if remaining < p.approach_velocity_scaling_dist:
            scaling = _hypot(local[-1, 0], local[-1, 1]) / p.approach_velocity_scaling_dist
            speed = min(speed, max(speed * scaling, p.min_approach_linear_velocity))
        return _clamp(speed, 0.0, p.desired_linear_vel)

    def _collision_imminent(
        self, pose: Pose2D, linear: float, angular: float, carrot_dist: float, costmap: Costmap2D
    ) -> bool:
        if in_collision(costmap, pose.x, pose.y):
            return True
        if abs(linear) < 0.01:
            return False
        dt = costmap.resolution / abs(linear)
        x, y, yaw = pose.x, pose.y, pose.yaw
        i = 1
        while i * dt < self.params.max_allowed_time_to_collision_up_to_carrot:
            i += 1
            x += dt * linear * math.cos(yaw)
            y += dt * linear * math.sin(yaw)
            yaw += dt * angular
            if _hypot(x - pose.x, y - pose.y) > carrot_dist:
                break
            if in_collision(costmap, x, y):
                return True
        return False


def _random_costmap(rng: np.random.Generator, centre: tuple[float, float]) -> Costmap2D:
    size = int(rng.integers(20, 70))
    costmap = Costmap2D(
        size,
        size,
        0.05,
        (centre[0] - size * 0.025 + rng.normal(0, 0.01), centre[1] - size * 0.025),
        inscribed_radius=0.105,
    )
    # Free space, a band of graded costs, and a few lethal / inscribed / unknown spots.
    data = rng.choice([0, 0, 0, 0, 50, 120, 200, 252, 253, 254, 255], size=(size, size))
    costmap.data[:] = np.where(rng.random((size, size)) < 0.7, 0, data).astype(np.uint8)
    return costmap


def _random_path(rng: np.random.Generator) -> Path:
    n = int(rng.integers(2, 200))
    step = rng.uniform(0.005, 0.08)
    headings = np.cumsum(rng.normal(0.0, 0.3, n))
    points = np.cumsum(np.column_stack([np.cos(headings), np.sin(headings)]) * step, axis=0)
    return Path.from_points(points, float(rng.uniform(-math.pi, math.pi)))


def _random_params(rng: np.random.Generator) -> RegulatedPurePursuitParams:
    params = RegulatedPurePursuitParams()
    flags = {
        "use_velocity_scaled_lookahead_dist": bool(rng.random() < 0.3),
        "use_interpolation": bool(rng.random() < 0.8),
        "use_rotate_to_heading": bool(rng.random() < 0.8),
        "use_regulated_linear_velocity_scaling": bool(rng.random() < 0.8),
        "use_cost_regulated_linear_velocity_scaling": bool(rng.random() < 0.8),
        "use_collision_detection": bool(rng.random() < 0.8),
    }
    search = [None, 0.0, 0.3, 1.0][int(rng.integers(4))]
    return replace(params, max_robot_pose_search_dist=search, **flags)


def _outcome(
    controller: RegulatedPurePursuit | ReferencePurePursuit,
    pose: Pose2D,
    velocity: tuple[float, float],
    path: Path,
    costmap: Costmap2D,
) -> tuple[object, ...]:
    try:
        result: object = controller.compute_velocity(pose, velocity, path, costmap)
    except CollisionAheadError:
        result = "collision"
    except NavigationError:
        result = "invalid"
    return result, controller.closest_index, controller.last_carrot


def test_the_kernel_matches_the_python_controller_bit_for_bit() -> None:
    rng = np.random.default_rng(11)
    outcomes: set[object] = set()
    for _ in range(150):
        params = _random_params(rng)
        path = _random_path(rng)
        compiled, reference = RegulatedPurePursuit(params), ReferencePurePursuit(params)
        for k in range(12):
            index = min(int(k * len(path) / 12 + rng.integers(0, 3)), len(path) - 1)
            x, y, yaw = path.poses[index]
            far = 3.0 if rng.random() < 0.05 else 0.0
            pose = Pose2D(
                x=float(x + far + rng.normal(0, 0.1)),
                y=float(y + rng.normal(0, 0.1)),
                yaw=float(yaw + rng.normal(0, 0.8)),
            )
            velocity = (float(rng.uniform(-0.05, 0.25)), float(rng.uniform(-2.0, 2.0)))
            costmap = _random_costmap(rng, (pose.x, pose.y))
            expected = _outcome(reference, pose, velocity, path, costmap)
            assert _outcome(compiled, pose, velocity, path, costmap) == expected
            outcomes.add(expected[0] if isinstance(expected[0], str) else "command")
    # The cases cover every outcome, so each branch was compared.
    assert outcomes == {"command", "collision", "invalid"}
