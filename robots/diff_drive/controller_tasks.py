"""Goal-style tasks over the tutorial controllers: go-to-goal and Bug2 as :class:`TaskHandle`\\ s.

:class:`BaseControllerServer` is the ``base_controllers`` capability of a mobile robot: a goal
starts the matching controller and returns a handle at once; a monitor callback (20 Hz, sim
time) ends the task when the controller reports the goal reached, or fails it when the robot
has not got closer to the goal for ``progress_timeout`` seconds of sim time (stuck against an
obstacle, or Bug2 circling an island it cannot leave). Cancelling stops the base. One task
runs at a time: a new goal preempts the running one (CANCELED).

The controllers are point controllers: a goal's yaw is ignored. They are created on first use,
so a run that never asks for them adds no callbacks to the simulation.
"""

from __future__ import annotations

from dataclasses import dataclass

from baobab.robots.diff_drive.base import DiffDriveBase
from baobab.robots.diff_drive.bug2 import Bug2Controller, Bug2Params
from baobab.robots.diff_drive.controller_errors import BaseControllerError
from baobab.robots.diff_drive.go_to_goal import (
    GoToGoalController,
    GoToGoalParams,
    goal_distance,
)
from baobab.sim.lidar import Lidar
from baobab.sim.simulation import PeriodicHandle, Simulation
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D


@dataclass(frozen=True)
class ControllerTaskConfig:
    """When a base-controller task counts as stuck.

    Attributes:
        progress_timeout: the task fails after this long without progress (s of sim time).
        progress_distance: getting this much closer to the goal than ever before counts as
            progress (m).
        monitor_period: how often the task is checked (s; a multiple of the physics step).

    Raises:
        ValueError: if a figure is not positive.
    """

    progress_timeout: float = 30.0
    progress_distance: float = 0.05
    monitor_period: float = 0.05

    def __post_init__(self) -> None:
        for name in ("progress_timeout", "progress_distance", "monitor_period"):
            value = getattr(self, name)
            if not value > 0:
                raise ValueError(f"{name} must be positive, got {value}")


@dataclass
class _Task:
    handle: TaskHandle
    controller: GoToGoalController | Bug2Controller
    goal: Pose2D
    goal_point: tuple[float, float]
    start_time: float
    best_distance: float
    last_progress: float


class BaseControllerServer:
    """The ``base_controllers`` capability: go-to-goal and Bug2 as goal-style tasks.

    Args:
        sim: the simulation the base lives in.
        base: the differential-drive base to command.
        lidar: the scanner Bug2 reads.
        go_to_goal_params: gains of the go-to-goal controller (seed §6 defaults).
        bug2_params: gains and wall-following figures of Bug2 (seed §7 defaults).
        config: when a task counts as stuck.
    """

    def __init__(
        self,
        sim: Simulation,
        base: DiffDriveBase,
        lidar: Lidar,
        *,
        go_to_goal_params: GoToGoalParams | None = None,
        bug2_params: Bug2Params | None = None,
        config: ControllerTaskConfig | None = None,
    ) -> None:
        self.sim = sim
        self.base = base
        self.lidar = lidar
        self.go_to_goal_params = go_to_goal_params or GoToGoalParams()
        self.bug2_params = bug2_params or Bug2Params()
        self.config = config or ControllerTaskConfig()
        self._go_to_goal: GoToGoalController | None = None
        self._bug2: Bug2Controller | None = None
        self._monitor: PeriodicHandle | None = None
        self._task: _Task | None = None

    # -- the port ---------------------------------------------------------------------------

    def go_to_goal(self, goal: Pose2D) -> TaskHandle:
        """Drive straight at ``goal`` (x, y in m; yaw ignored) with the go-to-goal law."""
        if self._go_to_goal is None:
            self._go_to_goal = GoToGoalController(self.sim, self.base, self.go_to_goal_params)
        return self._start("go_to_goal", self._go_to_goal, goal)

    def bug2(self, goal: Pose2D) -> TaskHandle:
        """Bug2 to ``goal`` (x, y in m; yaw ignored): M-line, walls on the left when blocked."""
        if self._bug2 is None:
            self._bug2 = Bug2Controller(self.sim, self.base, self.lidar, self.bug2_params)
        return self._start("bug2", self._bug2, goal)

    # -- state -------------------------------------------------------------------------------

    @property
    def active(self) -> TaskHandle | None:
        """The running task's handle, or None."""
        return None if self._task is None else self._task.handle

    @property
    def bug2_controller(self) -> Bug2Controller | None:
        """The Bug2 controller once created (its hit and leave points), else None."""
        return self._bug2

    def close(self) -> None:
        """Cancel the running task and unregister every callback of the server."""
        if self._task is not None:
            self._task.handle.cancel()
        for controller in (self._go_to_goal, self._bug2):
            if controller is not None:
                controller.close()
        if self._monitor is not None:
            self._monitor.cancel()

    # -- internals ---------------------------------------------------------------------------

    def _start(
        self, name: str, controller: GoToGoalController | Bug2Controller, goal: Pose2D
    ) -> TaskHandle:
        if self._task is not None:
            previous = self._task
            self._task = None
            previous.controller.cancel()
            previous.handle.finish(TaskOutcome(TaskStatus.CANCELED, 0, "preempted by a new goal"))
        if self._monitor is None:
            self._monitor = self.sim.every(
                self.config.monitor_period, self._check, name="base_controller_tasks"
            )
        handle = TaskHandle(name, self._cancel)
        now = self.sim.time
        distance = goal_distance(self.base.pose(), (goal.x, goal.y))
        controller.set_goal(goal.x, goal.y)
        self._task = _Task(handle, controller, goal, (goal.x, goal.y), now, distance, now)
        self._feedback(self._task, now, distance)
        return handle

    def _cancel(self, handle: TaskHandle) -> None:
        task = self._task
        if task is not None and task.handle is handle:
            self._task = None
            task.controller.cancel()
            handle.finish(TaskOutcome(TaskStatus.CANCELED, 0, "canceled"))

    def _check(self, now: float) -> None:
        task = self._task
        if task is None:
            return
        distance = goal_distance(self.base.pose(), task.goal_point)
        self._feedback(task, now, distance)
        if task.controller.reached:
            self._end(TaskOutcome(TaskStatus.SUCCEEDED))
            return
        config = self.config
        if distance < task.best_distance - config.progress_distance:
            task.best_distance = distance
            task.last_progress = now
        elif now - task.last_progress >= config.progress_timeout:
            task.controller.cancel()
            self._end(
                _failure(
                    BaseControllerError.FAILED_TO_MAKE_PROGRESS,
                    f"{task.handle.name} made no progress toward ({task.goal.x:.2f}, "
                    f"{task.goal.y:.2f}) for {config.progress_timeout:g} s; "
                    f"{distance:.2f} m from it",
                )
            )

    def _end(self, outcome: TaskOutcome) -> None:
        task, self._task = self._task, None
        if task is not None:
            task.handle.finish(outcome)

    def _feedback(self, task: _Task, now: float, distance: float) -> None:
        task.handle.feedback.update(
            distance_remaining=distance,
            navigation_time=now - task.start_time,
            state=task.controller.state.value,
        )


def _failure(code: BaseControllerError, message: str) -> TaskOutcome:
    return TaskOutcome(TaskStatus.FAILED, int(code), message, code.name)
