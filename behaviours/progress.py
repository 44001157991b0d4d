"""Clear the costmaps while the robot makes no forward progress.

The rule (:mod:`baobab.behaviours.progress_rule`) comes from the Nav2 Simple Commander tutorial's
``nav_to_pose.py``, which watches ``/cmd_vel`` while a goal runs: the robot is "moving forward" when
the last command's ``linear.x`` is above zero, and whenever it is not and more than
``COSTMAP_CLEARING_PERIOD`` (0.5 s) has passed since the last clearing, it clears all costmaps.
:class:`ClearCostmapsWhenStuck` is that rule as a decorator around a navigation node. It judges
forward progress by what the robot did rather than by what it was told: the forward speed over the
last tick, the displacement between two consecutive poses projected on the earlier heading, divided
by the sim time between them. Rotating in place, reversing, waiting and being blocked all count as
no forward progress, as a zero or negative ``linear.x`` does in the tutorial.
"""

from __future__ import annotations

from collections.abc import Callable

import py_trees

from baobab.behaviours.ports import Clock
from baobab.behaviours.progress_rule import DEFAULT_MIN_SPEED, DEFAULT_PERIOD, forward_speed
from baobab.sim.world import Pose2D

__all__ = ["DEFAULT_MIN_SPEED", "DEFAULT_PERIOD", "ClearCostmapsWhenStuck", "forward_speed"]

Status = py_trees.common.Status


class ClearCostmapsWhenStuck(py_trees.decorators.Decorator):
    """Pass the child's status through; while it runs, clear the costmaps every ``period``
    seconds of sim time during which the robot is not moving forward.

    The clearing clock starts when the decorator starts, as the tutorial's starts with its node:
    the first clearing comes at least ``period`` s after that.

    Args:
        name: the node's label.
        child: the decorated (navigation) subtree.
        clear: clears the costmaps.
        robot_pose: the robot's current pose (map frame).
        clock: the sim time (s).
        period: least sim time between two clearings (s, > 0).
        min_speed: forward speed (m/s, >= 0) above which the robot is making progress.

    Attributes:
        clears: costmap clearings so far, over every activation.
        moving_forward: the latest judgement (True before the first measurement).
    """

    def __init__(
        self,
        name: str,
        child: py_trees.behaviour.Behaviour,
        *,
        clear: Callable[[], None],
        robot_pose: Callable[[], Pose2D],
        clock: Clock,
        period: float = DEFAULT_PERIOD,
        min_speed: float = DEFAULT_MIN_SPEED,
    ) -> None:
        super().__init__(name=name, child=child)
        if not period > 0 or not min_speed >= 0:
            raise ValueError(f"need period > 0 s and min_speed >= 0 m/s, got {period}, {min_speed}")
        self.period = period
        self.min_speed = min_speed
        self._clear = clear
        self._robot_pose = robot_pose
        self._clock = clock
        self.clears = 0
        self.moving_forward = True
        self._last_clear = 0.0
        self._last_pose: Pose2D | None = None
        self._last_time = 0.0

    def initialise(self) -> None:
        """Start the clearing clock and the speed measurement."""
        self._last_clear = self._last_time = self._clock()
        self._last_pose = self._robot_pose()
        self.moving_forward = True
        self.feedback_message = ""

    def update(self) -> Status:
        """Judge the progress and clear if due, while the child runs; return its status."""
        status = self.decorated.status
        if status is not Status.RUNNING:
            return status
        now = self._clock()
        pose = self._robot_pose()
        if self._last_pose is not None and now > self._last_time:
            speed = forward_speed(self._last_pose, pose, now - self._last_time)
            self.moving_forward = speed > self.min_speed
        self._last_pose, self._last_time = pose, now
        # 1e-9: the tick period need not divide the clearing period exactly in binary.
        if not self.moving_forward and now - self._last_clear >= self.period - 1e-9:
            self._clear()
            self.clears += 1
            self._last_clear = now
        state = "moving forward" if self.moving_forward else "no forward progress"
        self.feedback_message = f"{state}; {self.clears} clearings"
        return status
