"""Nav2's controller server loop: follow one path with Regulated Pure Pursuit until the goal.

Per control cycle (20 Hz), as ``nav2_controller`` does it: check progress (FAILED_TO_MAKE_PROGRESS
when the robot stays within 0.5 m for 10 s), compute and send the velocity, then check the
goal against the path's last pose. When the controller finds no valid command (a collision
ahead), zero velocity is sent and the failure is tolerated for ``failure_tolerance`` seconds
before the cycle fails with PATIENCE_EXCEEDED. The goal counts as reached when the goal
checker agrees and at most ``path_length_tolerance`` of path is left (Rolling's guard against
paths that pass near their own end).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from baobab.nav.checkers import SimpleGoalChecker, SimpleProgressChecker
from baobab.nav.costmap import Costmap2D
from baobab.nav.costmap_filters import SpeedLimit
from baobab.nav.errors import FollowPathError, NavigationError
from baobab.nav.interfaces import MobileBase
from baobab.nav.path import Path
from baobab.nav.pure_pursuit import RegulatedPurePursuit, RegulatedPurePursuitParams
from baobab.robots.catalog import default_mobile_robot
from baobab.sim.tasks import TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D

_ROBOT = default_mobile_robot().tuning


@dataclass(frozen=True)
class ControllerParams:
    """Controller server settings: Nav2 bringup's (Hz, s, m, rad), the goal and progress
    checkers' for a robot (the default one unless given)."""

    controller_frequency: float = 20.0
    failure_tolerance: float = 0.3
    xy_goal_tolerance: float = _ROBOT.goal_tolerances[0]
    yaw_goal_tolerance: float = _ROBOT.goal_tolerances[1]
    stateful: bool = True
    path_length_tolerance: float = 1.0
    required_movement_radius: float = _ROBOT.progress[0]
    movement_time_allowance: float = _ROBOT.progress[1]
    rpp: RegulatedPurePursuitParams = field(default_factory=RegulatedPurePursuitParams)


def failed(code: FollowPathError, message: str) -> TaskOutcome:
    """A FollowPath failure outcome."""
    return TaskOutcome(TaskStatus.FAILED, int(code), message, code.name)


class PathFollower:
    """The controller server: one path at a time, one :meth:`cycle` per control period.

    Args:
        base: the robot.
        local_costmap: returns the up-to-date local costmap.
        params: settings.
    """

    def __init__(
        self,
        base: MobileBase,
        local_costmap: Callable[[], Costmap2D],
        params: ControllerParams | None = None,
    ) -> None:
        self.params = params or ControllerParams()
        p = self.params
        self.base = base
        self._local_costmap = local_costmap
        self.controller = RegulatedPurePursuit(p.rpp)
        self.goal_checker = SimpleGoalChecker(p.xy_goal_tolerance, p.yaw_goal_tolerance, p.stateful)
        self.progress_checker = SimpleProgressChecker(
            p.required_movement_radius, p.movement_time_allowance
        )
        self.path: Path | None = None
        self.located_path: Path | None = None
        """The path :meth:`remaining_length` refers to: the last one the controller ran on."""
        self.feedback: dict[str, Any] = {}
        self._last_valid = 0.0
        self._lengths: list[float] = [0.0]
        self.speed_limit: SpeedLimit | None = None
        """The speed limit in force (None: none was ever set)."""

    def start(self, path: Path, now: float) -> None:
        """Begin following ``path`` at sim time ``now`` (s): a new goal, checkers reset."""
        self.progress_checker.reset()
        self.controller.reset()
        self.feedback.clear()
        self._last_valid = now
        self.set_path(path)

    def set_path(self, path: Path) -> None:
        """Switch to an updated path (replanning); progress keeps counting."""
        self.path = path
        self.goal_checker.reset()
        self._lengths = path.cumulative_lengths.tolist()  # list items read faster than numpy's

    def set_speed_limit(self, limit: SpeedLimit) -> None:
        """Apply a speed limit (a speed filter's) to the controller, as Nav2's controller server
        forwards ``speed_limit`` to its controller; it lasts until the next one."""
        self.speed_limit = limit
        self.controller.set_speed_limit(limit)

    def remaining_length(self) -> float:
        """Length (m) of :attr:`located_path` from the pose closest to the robot last cycle."""
        lengths = self._lengths
        index = min(self.controller.closest_index, len(lengths) - 1)
        return lengths[-1] - lengths[index]

    def cycle(self, now: float) -> TaskOutcome | None:
        """One control cycle at sim time ``now`` (s); the outcome once the path ended."""
        path, p = self.path, self.params
        if path is None or len(path) == 0:
            self.base.stop()
            return failed(FollowPathError.INVALID_PATH, "no path to follow")
        pose = self.base.pose()
        velocity = self.base.body_velocity()
        if not self.progress_checker.check(pose, now):
            self.base.stop()
            return failed(FollowPathError.FAILED_TO_MAKE_PROGRESS, "Failed to make progress")
        try:
            self.located_path = path
            linear, angular = self.controller.compute_velocity(
                pose, velocity, path, self._local_costmap()
            )
        except NavigationError as error:
            self.base.stop()
            tolerant = p.failure_tolerance > 0 or p.failure_tolerance == -1.0
            if error.code != FollowPathError.NO_VALID_CONTROL or not tolerant:
                return TaskOutcome(
                    TaskStatus.FAILED, int(error.code), error.message, error.code_name
                )
            if p.failure_tolerance != -1.0 and now - self._last_valid > p.failure_tolerance + 1e-9:
                return failed(
                    FollowPathError.PATIENCE_EXCEEDED,
                    f"Controller patience exceeded: {error.message}",
                )
            return None
        self._last_valid = now
        self.base.command(linear, angular)
        remaining = self.remaining_length()
        self.feedback["distance_to_goal"] = remaining
        self.feedback["speed"] = velocity[0]
        self.feedback["tracking_feedback"] = self._tracking(path, pose, velocity[0], remaining)
        if remaining <= p.path_length_tolerance and self.goal_checker.is_goal_reached(
            pose, path.goal, velocity
        ):
            self.base.stop()
            return TaskOutcome(TaskStatus.SUCCEEDED)
        return None

    def halt(self) -> None:
        """Stop the robot (cancel or halted tree)."""
        self.base.stop()

    def _tracking(self, path: Path, pose: Pose2D, speed: float, remaining: float) -> dict[str, Any]:
        """Nav2's ``TrackingFeedback`` fields (m, rad, m/s) of this cycle (a nested dict, so
        that the run's trace, which keeps the scalar feedback fields, is unchanged)."""
        step = self.controller.step
        assert step is not None  # the controller just ran
        goal = path.goal
        return {
            "position_tracking_error": step.position_error,
            "heading_tracking_error": step.heading_error,
            "current_path_index": step.tracking_index,
            "robot_pose": pose,
            "distance_to_goal": math.hypot(goal.x - pose.x, goal.y - pose.y),
            "speed": speed,
            "remaining_path_length": remaining,
        }


class FollowPathTask:
    """Nav2's FollowPath action: the controller server alone on a given path.

    Satisfies the server's task protocol; a new path of the same type replaces the current one
    in place (:meth:`preempt`), as the controller server does.
    """

    def __init__(self, path: Path, follower: PathFollower) -> None:
        self.path = path
        self.follower = follower
        self.period = 1.0 / follower.params.controller_frequency
        self.feedback: dict[str, Any] = {}
        self._started = False

    def preempt(self, path: Path) -> None:
        """Follow ``path`` from now on."""
        self.path = path
        if self._started:
            self.follower.set_path(path)

    def tick(self, now: float) -> TaskOutcome | None:
        """One controller cycle at sim time ``now`` (s)."""
        if not self._started:
            self._started = True
            self.follower.start(self.path, now)
        outcome = self.follower.cycle(now)
        self.feedback.update(self.follower.feedback)
        return outcome

    def halt(self) -> None:
        """Stop the robot."""
        self.follower.halt()
