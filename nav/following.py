"""Nav2's following server (``opennav_following``): the ``follow_object`` action.

The robot keeps ``desired_distance`` from a moving object whose pose it hears on a topic
(``followObjectByTopic``) or reads as a TF frame (``followObjectByFrame``; the frame wins when
both are given), as Nav2's loop does (reference/nav2_ros_facts.md §7), ticked at the
navigation controller rate:

- the target is the object's pose pulled towards the robot by ``desired_distance`` (its
  heading the bearing from the robot, ``skip_orientation``), low-pass filtered
  (``filter_coef``). Within ``linear_tolerance`` and ``angular_tolerance`` of it the robot
  stops (STOPPING) and keeps watching; otherwise the graceful law drives towards the point
  0.25 m nearer the object (CONTROLLING);
- a pose older than ``detection_timeout`` (or none yet) is a lost detection: the robot goes on
  towards the last one meanwhile, then each lost cycle uses a retry; with
  ``search_by_rotating`` it first turns ``search_angle`` left then right looking for the
  object (RETRY; ``rotate_to_object_timeout``). After ``max_retries`` the goal fails with
  FAILED_TO_DETECT_OBJECT (a failed search: FAILED_TO_CONTROL);
- it succeeds after ``max_duration`` (0: never), or once the object stood still longer than
  ``static_object_timeout`` (negative: never).

Poses come from :class:`~baobab.nav.object_poses.ObjectPoses`. A cancel or a preemption stops
the base at once (:mod:`baobab.nav.task_slot`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any

from baobab.nav.errors import FollowObjectError, GoalRejectedError
from baobab.nav.graceful_control import GracefulParams, rotate_towards, velocity
from baobab.nav.interfaces import FEEDBACK_KEY, RESULT_KEY, MobileBase
from baobab.nav.object_poses import ObjectPoses
from baobab.nav.ros.nav2_msgs.action import FollowObject
from baobab.nav.rostime import Duration
from baobab.nav.task_slot import TaskSlot
from baobab.robots.catalog import default_mobile_robot
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D

_ROBOT = default_mobile_robot().tuning
FOLLOW_ACTION = "follow_object"
BACKWARD_PROJECTION = 0.25
"""m nearer the object than ``desired_distance`` the law aims at (Nav2: the law gets jittery
close to its target)."""


@dataclass(frozen=True)
class FollowingParams:
    """The following server's settings: Nav2's names, units and defaults (s, m, rad)."""

    detection_timeout: float = 2.0
    """A pose older than this (s) is a lost detection."""
    rotate_to_object_timeout: float = 10.0
    """s a search by rotating may take."""
    static_object_timeout: float = -1.0
    """Succeed once the object stood still this long (s); negative: never."""
    linear_tolerance: float = 0.15
    """How close (m) to the target the robot stops."""
    angular_tolerance: float = 0.15
    """How close (rad) in heading."""
    max_retries: int = 3
    """Lost detections tolerated before the goal fails."""
    desired_distance: float = 1.0
    """Distance (m) kept from the object."""
    skip_orientation: bool = True
    """Aim along the bearing robot -> object, not the object's own heading."""
    search_by_rotating: bool = False
    """Turn to look for a lost object."""
    search_angle: float = math.pi / 2
    """How far (rad) each way the search turns."""
    filter_coef: float = 0.1
    """Weight of a new pose in the low-pass filter (-)."""
    controller: GracefulParams = field(
        default_factory=lambda: GracefulParams(
            v_linear_max=min(GracefulParams.v_linear_max, _ROBOT.max_linear_speed)
        )
    )
    """The graceful law: Nav2's defaults, ``v_linear_max`` at most the robot's top speed (the
    default robot's here; :func:`~baobab.nav.robot_params.navigation_params` for another)."""


class FollowState(IntEnum):
    """``FollowObject.Feedback`` states."""

    NONE = 0
    INITIAL_PERCEPTION = 1
    CONTROLLING = 2
    STOPPING = 3
    RETRY = 4


class _LostError(Exception):
    """No pose of the object fresh enough."""


class FollowTask:
    """One FollowObject goal (module docstring)."""

    def __init__(
        self,
        base: MobileBase,
        poses: ObjectPoses,
        params: FollowingParams,
        *,
        topic: str,
        frame: str,
        max_duration: float,
        period: float,
    ) -> None:
        self.period = period
        self.feedback: dict[str, Any] = {}
        self.retries = 0
        self.state = FollowState.NONE
        self._base, self._poses, self._params = base, poses, params
        self._topic, self._frame, self._max_duration = topic, frame, max_duration
        self._started: float | None = None
        self._filtered: Pose2D | None = None
        self._still_since: float | None = None
        self._search: list[float] = []
        self._search_started = 0.0

    def tick(self, now: float) -> TaskOutcome | None:
        """Advance the following at sim time ``now`` (s)."""
        if self._started is None:
            self._started = now
            if not self._topic and not self._frame:
                return self._end(
                    now,
                    FollowObjectError.FAILED_TO_DETECT_OBJECT,
                    "no pose topic or target frame provided",
                )
        elapsed = now - self._started
        if 0 < self._max_duration < elapsed:
            return self._end(now, FollowObjectError.NONE, "")
        try:
            if self._search:
                return self._rotate(now)
            return self._follow(now)
        except _LostError as lost:
            return self._on_lost(now, str(lost))

    def halt(self) -> None:
        """Stop at once."""
        self._base.stop()
        self.feedback[RESULT_KEY] = FollowObject.Result(num_retries=self.retries)

    def _follow(self, now: float) -> TaskOutcome | None:
        assert self._started is not None
        p, here = self._params, self._base.pose()
        waiting = self._filtered is None and not self._frame and not self._fresh(now)
        if waiting and now - self._started <= p.detection_timeout:
            self._publish(now, FollowState.INITIAL_PERCEPTION)
            self._base.stop()
            return None
        target = self._target(now, here)
        goal = _toward(target, here, p.desired_distance)
        reached = (
            math.hypot(goal.x - here.x, goal.y - here.y) < p.linear_tolerance
            and abs(math.remainder(goal.yaw - here.yaw, math.tau)) < p.angular_tolerance
        )
        if reached:
            self._base.stop()
            self._publish(now, FollowState.STOPPING)
            if self._still_since is None:
                self._still_since = now
            timeout = p.static_object_timeout
            if timeout > 0 and now - self._still_since > timeout:
                return self._end(now, FollowObjectError.NONE, "")
            return None
        self._still_since = None
        aim = _toward(target, here, p.desired_distance - BACKWARD_PROJECTION)
        self._base.command(*velocity(p.controller, aim, here))
        self._publish(now, FollowState.CONTROLLING)
        return None

    def _fresh(self, now: float) -> bool:
        latest = self._poses.latest(self._topic)
        return latest is not None and now - latest.stamp <= self._params.detection_timeout

    def _target(self, now: float, here: Pose2D) -> Pose2D:
        """The filtered pose of the object, heading along the bearing from the robot."""
        p = self._params
        if self._frame:
            pose = self._poses.frame(self._frame)
            if pose is None:
                raise _LostError(f"no TF frame '{self._frame}'")
        else:
            latest = self._poses.latest(self._topic)
            if latest is None or now - latest.stamp > p.detection_timeout:
                raise _LostError("lost the object: no detection for the detection timeout")
            pose = latest.pose
        if p.skip_orientation:
            pose = Pose2D(x=pose.x, y=pose.y, yaw=math.atan2(pose.y - here.y, pose.x - here.x))
        previous, c = self._filtered, p.filter_coef
        if previous is not None:
            turn = math.remainder(pose.yaw - previous.yaw, math.tau)
            pose = Pose2D(
                x=previous.x + c * (pose.x - previous.x),
                y=previous.y + c * (pose.y - previous.y),
                yaw=math.remainder(previous.yaw + c * turn, math.tau),
            )
        self._filtered = pose
        return pose

    def _on_lost(self, now: float, message: str) -> TaskOutcome | None:
        self.retries += 1
        if self.retries > self._params.max_retries:
            return self._end(now, FollowObjectError.FAILED_TO_DETECT_OBJECT, message)
        if self._params.search_by_rotating and not self._search:
            yaw, angle = self._base.pose().yaw, self._params.search_angle
            self._search = [yaw + angle, yaw - angle]
            self._search_started = now
        self._publish(now, FollowState.RETRY)
        return None

    def _rotate(self, now: float) -> TaskOutcome | None:
        """Nav2's ``rotateToObject``: turn to each search heading until the object shows."""
        p = self._params
        if self._fresh(now) or (self._frame and self._poses.frame(self._frame) is not None):
            self._search = []
            return self._follow(now)
        if now - self._search_started > p.rotate_to_object_timeout:
            return self._end(now, FollowObjectError.FAILED_TO_CONTROL, "timed out rotating")
        error = math.remainder(self._search[0] - self._base.pose().yaw, math.tau)
        if abs(error) < p.angular_tolerance:
            self._search.pop(0)
            if not self._search:
                return self._end(
                    now, FollowObjectError.FAILED_TO_CONTROL, "failed to rotate to the object"
                )
            error = math.remainder(self._search[0] - self._base.pose().yaw, math.tau)
        self._base.command(0.0, rotate_towards(p.controller, error))
        self._publish(now, FollowState.RETRY)
        return None

    def _publish(self, now: float, state: FollowState) -> None:
        assert self._started is not None
        self.state = state
        self.feedback[FEEDBACK_KEY] = FollowObject.Feedback(
            state=int(state),
            following_time=Duration(seconds=now - self._started).to_msg(),
            num_retries=self.retries,
        )

    def _end(self, now: float, code: FollowObjectError, message: str) -> TaskOutcome:
        assert self._started is not None
        self._base.stop()
        self.feedback[RESULT_KEY] = FollowObject.Result(
            total_elapsed_time=Duration(seconds=now - self._started).to_msg(),
            error_code=int(code),
            num_retries=self.retries,
            error_msg=message,
        )
        if code is FollowObjectError.NONE:
            return TaskOutcome(TaskStatus.SUCCEEDED)
        return TaskOutcome(TaskStatus.FAILED, int(code), message, code.name)


def _toward(target: Pose2D, here: Pose2D, distance: float) -> Pose2D:
    """Nav2's ``getPoseAtDistance``: ``target`` moved ``distance`` m towards ``here``."""
    dx, dy = here.x - target.x, here.y - target.y
    length = math.hypot(dx, dy)
    if length < 1e-9:
        return target
    scale = distance / length
    return Pose2D(x=target.x + dx * scale, y=target.y + dy * scale, yaw=target.yaw)


class FollowingServer:
    """Following for one robot: its tasks run in the navigation server's task slot.

    Args:
        base: the robot's base.
        tasks: the navigation server's task slot.
        poses: the moving objects' topics and frames.
        params: settings; Nav2's defaults when None.
        period: s between two ticks (the controller period).
    """

    def __init__(
        self,
        base: MobileBase,
        tasks: TaskSlot,
        poses: ObjectPoses,
        params: FollowingParams | None = None,
        *,
        period: float = 0.05,
    ) -> None:
        self.params = params or FollowingParams()
        self.poses = poses
        self._base, self._tasks, self._period = base, tasks, period

    def follow_object(self, topic: str, frame: str, max_duration: float = 0.0) -> TaskHandle:
        """Follow the object whose pose is on ``topic`` (or TF ``frame``, which wins) for
        ``max_duration`` s (0: until canceled)."""
        return self._tasks.submit(
            FOLLOW_ACTION,
            lambda: FollowTask(
                self._base,
                self.poses,
                self.params,
                topic=topic,
                frame=frame,
                max_duration=max_duration,
                period=self._period,
            ),
            None,
        )

    def send_goal(self, goal: Any) -> TaskHandle:
        """The ``follow_object`` action server: Nav2's FollowObject goal messages."""
        seconds = goal.max_duration.sec + goal.max_duration.nanosec * 1e-9
        if seconds < 0:
            raise GoalRejectedError(
                f"max_duration {seconds:g} s is negative", FollowObjectError.UNKNOWN
            )
        return self.follow_object(goal.pose_topic, goal.tracked_frame, seconds)


__all__ = ["FOLLOW_ACTION", "FollowState", "FollowTask", "FollowingParams", "FollowingServer"]
