"""The tasks a :class:`~baobab.nav.navigator.BasicNavigator` tracks: sent, polled, canceled.

As in Nav2, the navigator tracks one task at a time (a new send replaces the tracked one) and,
beside it, one route-tracking task (``getAndTrackRoute``), whose feedback messages queue up
until read. This module holds that state and the Simple Commander calls over it:
``isTaskComplete``, ``getFeedback``, ``getResult``, ``cancelTask``, the task-error API, and
the attributes scripts read (``feedback``, ``status``, ``goal_handle``, ``result_future``,
``initial_pose_received``, ``last_action_error_code`` / ``_msg``, the route's).

A task runs on the navigation server (a :class:`~baobab.sim.tasks.TaskHandle` whose feedback
is a dict of plain values, turned into messages by :mod:`baobab.nav.navigator_feedback`) or on
a plugged-in :class:`~baobab.nav.interfaces.ActionServer`, whose handle carries the action's
messages themselves (keys ``feedback``, ``queue`` and ``result``).
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal

from baobab.nav.errors import NavigationError
from baobab.nav.interfaces import FEEDBACK_KEY, FEEDBACK_QUEUE_KEY, RESULT_KEY
from baobab.nav.navigator_core import POLL_HORIZON, NavigatorCore, TaskResult
from baobab.nav.navigator_feedback import (
    RunningTask,
    feedback_message,
    goal_status,
    result_message,
    unknown_code,
)
from baobab.nav.navigator_handles import GoalHandle, ResultFuture
from baobab.nav.navigator_messages import GoalRejectedError
from baobab.nav.rosmsg import Message
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus

_RESULTS = {
    TaskStatus.SUCCEEDED: TaskResult.SUCCEEDED,
    TaskStatus.CANCELED: TaskResult.CANCELED,
    TaskStatus.FAILED: TaskResult.FAILED,
}


@dataclass
class TrackedGoal:
    """One sent goal: its server handle, or the outcome of a rejected send.

    Attributes:
        kind: the task.
        handle: the server's handle; None when the send was rejected.
        rejection: how a rejected send ended.
        external: served by a plugged-in action server (its handle holds messages).
        goal_handle: the rclpy-shaped handle scripts see.
        read_from_queue: how many queued feedback messages were read (route tracking).
    """

    kind: RunningTask
    handle: TaskHandle | None
    rejection: TaskOutcome | None = None
    external: bool = False
    goal_handle: GoalHandle | None = None
    read_from_queue: int = field(default=0)

    def outcome(self) -> TaskOutcome | None:
        """How the goal ended; None while it runs."""
        return self.rejection if self.handle is None else self.handle.outcome


class NavigatorTracking(NavigatorCore):
    """Task tracking for :class:`~baobab.nav.navigator.BasicNavigator` (module docstring)."""

    def _setup(self) -> None:
        super()._setup()
        self._goal: TrackedGoal | None = None
        self._route: TrackedGoal | None = None
        self._goals_sent = 0
        self._feedback_hidden_at: float | None = None
        self._task_error: tuple[int, str] | None = None
        self._task_error_until_outcome = False

    # -- sending ------------------------------------------------------------------------------

    def _send(
        self, kind: RunningTask, submit: Callable[[], TaskHandle], *, external: bool = False
    ) -> RunningTask | None:
        """Hand a goal to its server; the task, or None (logged, task error set) if rejected.

        A rejected send also cancels the task that was running (not for the route task, which
        runs beside it), so the robot is never left driving a goal the script no longer tracks.
        """
        server = self._live_server()
        self._feedback_hidden_at = None
        self._set_task_error(None)
        try:
            handle = submit()
        except GoalRejectedError as exc:
            if kind is not RunningTask.COMPUTE_AND_TRACK_ROUTE:
                server.cancel()
            unknown = unknown_code(kind)
            code = int(exc.code if exc.code is not None else unknown)
            message = f"{kind.name} goal was rejected: {exc}"
            self.error(message)
            outcome = TaskOutcome(TaskStatus.FAILED, code, message)
            self._track(TrackedGoal(kind, None, outcome, external))
            self._set_task_error((code, message))
            return None
        self._track(TrackedGoal(kind, handle, external=external))
        return kind

    def _track(self, goal: TrackedGoal) -> None:
        self._goals_sent += 1
        future = None
        if goal.handle is not None:
            future = ResultFuture(goal.outcome, lambda outcome: self._result_of(goal, outcome))
        handle = goal.handle
        goal.goal_handle = GoalHandle(
            handle is not None,
            self._stamp(),
            goal.outcome,
            future,
            (lambda: None) if handle is None else handle.cancel,
            self._goals_sent,
        )
        if goal.kind is RunningTask.COMPUTE_AND_TRACK_ROUTE:
            self._route = goal
        else:
            self._goal = goal

    def _result_of(self, goal: TrackedGoal, outcome: TaskOutcome) -> Message:
        handle = goal.handle
        values = {} if handle is None else handle.feedback
        if goal.external and RESULT_KEY in values:
            result: Message = values[RESULT_KEY]
            return result
        elapsed = 0.0
        if handle is not None and handle.started_at is not None and handle.ended_at is not None:
            elapsed = handle.ended_at - handle.started_at
        return result_message(goal.kind, outcome, values, elapsed)

    # -- polling ------------------------------------------------------------------------------

    def _watched(self, task: object, tracking_route: bool) -> TrackedGoal | None:
        if task is RunningTask.COMPUTE_AND_TRACK_ROUTE or tracking_route:
            return self._route
        return self._goal

    def _tracked_goal_ended(self) -> bool:
        goal = self._goal
        return goal is not None and goal.outcome() is not None

    def isTaskComplete(
        self,
        task: RunningTask | Literal[False] | None = RunningTask.NONE,
        *,
        trackingRoute: bool = False,
    ) -> bool:
        """Advance the sim up to 0.1 s; True once the task ended (or if there is none).

        ``task`` is Kilted's argument: ``RunningTask.COMPUTE_AND_TRACK_ROUTE`` polls the route
        task, anything else the tracked one; ``trackingRoute=True`` is the name a 2025
        development version used. A rejected send (``task`` None) is complete at once, where
        Nav2 returns False for ever.
        """
        goal = self._watched(task, trackingRoute)
        if goal is None or goal.outcome() is not None:
            return True
        self._advance(POLL_HORIZON, lambda: goal.outcome() is not None, changes_in_callbacks=True)
        outcome = goal.outcome()
        if outcome is None:
            return False
        if outcome.status is not TaskStatus.SUCCEEDED:
            self.debug(
                f"Task with failed with status code: {outcome.status.name}:"
                f"{outcome.error_code}:{outcome.error_msg}"
            )
        return True

    isNavComplete = isTaskComplete

    def getFeedback(
        self, task: RunningTask | None = RunningTask.NONE, *, trackingRoute: bool = False
    ) -> Message | None:
        """The tracked task's latest feedback message, None before the first one.

        For the route task (``RunningTask.COMPUTE_AND_TRACK_ROUTE``) the oldest feedback not
        read yet, None when all were read: route feedback queues up, as in Nav2.
        """
        goal = self._watched(task, trackingRoute)
        if goal is None or goal.handle is None:
            return None
        if goal.kind is RunningTask.COMPUTE_AND_TRACK_ROUTE:
            queue = goal.handle.feedback.get(FEEDBACK_QUEUE_KEY, [])
            if goal.read_from_queue >= len(queue):
                return None
            goal.read_from_queue += 1
            message: Message = queue[goal.read_from_queue - 1]
            return message
        if self._feedback_hidden(goal):
            return None
        if goal.external:
            return goal.handle.feedback.get(FEEDBACK_KEY)
        return feedback_message(goal.kind, goal.handle.feedback, self._stamped)

    def _feedback_hidden(self, goal: TrackedGoal) -> bool:
        """Feedback is hidden from a clear (cancel, clearPreviousState) until the task reports
        again: once sim time has passed while it still ran."""
        hidden_at = self._feedback_hidden_at
        if hidden_at is None:
            return False
        if hidden_at < 0 or self._sim_seconds() <= hidden_at:
            return True
        self._feedback_hidden_at = None
        return False

    def getResult(self) -> TaskResult:
        """How the last task ended; UNKNOWN while it runs or before any task."""
        goal = self._goal
        outcome = None if goal is None else goal.outcome()
        return TaskResult.UNKNOWN if outcome is None else _RESULTS[outcome.status]

    def cancelTask(self) -> None:
        """Cancel the tracked task and the route task: they end CANCELED, the robot stops."""
        self.info("Canceling current task.")
        self._live_server()
        handles = [g.handle for g in (self._goal, self._route) if g is not None and g.handle]
        if not handles:
            self._set_task_error((0, "Cancel task failed, goal handle is None"))
            return
        for handle in handles:
            handle.cancel()
        self._feedback_hidden_at = -1.0
        self._set_task_error(None)

    cancelNav = cancelTask

    # -- task errors --------------------------------------------------------------------------

    def getTaskError(self) -> tuple[int, str]:
        """``(error_code, error_msg)`` of the last task or request that did not succeed, else
        ``(0, '')``: a planning or smoothing request's sets it too, as in Nav2 Kilted."""
        goal = self._goal
        outcome = None if goal is None else goal.outcome()
        failed = outcome is not None and outcome.status is not TaskStatus.SUCCEEDED
        if self._task_error is not None and not (failed and self._task_error_until_outcome):
            return self._task_error
        if outcome is None or not failed:
            return (0, "")
        return (outcome.error_code, outcome.error_msg)

    def setTaskError(self, error_code: int, error_msg: str) -> None:
        """Make ``(error_code, error_msg)`` the task error (Nav2 Kilted's setter)."""
        self._set_task_error((int(error_code), str(error_msg)))

    def clearTaskError(self) -> None:
        """Reset the task error to ``(0, '')`` (Nav2 Kilted)."""
        self._set_task_error((0, ""))

    def clearPreviousState(self) -> None:
        """Reset the task error and hide the feedback until the task reports again (Rolling)."""
        self.clearTaskError()
        goal = self._goal
        ended = goal is None or goal.outcome() is not None
        self._feedback_hidden_at = -1.0 if ended else self._sim_seconds()

    getLastError = getTaskError
    setLastError = setTaskError
    clearLastError = clearTaskError

    def _set_task_error(self, error: tuple[int, str] | None) -> None:
        """What :meth:`getTaskError` returns (None: the last task's own error) until the next
        task starts or, when set while a task runs, until that task fails (as Nav2's
        ``setTaskError``, which the client calls again when it sees a task fail)."""
        goal = self._goal
        self._task_error = error
        self._task_error_until_outcome = goal is not None and goal.outcome() is None

    def _request_failed(
        self, what: str, exc: GoalRejectedError | NavigationError, unknown: enum.IntEnum
    ) -> None:
        """Log a planning or smoothing request's failure and make it the task error; a
        request refused before it reached the server has the action's UNKNOWN code."""
        self.warn(f"{what} failed: {exc}")
        if isinstance(exc, NavigationError):
            self._set_task_error((int(exc.code), exc.message))
        else:
            self._set_task_error((int(unknown if exc.code is None else exc.code), str(exc)))

    # -- attributes scripts read --------------------------------------------------------------

    @property
    def feedback(self) -> Message | None:
        """The tracked task's latest feedback (Nav2's attribute; :meth:`getFeedback`)."""
        return self.getFeedback()

    @property
    def status(self) -> int | None:
        """The ``action_msgs/GoalStatus`` code of the tracked task once it ended, else None."""
        goal = self._goal
        outcome = None if goal is None else goal.outcome()
        return None if outcome is None else int(goal_status(outcome))

    @property
    def goal_handle(self) -> GoalHandle | None:
        """The tracked task's goal handle (``accepted``, ``status``, ``goal_id``)."""
        return None if self._goal is None else self._goal.goal_handle

    @property
    def result_future(self) -> ResultFuture | None:
        """The tracked task's result future (``.done()``, ``.result().result``); None before
        any send and after a rejected one."""
        handle = self.goal_handle
        return None if handle is None else handle.get_result_async()

    @property
    def route_goal_handle(self) -> GoalHandle | None:
        """The route task's goal handle."""
        return None if self._route is None else self._route.goal_handle

    @property
    def route_result_future(self) -> ResultFuture | None:
        """The route task's result future."""
        handle = self.route_goal_handle
        return None if handle is None else handle.get_result_async()

    @property
    def route_feedback(self) -> list[Message]:
        """The route feedback messages not read yet by :meth:`getFeedback`."""
        route = self._route
        if route is None or route.handle is None:
            return []
        return list(route.handle.feedback.get(FEEDBACK_QUEUE_KEY, [])[route.read_from_queue :])

    @property
    def initial_pose_received(self) -> bool:
        """Always True: the simulation localises perfectly, so ``amcl_pose`` is there at once."""
        return True

    @property
    def last_action_error_code(self) -> int:
        """The task error's code (Nav2's attribute behind :meth:`getTaskError`)."""
        return self.getTaskError()[0]

    @last_action_error_code.setter
    def last_action_error_code(self, code: int) -> None:
        self.setTaskError(code, self.getTaskError()[1])

    @property
    def last_action_error_msg(self) -> str:
        """The task error's message."""
        return self.getTaskError()[1]

    @last_action_error_msg.setter
    def last_action_error_msg(self, message: str) -> None:
        self.setTaskError(self.getTaskError()[0], message)
