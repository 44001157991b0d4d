"""NavigateToPose and NavigateThroughPoses: behaviour trees shaped like Nav2's default trees.

The tree (reference/nav2.md §4.2; Jazzy's gating of recoveries by error code)::

    RecoveryNode(6) NavigateRecovery
    ├─ PipelineSequence NavigateWithReplanning
    │   ├─ RateController(1 Hz; 0.333 Hz through poses)
    │   │   └─ RecoveryNode(1) ComputePathToPose
    │   │       ├─ ComputePathToPose   (through poses: ReactiveSequence[RemovePassedGoals(0.7 m),
    │   │       │                                                  ComputePathThroughPoses])
    │   │       └─ Sequence[WouldAPlannerRecoveryHelp, ClearEntireCostmap(global)]
    │   └─ RecoveryNode(1) FollowPath
    │       ├─ FollowPath
    │       └─ Sequence[WouldAControllerRecoveryHelp, ClearEntireCostmap(local)]
    └─ Sequence
        ├─ ReactiveFallback[WouldAControllerRecoveryHelp, WouldAPlannerRecoveryHelp]
        └─ ReactiveFallback RecoveryFallback
            ├─ GoalUpdated
            └─ RoundRobin RecoveryActions
                ├─ Sequence[ClearEntireCostmap(local), ClearEntireCostmap(global)]
                ├─ Spin(1.57)
                ├─ Wait(5 s)
                └─ BackUp(0.30 m, 0.15 m/s)

Only recoverable codes start a recovery: planner UNKNOWN, TIMEOUT, NO_VALID_PATH; controller
UNKNOWN, PATIENCE_EXCEEDED, FAILED_TO_MAKE_PROGRESS, NO_VALID_CONTROL. Anything else (a goal
in an obstacle or off the map, an invalid path) fails the navigation at once. Like Nav2's
blackboard, :class:`NavigationContext` keeps each action's latest error code (reset when the
action succeeds); the task reports the numerically lowest one (§2.7).

The tree ticks at the controller rate (20 Hz), so the FollowPath leaf runs one controller
cycle per tick; the recovery behaviours run at the behaviour server's 10 Hz inside it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import py_trees
from py_trees.behaviour import Behaviour

from baobab.nav.behaviors import BackUp, BehaviorContext, Spin, Wait
from baobab.nav.bt import (
    Clock,
    Condition,
    PipelineSequence,
    RateController,
    ReactiveFallback,
    RecoveryNode,
    RoundRobin,
    reactive_sequence,
    sequence,
    tick_child,
)
from baobab.nav.bt_nodes import (
    CONTROLLER_RECOVERABLE_CODES,
    PLANNER_RECOVERABLE_CODES,
    BehaviorLeaf,
    ClearEntireCostmap,
    ComputePathThroughPoses,
    ComputePathToPose,
    FollowPath,
    GoalUpdated,
    NavigationContext,
    NavigationMetrics,
    PlanningServices,
    RemovePassedGoals,
)
from baobab.nav.controller_server import PathFollower
from baobab.nav.errors import NavigateThroughPosesError, NavigateToPoseError
from baobab.nav.feedback import PathProgress, SpeedFilter, estimated_time_remaining
from baobab.nav.waypoints import WaypointStatus
from baobab.sim.tasks import TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D

__all__ = [
    "CONTROLLER_RECOVERABLE_CODES",
    "PLANNER_RECOVERABLE_CODES",
    "NavigateTask",
    "NavigationContext",
    "NavigationMetrics",
    "NavigatorParams",
    "PlanningServices",
    "navigation_tree",
]

Status = py_trees.common.Status


@dataclass(frozen=True)
class NavigatorParams:
    """BT navigator settings: Nav2's default trees and feedback (Hz, m, s, rad)."""

    replanning_hz: float = 1.0
    through_poses_replanning_hz: float = 0.333
    number_of_retries: int = 6
    remove_passed_goals_radius: float = 0.7
    spin_dist: float = 1.57
    wait_duration: float = 5.0
    backup_dist: float = 0.30
    backup_speed: float = 0.15
    recovery_time_allowance: float = 10.0
    speed_filter_duration: float = 0.3
    distance_search_window: float = 2.0


def navigation_tree(
    context: NavigationContext,
    services: PlanningServices,
    follower: PathFollower,
    behaviors: BehaviorContext,
    params: NavigatorParams,
    *,
    through_poses: bool,
) -> Behaviour:
    """Nav2's ``navigate_{to,through}_pose(s)_w_replanning_and_recovery`` tree."""
    pipeline = _replanning_pipeline(context, services, follower, params, through_poses)
    recovery = _recovery(context, services, behaviors, params)
    return RecoveryNode("NavigateRecovery", params.number_of_retries, [pipeline, recovery])


def _clear(
    context: NavigationContext, services: PlanningServices, name: str, which: str
) -> Behaviour:
    return ClearEntireCostmap(name, context, services, which)


def _replanning_pipeline(
    context: NavigationContext,
    services: PlanningServices,
    follower: PathFollower,
    params: NavigatorParams,
    through_poses: bool,
) -> Behaviour:
    """``NavigateWithReplanning``: plan at the replanning rate, follow the path; each with its
    contextual costmap clearing."""
    planner_helps = Condition("WouldAPlannerRecoveryHelp", context.planner_recovery_helps)
    controller_helps = Condition("WouldAControllerRecoveryHelp", context.controller_recovery_helps)
    plan: Behaviour
    if through_poses:
        plan = reactive_sequence(
            "PlanThroughPoses",
            [
                RemovePassedGoals(context, services, params.remove_passed_goals_radius),
                ComputePathThroughPoses(context, services),
            ],
        )
        hz = params.through_poses_replanning_hz
    else:
        plan = ComputePathToPose(context, services)
        hz = params.replanning_hz
    clear_global = _clear(context, services, "ClearGlobalCostmap-Context", "global")
    planning = RecoveryNode(
        "ComputePathToPose",
        1,
        [plan, sequence("ClearGlobalContext", [planner_helps, clear_global])],
    )
    clear_local = _clear(context, services, "ClearLocalCostmap-Context", "local")
    following = RecoveryNode(
        "FollowPath",
        1,
        [
            FollowPath(context, follower),
            sequence("ClearLocalContext", [controller_helps, clear_local]),
        ],
    )
    rate = RateController(
        "RateController", planning, hz, context.clock, tick_now=context.goal_changed_since_plan
    )
    return PipelineSequence("NavigateWithReplanning", [rate, following])


def _recovery(
    context: NavigationContext,
    services: PlanningServices,
    behaviors: BehaviorContext,
    params: NavigatorParams,
) -> Behaviour:
    """``Recovery``: while a recovery would help and the goal is unchanged, the next of clear
    costmaps, spin, wait and back up in turn."""
    p = params
    clearing = sequence(
        "ClearingActions",
        [
            _clear(context, services, "ClearLocalCostmap-Subtree", "local"),
            _clear(context, services, "ClearGlobalCostmap-Subtree", "global"),
        ],
    )
    actions = RoundRobin(
        "RecoveryActions",
        [
            clearing,
            BehaviorLeaf(
                "Spin",
                context,
                lambda: Spin(behaviors, p.spin_dist, p.recovery_time_allowance),
                "spin",
            ),
            BehaviorLeaf("Wait", context, lambda: Wait(behaviors, p.wait_duration), "wait"),
            BehaviorLeaf(
                "BackUp",
                context,
                lambda: BackUp(behaviors, p.backup_dist, p.backup_speed, p.recovery_time_allowance),
                "backup",
            ),
        ],
    )
    would_help = ReactiveFallback(
        "RecoveryWouldHelp",
        [
            Condition("WouldAControllerRecoveryHelp", context.controller_recovery_helps),
            Condition("WouldAPlannerRecoveryHelp", context.planner_recovery_helps),
        ],
    )
    return sequence(
        "Recovery",
        [would_help, ReactiveFallback("RecoveryFallback", [GoalUpdated(context), actions])],
    )


class NavigateTask:
    """One NavigateToPose or NavigateThroughPoses goal: its tree, blackboard and feedback.

    Satisfies the server's task protocol (``period``, ``feedback``, ``tick``, ``halt``) and
    accepts same-type preemption in place (:meth:`preempt`).

    Args:
        goals: the goal (one pose) or the poses to pass through.
        through_poses: NavigateThroughPoses when True.
        services: planner and costmap services of the server.
        follower: the controller server.
        behaviors: the behaviour server's context for the recoveries.
        params: navigator settings.
        metrics: the server's run totals.
        clock: sim time (s).
    """

    def __init__(
        self,
        goals: Sequence[Pose2D],
        *,
        through_poses: bool,
        services: PlanningServices,
        follower: PathFollower,
        behaviors: BehaviorContext,
        params: NavigatorParams,
        metrics: NavigationMetrics,
        clock: Clock,
    ) -> None:
        self.through_poses = through_poses
        self.context = NavigationContext(clock=clock, goals=list(goals), metrics=metrics)
        self.root = navigation_tree(
            self.context, services, follower, behaviors, params, through_poses=through_poses
        )
        self.period = 1.0 / follower.params.controller_frequency
        self.feedback: dict[str, Any] = {}
        self._services = services
        self._base = follower.base
        self._follower = follower
        self._progress = PathProgress(params.distance_search_window)
        self._speed = SpeedFilter(params.speed_filter_duration)
        self._start_time: float | None = None
        self._poses = list(goals)
        self._passed = -1

    def preempt(self, goals: Sequence[Pose2D]) -> None:
        """Take a new goal in place: the tree keeps running, time and recoveries restart."""
        context = self.context
        context.goals = list(goals)
        self._poses = list(goals)
        self._passed = -1
        context.goal_revision += 1
        context.number_of_recoveries = 0
        context.plans = 0
        self._start_time = None

    def tick(self, now: float) -> TaskOutcome | None:
        """Tick the tree once at sim time ``now`` (s); the outcome when it finished."""
        if self._start_time is None:
            self._start_time = now
        tick_child(self.root)
        self._update_feedback(now)
        outcome = self._outcome()
        if outcome is not None:
            self._update_statuses(outcome)
        return outcome

    def _outcome(self) -> TaskOutcome | None:
        status = self.root.status
        if status is Status.SUCCESS:
            return TaskOutcome(TaskStatus.SUCCEEDED)
        if status is Status.FAILURE:
            failure = self.context.reported_failure()
            if failure is not None:
                return failure
            codes = NavigateThroughPosesError if self.through_poses else NavigateToPoseError
            return TaskOutcome(
                TaskStatus.FAILED, int(codes.UNKNOWN), "navigation failed", codes.UNKNOWN.name
            )
        return None

    def halt(self) -> None:
        """Halt the tree (its running leaves stop the robot); the poses not passed failed."""
        if self.root.status is Status.RUNNING:
            self.root.stop(Status.INVALID)
        self._update_statuses(TaskOutcome(TaskStatus.CANCELED))

    def _update_statuses(self, final: TaskOutcome | None = None) -> None:
        """NavigateThroughPoses' ``waypoint_statuses``: the poses the robot passed (pruned
        from the goal list) are COMPLETED, the others PENDING until the end, then COMPLETED
        on success or FAILED, with the navigation's error, otherwise."""
        if not self.through_poses:
            return
        passed = len(self._poses) - len(self.context.goals)
        if final is None and passed == self._passed:
            return
        self._passed = passed
        rest, code, message = WaypointStatus.PENDING, 0, ""
        if final is not None:
            succeeded = final.status is TaskStatus.SUCCEEDED
            rest = WaypointStatus.COMPLETED if succeeded else WaypointStatus.FAILED
            code, message = final.error_code, final.error_msg
        self.feedback["waypoint_statuses"] = [
            {"status": WaypointStatus.COMPLETED, "index": index, "pose": pose}
            if index < passed
            else {
                "status": rest,
                "index": index,
                "pose": pose,
                "error_code": code if rest == WaypointStatus.FAILED else 0,
                "error_msg": message if rest == WaypointStatus.FAILED else "",
            }
            for index, pose in enumerate(self._poses)
        ]

    def _update_feedback(self, now: float) -> None:
        context = self.context
        pose = self._services.robot_pose()
        speed = self._speed.add(now, self._base.body_velocity()[0])
        path = context.path
        if path is None:
            distance = 0.0
        elif path is self._follower.located_path:
            distance = self._follower.remaining_length()  # the controller just located the robot
        else:
            distance = self._progress.distance_remaining(path, pose.x, pose.y)
        feedback = self.feedback
        feedback["current_pose"] = pose
        start = now if self._start_time is None else self._start_time
        feedback["navigation_time"] = now - start
        feedback["estimated_time_remaining"] = estimated_time_remaining(distance, speed)
        feedback["distance_remaining"] = distance
        feedback["number_of_recoveries"] = context.number_of_recoveries
        tracking = self._follower.feedback.get("tracking_feedback")
        if tracking is not None and path is self._follower.located_path:
            feedback["tracking_feedback"] = dict(tracking)
        if self.through_poses:
            feedback["number_of_poses_remaining"] = len(context.goals)
            self._update_statuses()
