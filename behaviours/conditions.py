"""Condition leaves: answer SUCCESS or FAILURE on the tick they are asked, never RUNNING."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import py_trees

from baobab.behaviours.ports import Clock
from baobab.sim.world import Pose2D

Status = py_trees.common.Status


def _angle_between(a: float, b: float) -> float:
    return abs(math.remainder(a - b, math.tau))


class IsAt(py_trees.behaviour.Behaviour):
    """SUCCESS when the robot is within ``tolerance`` m (and ``yaw_tolerance`` rad) of a pose.

    Args:
        name: the node's label.
        target: the pose to compare with (map frame).
        tolerance: distance tolerance (m).
        yaw_tolerance: heading tolerance (rad); None ignores the heading.
        robot_pose: returns the robot's current pose.
    """

    def __init__(
        self,
        name: str,
        target: Pose2D,
        tolerance: float,
        yaw_tolerance: float | None,
        robot_pose: Callable[[], Pose2D],
    ) -> None:
        super().__init__(name=name)
        self.target = target
        self.tolerance = tolerance
        self.yaw_tolerance = yaw_tolerance
        self._robot_pose = robot_pose

    def update(self) -> Status:
        """Compare the current pose with the target."""
        pose = self._robot_pose()
        distance = math.hypot(pose.x - self.target.x, pose.y - self.target.y)
        near = distance <= self.tolerance
        if near and self.yaw_tolerance is not None:
            near = _angle_between(pose.yaw, self.target.yaw) <= self.yaw_tolerance
        self.feedback_message = f"{distance:.3f} m away"
        return Status.SUCCESS if near else Status.FAILURE


class Elapsed(py_trees.behaviour.Behaviour):
    """SUCCESS once the sim clock reads at least ``time`` seconds, else FAILURE.

    Args:
        name: the node's label.
        time: the sim time threshold (s since the start of the run).
        clock: returns the sim time (s).
    """

    def __init__(self, name: str, time: float, clock: Clock) -> None:
        super().__init__(name=name)
        self.time = time
        self._clock = clock

    def update(self) -> Status:
        """Compare the clock with the threshold."""
        now = self._clock()
        self.feedback_message = f"t = {now:.2f} s"
        return Status.SUCCESS if now >= self.time else Status.FAILURE


class ObjectNear(py_trees.behaviour.Behaviour):
    """SUCCESS when a named object lies within ``tolerance`` m of a point.

    Args:
        name: the node's label.
        position: returns the object's current world position (m).
        target: the point to compare with (m).
        tolerance: distance tolerance (m).
    """

    def __init__(
        self,
        name: str,
        position: Callable[[], Sequence[float]],
        target: Sequence[float],
        tolerance: float,
    ) -> None:
        super().__init__(name=name)
        self._position = position
        self.target = tuple(target)
        self.tolerance = tolerance

    def update(self) -> Status:
        """Compare the object's position with the target."""
        distance = math.dist(self._position(), self.target)
        self.feedback_message = f"{distance:.3f} m away"
        return Status.SUCCESS if distance <= self.tolerance else Status.FAILURE
