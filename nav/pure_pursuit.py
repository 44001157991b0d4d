"""Regulated Pure Pursuit: Nav2's path-following controller, scaled to a robot's limits.

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
   ``max_allowed_time_to_collision_up_to_carrot``), checking the robot's footprint (a polygon
   at each projected yaw, turns in place too); a projected collision raises
   :class:`~baobab.nav.errors.CollisionAheadError` (Nav2: NO_VALID_CONTROL).

The cycle runs as one compiled call (:mod:`baobab.nav.rpp_kernel`).

Nav2's defaults are kept except where the robot's limits demand otherwise
(:mod:`baobab.robots.tuning`): its top speed and yaw rate, and
``regulated_linear_scaling_min_speed`` scaled like the top speed (0.25 m/s of 0.5 m/s). Built
without a robot's, the settings are the registry's default mobile robot's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from baobab.nav import rpp_kernel as kernel
from baobab.nav.costmap import Costmap2D
from baobab.nav.costmap_filters import SpeedLimit, applied_speed
from baobab.nav.errors import CollisionAheadError, FollowPathError, NavigationError
from baobab.nav.feedback import PathTracking
from baobab.nav.path import Path
from baobab.robots.catalog import default_mobile_robot
from baobab.sim.records import record
from baobab.sim.world import Pose2D

_ROBOT = default_mobile_robot().tuning


@dataclass(frozen=True)
class RegulatedPurePursuitParams:
    """Controller settings (m, s, rad): Nav2's defaults scaled to a robot (the default one)."""

    desired_linear_vel: float = _ROBOT.max_linear_speed
    max_angular_vel: float = _ROBOT.max_angular_speed
    lookahead_dist: float = 0.6
    min_lookahead_dist: float = 0.3
    max_lookahead_dist: float = 0.9
    lookahead_time: float = 1.5
    use_velocity_scaled_lookahead_dist: bool = False
    use_interpolation: bool = True
    use_rotate_to_heading: bool = True
    rotate_to_heading_min_angle: float = 0.785
    rotate_to_heading_angular_vel: float = _ROBOT.rotate_to_heading_speed
    max_angular_accel: float = _ROBOT.max_angular_accel
    use_regulated_linear_velocity_scaling: bool = True
    regulated_linear_scaling_min_radius: float = 0.9
    regulated_linear_scaling_min_speed: float = _ROBOT.min_regulated_speed
    use_cost_regulated_linear_velocity_scaling: bool = True
    cost_scaling_dist: float = 0.6
    cost_scaling_gain: float = 1.0
    inflation_cost_scaling_factor: float = _ROBOT.cost_scaling_factor
    min_approach_linear_velocity: float = 0.05
    approach_velocity_scaling_dist: float = 0.6
    use_collision_detection: bool = True
    max_allowed_time_to_collision_up_to_carrot: float = 1.0
    goal_dist_tol: float = 0.25
    controller_frequency: float = 20.0
    max_robot_pose_search_dist: float | None = None

    def pack(self, desired_linear_vel: float | None = None) -> np.ndarray:
        """These settings as the kernel's :data:`~baobab.nav.rpp_kernel.RPP_SETTINGS` record,
        with ``desired_linear_vel`` (m/s) replaced when given (a speed limit in force).

        ``max_robot_pose_search_dist`` None or 0 means the costmap's half extent (NaN there).
        """
        search = self.max_robot_pose_search_dist or math.nan
        speed = self.desired_linear_vel if desired_linear_vel is None else desired_linear_vel
        return record(
            kernel.RPP_SETTINGS,
            self,
            max_robot_pose_search_dist=search,
            desired_linear_vel=speed,
        )


class RegulatedPurePursuit:
    """Nav2's ``RegulatedPurePursuitController`` for a differential-drive robot.

    The controller remembers how far along the current path the robot got, so passed poses
    stay pruned; passing a different ``Path`` object (or calling :meth:`reset`) starts over.

    Attributes:
        last_carrot: map-frame ``(x, y)`` of the last carrot, for display.
        closest_index: index in the path of the pose nearest to the robot.
        step: what the last cycle's compiled step found (None before the first): the
            command, the carrot, and the tracking errors against the path near
            ``closest_index`` (:func:`baobab.nav.feedback.path_tracking`, computed in the
            compiled cycle; :attr:`tracking` has them as a record).
    """

    def __init__(self, params: RegulatedPurePursuitParams | None = None) -> None:
        self.params = params or RegulatedPurePursuitParams()
        self._settings = self.params.pack()
        self._path: Path | None = None
        self._along = np.zeros(1)
        self.closest_index = 0
        self.last_carrot: tuple[float, float] | None = None
        self.step: kernel.PursuitStep | None = None

    @property
    def tracking(self) -> PathTracking:
        """The tracking errors of the last cycle (zeros before the first)."""
        step = self.step
        if step is None:
            return PathTracking(0.0, 0.0, 0)
        return PathTracking(step.position_error, step.heading_error, step.tracking_index)

    def set_speed_limit(self, limit: SpeedLimit | None) -> None:
        """Nav2's ``setSpeedLimit``: the top speed becomes ``desired_linear_vel`` limited by
        ``limit`` (a percentage of it, or m/s; None or 0 restores it)."""
        speed = applied_speed(limit, self.params.desired_linear_vel)
        self._settings = self.params.pack(desired_linear_vel=speed)

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
        if len(path) == 0:
            raise NavigationError(FollowPathError.INVALID_PATH, "the path has no poses")
        if path is not self._path:
            self._path = path
            self.closest_index = 0
            self._along = path.cumulative_lengths
        x, y = pose.x, pose.y
        step = kernel.rpp_step(
            path.poses,
            self._along,
            self.closest_index,
            (x, y, pose.yaw),
            velocity,
            costmap.arrays(),
            self._settings,
        )
        self.closest_index = step.closest
        self.step = step
        if step.status == kernel.NO_POSE_NEAR:
            raise NavigationError(
                FollowPathError.INVALID_PATH,
                f"no path pose within {step.extent:.2f} m of ({x:.2f}, {y:.2f})",
            )
        self.last_carrot = (step.carrot_x, step.carrot_y)
        linear, angular = step.linear, step.angular
        if step.status == kernel.COLLISION_AHEAD:
            raise CollisionAheadError(
                f"projected motion ({linear:.2f} m/s, {angular:.2f} rad/s) from "
                f"({x:.2f}, {y:.2f}) collides before the carrot"
            )
        return linear, angular
