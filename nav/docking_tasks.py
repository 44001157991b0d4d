"""Nav2's DockRobot and UndockRobot goals as server tasks, ticked at the controller rate.

Docking (``opennav_docking``'s ``dockRobot``, reference/nav2_ros_facts.md §6):

0. a base the charger already charges is docked: success at once;
1. NAV_TO_STAGING_POSE: NavigateToPose to the staging pose unless told not to or already
   within ``dock_prestaging_tolerance``; failure or ``max_staging_time`` -> FAILED_TO_STAGE;
2. INITIAL_PERCEPTION: the lidar detector looks for the dock near the database pose;
   ``initial_perception_timeout`` -> FAILED_TO_DETECT_DOCK;
3. CONTROLLING: the graceful law drives onto the detected dock pose, refined at every new
   scan, until the base is within ``docking_threshold`` of it (or charging). Detection lost for
   ``detection_timeout`` -> FAILED_TO_DETECT_DOCK; a projected path that collides, or
   ``dock_approach_timeout`` -> FAILED_TO_CONTROL;
4. WAIT_FOR_CHARGE: ``wait_charge_timeout`` -> FAILED_TO_CHARGE;
5. success.

The failures of phases 3 and 4 are retried: the base backs out to the staging pose (RETRY) and
approaches again, up to ``max_retries`` times, then the task fails with the last code. Undocking
switches charging off and backs the base out to the staging pose of where it stands, within
the undock tolerances and ``max_undocking_time``; a base that is not docked has nothing to
undock and succeeds at once (Nav2 logs "no need to undock"). A cancel or a preemption stops
the base at once (:mod:`baobab.nav.task_slot`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any

from baobab.nav.costmap import Costmap2D
from baobab.nav.dock_detection import DockDetector
from baobab.nav.docking import Charger, DockingParams, LatestScan, pose_distance, staging_pose
from baobab.nav.errors import DockRobotError, UndockRobotError
from baobab.nav.footprint import collision_mask
from baobab.nav.graceful_control import projected_poses, velocity
from baobab.nav.interfaces import FEEDBACK_KEY, RESULT_KEY, MobileBase, ServerTask
from baobab.nav.ros.nav2_msgs.action import DockRobot, UndockRobot
from baobab.nav.rostime import Duration
from baobab.sim.docks import DOCK_TYPES
from baobab.sim.tasks import TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D


class DockState(IntEnum):
    """``DockRobot.Feedback`` states."""

    NONE = 0
    NAV_TO_STAGING_POSE = 1
    INITIAL_PERCEPTION = 2
    CONTROLLING = 3
    WAIT_FOR_CHARGE = 4
    RETRY = 5


@dataclass
class DockingContext:
    """What the docking tasks share with their server (and one another)."""

    base: MobileBase
    charger: Charger
    scans: LatestScan
    navigate: Callable[[Pose2D], ServerTask]
    """Starts a NavigateToPose task."""
    local_costmap: Callable[[], Costmap2D]
    params: DockingParams
    period: float
    """s between two ticks of a docking task."""
    docked_type: str = ""
    """The type of the dock the robot docked at last (Nav2's ``curr_dock_type_``)."""
    docked_pose: Pose2D | None = field(default=None)
    """Where that dock was detected."""


@dataclass(frozen=True)
class DockTarget:
    """A validated DockRobot goal: the dock's pose and type, and how to reach it."""

    pose: Pose2D
    dock_type: str
    navigate_to_staging_pose: bool
    max_staging_time: float


class _DockingError(Exception):
    def __init__(self, code: IntEnum, message: str, *, recoverable: bool = False) -> None:
        super().__init__(message)
        self.code = code
        self.recoverable = recoverable


class DockTask:
    """One DockRobot goal (module docstring)."""

    def __init__(self, context: DockingContext, target: DockTarget | _DockingError) -> None:
        self.period = context.period
        self.feedback: dict[str, Any] = {}
        self.retries = 0
        self.state = DockState.NONE
        self._context = context
        self._target = target
        self._child: ServerTask | None = None
        self._started: float | None = None
        self._phase_started = 0.0
        self._detector: DockDetector | None = None
        self._detected: Pose2D | None = None
        self._last_seen = 0.0

    def tick(self, now: float) -> TaskOutcome | None:
        """Advance the docking at sim time ``now`` (s)."""
        if self._started is None:
            self._started = now
        try:
            outcome = self._step(now)
        except _DockingError as failure:
            if failure.recoverable:
                self.retries += 1
                if self.retries <= self._context.params.max_retries:
                    self._context.base.stop()
                    self._enter(DockState.RETRY, now)
                    self._publish(now)
                    return None
            return self._end(now, failure.code, str(failure))
        self._publish(now)
        return outcome

    def halt(self) -> None:
        """Stop at once: the navigation to staging too."""
        if self._child is not None:
            self._child.halt()
            self._child = None
        self._context.base.stop()
        self.feedback[RESULT_KEY] = DockRobot.Result(success=False, num_retries=self.retries)

    def _enter(self, state: DockState, now: float) -> None:
        self.state = state
        self._phase_started = now

    def _publish(self, now: float) -> None:
        assert self._started is not None
        self.feedback[FEEDBACK_KEY] = DockRobot.Feedback(
            state=int(self.state),
            docking_time=Duration(seconds=now - self._started).to_msg(),
            num_retries=self.retries,
        )

    def _end(self, now: float, code: IntEnum, message: str) -> TaskOutcome:
        self._publish(now)
        success = int(code) == 0
        self.feedback[RESULT_KEY] = DockRobot.Result(
            success=success, error_code=int(code), num_retries=self.retries, error_msg=message
        )
        if success:
            return TaskOutcome(TaskStatus.SUCCEEDED)
        return TaskOutcome(TaskStatus.FAILED, int(code), message, code.name)

    def _step(self, now: float) -> TaskOutcome | None:
        target = self._target
        if isinstance(target, _DockingError):
            raise target
        return _STEPS[self.state](self, now, target)

    def _start(self, now: float, target: DockTarget) -> TaskOutcome | None:
        context = self._context
        context.charger.enabled = True
        if context.charger.is_charging():
            return self._end(now, DockRobotError.NONE, "already docked and charging")
        staging = staging_pose(target.pose, context.params)
        far = (
            pose_distance(context.base.pose(), staging) >= context.params.dock_prestaging_tolerance
        )
        if target.navigate_to_staging_pose and far:
            self._child = context.navigate(staging)
            self._enter(DockState.NAV_TO_STAGING_POSE, now)
        else:
            self._enter(DockState.INITIAL_PERCEPTION, now)
        return None

    def _stage(self, now: float, target: DockTarget) -> TaskOutcome | None:
        assert self._child is not None
        if now - self._phase_started > target.max_staging_time:
            self.halt()
            raise _DockingError(DockRobotError.FAILED_TO_STAGE, "staging took too long")
        outcome = self._child.tick(now)
        if outcome is None:
            return None
        self._child = None
        if outcome.status is not TaskStatus.SUCCEEDED:
            raise _DockingError(
                DockRobotError.FAILED_TO_STAGE,
                f"navigation to the staging pose failed: {outcome.error_name} "
                f"({outcome.error_code}): {outcome.error_msg}",
            )
        self._enter(DockState.INITIAL_PERCEPTION, now)
        return None

    def _perceive(self, now: float, target: DockTarget) -> TaskOutcome | None:
        context = self._context
        context.base.stop()
        if self._detector is None:
            self._detector = DockDetector(target.pose, context.params.detector)
        scan = context.scans.take()
        found = None if scan is None else self._detector.detect(scan)
        if found is not None:
            self._detected, self._last_seen = found, now
            self._enter(DockState.CONTROLLING, now)
        elif now - self._phase_started > context.params.initial_perception_timeout:
            raise _DockingError(
                DockRobotError.FAILED_TO_DETECT_DOCK, "failed initial dock detection"
            )
        return None

    def _approach(self, now: float, target: DockTarget) -> TaskOutcome | None:
        context, params = self._context, self._context.params
        dock, here = self._detected, context.base.pose()
        assert dock is not None and self._detector is not None
        if math.hypot(here.x - dock.x, here.y - dock.y) < params.docking_threshold or (
            context.charger.is_charging()
        ):
            context.base.stop()
            context.docked_type, context.docked_pose = target.dock_type, dock
            self._enter(DockState.WAIT_FOR_CHARGE, now)
            return None
        scan = context.scans.take()
        found = None if scan is None else self._detector.detect(scan)
        if found is not None:
            self._detected, self._last_seen, dock = found, now, found
        elif (
            now - self._last_seen > params.detection_timeout
            and math.hypot(here.x - dock.x, here.y - dock.y) > params.blind_distance
        ):
            raise _DockingError(
                DockRobotError.FAILED_TO_DETECT_DOCK, "lost the dock", recoverable=True
            )
        if now - self._phase_started > params.dock_approach_timeout:
            raise _DockingError(
                DockRobotError.FAILED_TO_CONTROL,
                "timed out approaching the dock; neither docked nor charging",
                recoverable=True,
            )
        if params.use_collision_detection and self._collides(dock, here):
            raise _DockingError(
                DockRobotError.FAILED_TO_CONTROL,
                "the approach to the dock is blocked",
                recoverable=True,
            )
        context.base.command(*velocity(params.controller, dock, here))
        return None

    def _collides(self, dock: Pose2D, here: Pose2D) -> bool:
        params = self._context.params
        poses = projected_poses(params.controller, dock, here, horizon=params.projection_time)
        far = (
            (poses[:, 0] - dock.x) ** 2 + (poses[:, 1] - dock.y) ** 2
        ) ** 0.5 >= params.dock_collision_threshold
        if not far.any():
            return False
        return bool(
            collision_mask(self._context.local_costmap(), poses[far, 0], poses[far, 1]).any()
        )

    def _wait_for_charge(self, now: float, target: DockTarget) -> TaskOutcome | None:
        context = self._context
        context.base.stop()
        if context.charger.is_charging():
            return self._end(now, DockRobotError.NONE, "")
        if now - self._phase_started > context.params.wait_charge_timeout:
            raise _DockingError(
                DockRobotError.FAILED_TO_CHARGE,
                "timed out waiting for charging to start",
                recoverable=True,
            )
        return None

    def _reset_approach(self, now: float, target: DockTarget) -> TaskOutcome | None:
        params = self._context.params
        if now - self._phase_started > params.dock_approach_timeout:
            raise _DockingError(
                DockRobotError.FAILED_TO_CONTROL, "timed out resetting the approach"
            )
        staging = staging_pose(target.pose, params)
        if drive_to(self._context, staging, backward=True):
            self._last_seen = now
            self._enter(DockState.CONTROLLING, now)
        return None


_STEPS: dict[DockState, Callable[[DockTask, float, DockTarget], TaskOutcome | None]] = {
    DockState.NONE: DockTask._start,
    DockState.NAV_TO_STAGING_POSE: DockTask._stage,
    DockState.INITIAL_PERCEPTION: DockTask._perceive,
    DockState.CONTROLLING: DockTask._approach,
    DockState.WAIT_FOR_CHARGE: DockTask._wait_for_charge,
    DockState.RETRY: DockTask._reset_approach,
}
"""What a docking task does on a tick in each state (built once, not per tick)."""


def drive_to(context: DockingContext, goal: Pose2D, *, backward: bool) -> bool:
    """Command the graceful law towards ``goal``; True (and stopped) once within the undock
    tolerances (Nav2's ``getCommandToPose``)."""
    params, here = context.params, context.base.pose()
    if (
        math.hypot(here.x - goal.x, here.y - goal.y) < params.undock_linear_tolerance
        and abs(math.remainder(here.yaw - goal.yaw, math.tau)) < params.undock_angular_tolerance
    ):
        context.base.stop()
        return True
    context.base.command(*velocity(params.controller, goal, here, backward))
    return False


def failed_target(code: IntEnum, message: str) -> _DockingError:
    """A DockRobot goal that fails on its first tick with ``code``."""
    return _DockingError(code, message)


class UndockTask:
    """One UndockRobot goal (module docstring)."""

    def __init__(self, context: DockingContext, dock_type: str, max_undocking_time: float):
        self.period = context.period
        self.feedback: dict[str, Any] = {}
        self._context = context
        self._dock_type = dock_type
        self._limit = max_undocking_time
        self._started: float | None = None
        self._staging: Pose2D | None = None

    def tick(self, now: float) -> TaskOutcome | None:
        """Advance the undocking at sim time ``now`` (s)."""
        context = self._context
        if self._started is None:
            self._started = now
            outcome = self._begin()
            if outcome is not None:
                return outcome
        assert self._staging is not None
        if now - self._started > self._limit:
            return self._end(UndockRobotError.FAILED_TO_CONTROL, "undocking timed out")
        # Nav2's hasStoppedCharging: the contacts are apart once the base is back at staging.
        if drive_to(context, self._staging, backward=True) and context.charger.contact() is None:
            context.docked_type, context.docked_pose = "", None
            context.charger.enabled = True
            return self._end(UndockRobotError.NONE, "")
        return None

    def _begin(self) -> TaskOutcome | None:
        context = self._context
        dock_type = self._dock_type or context.docked_type
        if not dock_type:
            return self._end(UndockRobotError.DOCK_NOT_VALID, "no dock information to undock from")
        if dock_type not in DOCK_TYPES:
            return self._end(
                UndockRobotError.DOCK_NOT_VALID, f"dock type '{dock_type}' has no plugin"
            )
        docked = context.docked_pose
        here = context.base.pose()
        near = docked is not None and math.hypot(here.x - docked.x, here.y - docked.y) < (
            context.params.docking_threshold
        )
        if context.charger.contact() is None and not near:
            # Nav2 logs "no need to undock" and returns: nothing was to be done.
            context.docked_type, context.docked_pose = "", None
            return self._end(UndockRobotError.NONE, "the robot is not docked: nothing to undock")
        context.charger.enabled = False
        self._staging = staging_pose(here, context.params)
        return None

    def halt(self) -> None:
        """Stop at once."""
        self._context.base.stop()
        self.feedback[RESULT_KEY] = UndockRobot.Result(success=False)

    def _end(self, code: UndockRobotError, message: str) -> TaskOutcome:
        success = code is UndockRobotError.NONE
        self.feedback[RESULT_KEY] = UndockRobot.Result(
            success=success, error_code=int(code), error_msg=message
        )
        if success:
            return TaskOutcome(TaskStatus.SUCCEEDED)
        return TaskOutcome(TaskStatus.FAILED, int(code), message, code.name)
