"""Goal and progress checkers of Nav2's controller server.

:class:`SimpleGoalChecker` decides when the robot has arrived; :class:`SimpleProgressChecker`
decides when it has stopped making progress (FollowPath's FAILED_TO_MAKE_PROGRESS). Both are
stateful, take sim time from the caller and are reset for each new goal.
"""

from __future__ import annotations

import math

from baobab.nav.path import wrap_angle
from baobab.sim.world import Pose2D


class SimpleGoalChecker:
    """Arrived when within ``xy_goal_tolerance`` (m) and ``yaw_goal_tolerance`` (rad).

    With ``stateful`` (Nav2's default), once the position is within tolerance it stays
    accepted until :meth:`reset`, so the robot may finish by rotating in place even if that
    rotation drifts it slightly out of the circle.
    """

    def __init__(
        self,
        xy_goal_tolerance: float = 0.25,
        yaw_goal_tolerance: float = 0.25,
        stateful: bool = True,
    ) -> None:
        if xy_goal_tolerance < 0 or yaw_goal_tolerance < 0:
            raise ValueError("goal tolerances must not be negative")
        self.xy_goal_tolerance = xy_goal_tolerance
        self.yaw_goal_tolerance = yaw_goal_tolerance
        self.stateful = stateful
        self._check_xy = True

    def reset(self) -> None:
        """Forget a latched position (new goal)."""
        self._check_xy = True

    def is_goal_reached(
        self, pose: Pose2D, goal: Pose2D, velocity: tuple[float, float] = (0.0, 0.0)
    ) -> bool:
        """True when ``pose`` is at ``goal``; ``velocity`` is unused, as in Nav2's checker."""
        if self._check_xy:
            if math.hypot(pose.x - goal.x, pose.y - goal.y) > self.xy_goal_tolerance:
                return False
            if self.stateful:
                self._check_xy = False
        return abs(wrap_angle(goal.yaw - pose.yaw)) < self.yaw_goal_tolerance

    @property
    def position_latched(self) -> bool:
        """True once the stateful position check has been passed."""
        return not self._check_xy

    def tolerances(self) -> tuple[float, float]:
        """``(xy, yaw)`` tolerances (m, rad)."""
        return self.xy_goal_tolerance, self.yaw_goal_tolerance


class SimpleProgressChecker:
    """Fails when the robot stays within ``required_movement_radius`` (m) for too long.

    The first check sets a baseline pose and time; every time the robot gets farther than the
    radius from the baseline, the baseline moves to the robot. :meth:`check` returns False once
    more than ``movement_time_allowance`` (s) of sim time passed since the baseline was set.
    """

    def __init__(
        self, required_movement_radius: float = 0.5, movement_time_allowance: float = 10.0
    ) -> None:
        if required_movement_radius < 0 or movement_time_allowance <= 0:
            raise ValueError("progress checker radius must be >= 0 and time allowance > 0")
        self.required_movement_radius = required_movement_radius
        self.movement_time_allowance = movement_time_allowance
        self._baseline: Pose2D | None = None
        self._baseline_time = 0.0

    def reset(self) -> None:
        """Forget the baseline (new goal or new path)."""
        self._baseline = None

    def check(self, pose: Pose2D, now: float) -> bool:
        """True while the robot is making progress at sim time ``now`` (s)."""
        baseline = self._baseline
        if baseline is None or (
            math.hypot(pose.x - baseline.x, pose.y - baseline.y) > self.required_movement_radius
        ):
            self._baseline = pose
            self._baseline_time = now
            return True
        return now - self._baseline_time <= self.movement_time_allowance
