"""Nav2's behaviour-tree action and condition nodes over one navigation's blackboard.

:class:`NavigationContext` is the blackboard a navigation tree shares: goals, the current path,
each action's latest result and the recovery count. The nodes are the ones Nav2's default
trees use: ComputePathToPose, ComputePathThroughPoses, RemovePassedGoals, FollowPath,
ClearEntireCostmap, GoalUpdated, and the behaviour-server actions (Spin, Wait, BackUp) through
:class:`BehaviorLeaf`. Like Nav2's BT action nodes, each action writes its error code under its
key (``compute_path``, ``follow_path``, ``spin``, ...) and resets it to 0 when it succeeds.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import py_trees

from baobab.nav.behaviors import Behavior
from baobab.nav.bt import Clock, Leaf
from baobab.nav.controller_server import PathFollower
from baobab.nav.errors import NavigationError, reported_error_code
from baobab.nav.path import Path
from baobab.sim.tasks import TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D

Status = py_trees.common.Status

PLANNER_RECOVERABLE_CODES = frozenset({200, 207, 208, 300, 307, 308})
"""Planner codes a recovery may fix: UNKNOWN, TIMEOUT, NO_VALID_PATH (both planner actions)."""
CONTROLLER_RECOVERABLE_CODES = frozenset({100, 104, 105, 106})
"""Controller codes a recovery may fix: UNKNOWN, PATIENCE_EXCEEDED, FAILED_TO_MAKE_PROGRESS,
NO_VALID_CONTROL."""


class PlanningServices(Protocol):
    """What the navigation trees ask of the navigation server."""

    def robot_pose(self) -> Pose2D:
        """The robot's pose in the map frame."""
        ...

    def compute_path(self, start: Pose2D | None, goal: Pose2D) -> Path:
        """A path from ``start`` (None: the robot) to ``goal``, or NavigationError."""
        ...

    def compute_path_through_poses(self, start: Pose2D | None, goals: Sequence[Pose2D]) -> Path:
        """A path through ``goals`` in order, or NavigationError."""
        ...

    def clear_costmaps(self, which: str) -> None:
        """Clear the ``local``, ``global`` or ``all`` costmaps."""
        ...


@dataclass
class NavigationMetrics:
    """Run totals the server keeps for reports.

    Attributes:
        distance_driven: ground-truth distance (m) the base travelled, sampled at 20 Hz.
        planned_path_length: sum over navigation goals of the length (m) of the first path
            planned for each.
        number_of_recoveries: recovery actions started (each costmap clear counts, as in Nav2).
        plans: paths computed by the navigation trees.
        replans: of those, the ones after a goal's first path.
    """

    distance_driven: float = 0.0
    planned_path_length: float = 0.0
    number_of_recoveries: int = 0
    plans: int = 0
    replans: int = 0


@dataclass
class NavigationContext:
    """One navigation's blackboard: goals, current path, error codes, counters."""

    clock: Clock
    goals: list[Pose2D]
    metrics: NavigationMetrics
    goal_revision: int = 0
    planned_revision: int = -1
    path: Path | None = None
    number_of_recoveries: int = 0
    plans: int = 0
    errors: dict[str, TaskOutcome] = field(default_factory=dict)

    def set_path(self, path: Path) -> None:
        """Publish a new path for the current goal."""
        self.path = path
        self.planned_revision = self.goal_revision
        self.plans += 1
        self.metrics.plans += 1
        if self.plans == 1:
            self.metrics.planned_path_length += path.length()
        else:
            self.metrics.replans += 1

    def goal_changed_since_plan(self) -> bool:
        """True when the goal was replaced after the current path was planned."""
        return self.planned_revision != self.goal_revision

    def record(self, key: str, outcome: TaskOutcome) -> None:
        """Store an action's result under ``key`` (``compute_path``, ``follow_path``, ...)."""
        self.errors[key] = outcome

    def record_error(self, key: str, error: NavigationError) -> None:
        """Store an action's failure."""
        self.errors[key] = TaskOutcome(
            TaskStatus.FAILED, int(error.code), error.message, error.code_name
        )

    def error_code(self, key: str) -> int:
        """The latest code of action ``key`` (0 when it last succeeded or never ran)."""
        outcome = self.errors.get(key)
        return 0 if outcome is None else outcome.error_code

    def count_recovery(self) -> None:
        """A recovery action started."""
        self.number_of_recoveries += 1
        self.metrics.number_of_recoveries += 1

    def planner_recovery_helps(self) -> bool:
        """Nav2's ``WouldAPlannerRecoveryHelp``."""
        return self.error_code("compute_path") in PLANNER_RECOVERABLE_CODES

    def controller_recovery_helps(self) -> bool:
        """Nav2's ``WouldAControllerRecoveryHelp``."""
        return self.error_code("follow_path") in CONTROLLER_RECOVERABLE_CODES

    def reported_failure(self) -> TaskOutcome | None:
        """The failure with the numerically lowest non-zero code, if any."""
        code = reported_error_code(outcome.error_code for outcome in self.errors.values())
        return next((o for o in self.errors.values() if o.error_code == code), None)


class _ContextLeaf(Leaf):
    def __init__(self, name: str, context: NavigationContext) -> None:
        super().__init__(name=name)
        self.context = context


class _ComputePath(_ContextLeaf):
    """Plan synchronously; the path goes on the context, the result under ``compute_path``."""

    def __init__(self, name: str, context: NavigationContext, services: PlanningServices) -> None:
        super().__init__(name, context)
        self._services = services

    def plan(self) -> Path:
        """The planner call (raises NavigationError)."""
        raise NotImplementedError

    def update(self) -> Status:
        """Plan and record the result."""
        context = self.context
        try:
            path = self.plan()
        except NavigationError as error:
            context.record_error("compute_path", error)
            self.feedback_message = str(error)
            return Status.FAILURE
        context.set_path(path)
        context.record("compute_path", TaskOutcome(TaskStatus.SUCCEEDED))
        return Status.SUCCESS


class ComputePathToPose(_ComputePath):
    """Plan from the robot to the goal."""

    def __init__(self, context: NavigationContext, services: PlanningServices) -> None:
        super().__init__("ComputePathToPose", context, services)

    def plan(self) -> Path:
        """A path from the robot to the goal."""
        return self._services.compute_path(None, self.context.goals[-1])


class ComputePathThroughPoses(_ComputePath):
    """Plan from the robot through every remaining goal in order."""

    def __init__(self, context: NavigationContext, services: PlanningServices) -> None:
        super().__init__("ComputePathThroughPoses", context, services)

    def plan(self) -> Path:
        """A path from the robot through the remaining goals."""
        return self._services.compute_path_through_poses(None, self.context.goals)


class RemovePassedGoals(_ContextLeaf):
    """Drop leading goals within ``radius`` (m) of the robot; the last goal always stays."""

    def __init__(
        self, context: NavigationContext, services: PlanningServices, radius: float
    ) -> None:
        super().__init__("RemovePassedGoals", context)
        self._services = services
        self.radius = radius

    def update(self) -> Status:
        """Prune and succeed."""
        goals = self.context.goals
        pose = self._services.robot_pose()
        while (
            len(goals) > 1 and math.hypot(goals[0].x - pose.x, goals[0].y - pose.y) <= self.radius
        ):
            goals.pop(0)
        return Status.SUCCESS


class FollowPath(_ContextLeaf):
    """Run the controller server on the context's path; new paths are handed over as they come."""

    def __init__(self, context: NavigationContext, follower: PathFollower) -> None:
        super().__init__("FollowPath", context)
        self.follower = follower
        self._following: Path | None = None

    def initialise(self) -> None:
        """Start following the current path (a new controller goal)."""
        self._following = self.context.path
        if self._following is not None:
            self.follower.start(self._following, self.context.clock())

    def update(self) -> Status:
        """One controller cycle."""
        context = self.context
        if context.path is not None and context.path is not self._following:
            if self._following is None:
                self.follower.start(context.path, context.clock())
            else:
                self.follower.set_path(context.path)
            self._following = context.path
        outcome = self.follower.cycle(context.clock())
        if outcome is None:
            return Status.RUNNING
        context.record("follow_path", outcome)
        self.feedback_message = outcome.error_msg
        return Status.SUCCESS if outcome.status is TaskStatus.SUCCEEDED else Status.FAILURE

    def terminate(self, new_status: Status) -> None:
        """Stop the robot when halted while running."""
        if new_status is Status.INVALID and self.status is Status.RUNNING:
            self.follower.halt()


class ClearEntireCostmap(_ContextLeaf):
    """Clear the ``local`` or ``global`` costmap; counts as a recovery."""

    def __init__(
        self, name: str, context: NavigationContext, services: PlanningServices, which: str
    ) -> None:
        super().__init__(name, context)
        self._services = services
        self.which = which

    def update(self) -> Status:
        """Clear and succeed."""
        self.context.count_recovery()
        self._services.clear_costmaps(self.which)
        return Status.SUCCESS


class GoalUpdated(_ContextLeaf):
    """SUCCESS when the goal was replaced since this node's activation began."""

    def __init__(self, context: NavigationContext) -> None:
        super().__init__("GoalUpdated", context)
        self._seen: int | None = None

    def update(self) -> Status:
        """Compare the goal revision with the one seen first."""
        revision = self.context.goal_revision
        if self._seen is None or revision == self._seen:
            self._seen = revision
            return Status.FAILURE
        self._seen = revision
        return Status.SUCCESS

    def terminate(self, new_status: Status) -> None:
        """A reset forgets the goal seen."""
        if new_status is Status.INVALID:
            self._seen = None


class BehaviorLeaf(_ContextLeaf):
    """A behaviour-server action inside the tree, cycled at the behaviour's own rate (10 Hz)."""

    def __init__(
        self,
        name: str,
        context: NavigationContext,
        make: Callable[[], Behavior],
        error_key: str,
    ) -> None:
        super().__init__(name, context)
        self._make = make
        self.error_key = error_key
        self.behavior: Behavior | None = None
        self._next_cycle = 0.0

    def initialise(self) -> None:
        """A fresh behaviour goal; counts as a recovery."""
        self.behavior = self._make()
        self.context.count_recovery()
        self._next_cycle = self.context.clock()

    def update(self) -> Status:
        """Cycle the behaviour when due."""
        now = self.context.clock()
        behavior = self.behavior
        if behavior is None:
            return Status.INVALID
        if now < self._next_cycle - 1e-9:
            return Status.RUNNING
        self._next_cycle = now + behavior.period
        outcome = behavior.tick(now)
        if outcome is None:
            return Status.RUNNING
        self.context.record(self.error_key, outcome)
        self.feedback_message = outcome.error_msg
        return Status.SUCCESS if outcome.status is TaskStatus.SUCCEEDED else Status.FAILURE

    def terminate(self, new_status: Status) -> None:
        """Stop the robot when halted while running."""
        if new_status is Status.INVALID and self.status is Status.RUNNING and self.behavior:
            self.behavior.halt()
