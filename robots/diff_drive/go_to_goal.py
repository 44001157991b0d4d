"""Point-to-point navigation (seed §6): a go-to-goal law and the IDLE / GO_TO_GOAL state machine.

The law steers proportionally to the heading error toward the goal and scales the forward
speed down with that error, stopping to turn in place when the error exceeds ``theta_max``:

    theta_err = wrap(atan2(gy - y, gx - x) - yaw)
    w = clamp(k_w * theta_err, -w_max, w_max)
    v = v_max * max(0, 1 - |theta_err| / theta_max)

:func:`go_to_goal_command` is the law alone; :class:`GoToGoalController` runs it every
``period`` seconds of sim time on a :class:`DiffDriveBase`.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from baobab.robots.diff_drive.base import DiffDriveBase, clamp
from baobab.sim.simulation import PeriodicHandle, Simulation
from baobab.sim.world import Pose2D

Point = tuple[float, float]
"""A point in the map frame (m)."""


class NavState(enum.Enum):
    """States of the tutorial navigation state machines (seed Fig. 6 and Fig. 10)."""

    IDLE = "IDLE"
    GO_TO_GOAL = "GO_TO_GOAL"
    WALL_FOLLOW = "WALL_FOLLOW"


@dataclass(frozen=True)
class GoToGoalParams:
    """Gains and limits of the go-to-goal law (seed §6 defaults).

    Raises:
        ValueError: if a speed, gain, angle, tolerance or period is not positive.
    """

    linear_speed: float = 0.20
    """Forward speed when aligned with the goal, v_max (m/s)."""
    angular_speed: float = 0.6
    """Yaw-rate limit, w_max (rad/s)."""
    heading_gain: float = 1.5
    """Proportional gain on the heading error, k_w (1/s)."""
    theta_max: float = math.radians(70.0)
    """Heading error at and beyond which the robot only turns (rad)."""
    goal_tolerance: float = 0.05
    """The goal counts as reached closer than this (m)."""
    period: float = 0.05
    """Control period (s)."""

    def __post_init__(self) -> None:
        for name in (
            "linear_speed",
            "angular_speed",
            "heading_gain",
            "theta_max",
            "goal_tolerance",
            "period",
        ):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive number, got {value}")


def angle_wrap(angle: float) -> float:
    """``angle`` (rad) wrapped to ``[-pi, pi]``."""
    return math.remainder(angle, 2 * math.pi)


def goal_distance(pose: Pose2D, goal: Point) -> float:
    """Euclidean distance (m) from ``pose`` to ``goal``."""
    return math.hypot(goal[0] - pose.x, goal[1] - pose.y)


def go_to_goal_command(
    pose: Pose2D, goal: Point, params: GoToGoalParams = GoToGoalParams()
) -> tuple[float, float]:
    """The go-to-goal law: ``(v, w)`` (m/s, rad/s) that drive ``pose`` toward ``goal``."""
    desired = math.atan2(goal[1] - pose.y, goal[0] - pose.x)
    error = angle_wrap(desired - pose.yaw)
    angular = clamp(params.heading_gain * error, -params.angular_speed, params.angular_speed)
    linear = params.linear_speed * max(0.0, 1.0 - abs(error) / params.theta_max)
    return linear, angular


class GoToGoalController:
    """Drives the base to a goal point, stopping within ``goal_tolerance`` (seed Fig. 6).

    IDLE -> GO_TO_GOAL on :meth:`set_goal`; GO_TO_GOAL -> IDLE when the goal is reached (the
    base is told to stop) or on :meth:`cancel`. The robot pose is the base's ground truth.

    Args:
        sim: the simulation; the controller registers a periodic callback.
        base: the base to command.
        params: gains, limits and period.
    """

    callback_name = "go_to_goal"
    """Name of the periodic sim callback."""

    def __init__(
        self, sim: Simulation, base: DiffDriveBase, params: GoToGoalParams = GoToGoalParams()
    ) -> None:
        self.base = base
        self.params = params
        self.state = NavState.IDLE
        self.goal: Point | None = None
        self.reached = False
        """True once the latest goal was reached."""
        self.handle: PeriodicHandle = sim.every(params.period, self.step, name=self.callback_name)

    def set_goal(self, x: float, y: float) -> None:
        """Head for ``(x, y)`` (m, map frame) from now on."""
        self.goal = (x, y)
        self.reached = False
        self.state = NavState.GO_TO_GOAL

    def cancel(self) -> None:
        """Stop the robot and go IDLE."""
        self.base.stop()
        self.state = NavState.IDLE

    def close(self) -> None:
        """Cancel and unregister the periodic callback."""
        self.cancel()
        self.handle.cancel()

    def step(self, _time: float) -> None:
        """One control step (the periodic callback)."""
        if self.state is not NavState.GO_TO_GOAL or self.goal is None:
            return
        pose = self.base.pose()
        if goal_distance(pose, self.goal) < self.params.goal_tolerance:
            self.base.stop()
            self.state = NavState.IDLE
            self.reached = True
            return
        self.base.command(*go_to_goal_command(pose, self.goal, self.params))
