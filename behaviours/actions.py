"""Action leaves: goal-style tasks on a capability server, and instant calls.

:class:`GoalTaskLeaf` follows the py_trees lifecycle exactly: ``initialise`` sends the goal and
keeps the :class:`~baobab.sim.tasks.TaskHandle`, ``update`` polls it and never blocks, and
``terminate(INVALID)`` (preemption by a higher-priority branch, a timeout decorator, a parallel
that finished, a halted tree) cancels a task that is still running. ``terminate`` may arrive
more than once and for a leaf that already finished, so it only cancels an in-flight task.
"""

from __future__ import annotations

from collections.abc import Callable

import py_trees

from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus

Status = py_trees.common.Status


class GoalTaskLeaf(py_trees.behaviour.Behaviour):
    """Send one goal per activation and report the task's status.

    Args:
        name: the node's label in trees and traces.
        send_goal: called in ``initialise``; sends the goal to a server and returns its handle.
            Any target that depends on the world at that moment (an object's position, the
            current tool pose) is computed inside this callable.
    """

    def __init__(self, name: str, send_goal: Callable[[], TaskHandle]) -> None:
        super().__init__(name=name)
        self._send_goal = send_goal
        self.handle: TaskHandle | None = None
        self.goals_sent = 0

    @property
    def outcome(self) -> TaskOutcome | None:
        """How the latest task ended (None while it runs or before the first goal)."""
        return None if self.handle is None else self.handle.outcome

    def initialise(self) -> None:
        """Send the goal and keep its handle."""
        self.handle = self._send_goal()
        self.goals_sent += 1
        self.feedback_message = "goal sent"

    def update(self) -> Status:
        """Map the task's status: RUNNING, SUCCEEDED -> SUCCESS, FAILED/CANCELED -> FAILURE."""
        if self.handle is None:  # py_trees always initialises before updating
            return Status.INVALID
        status = self.handle.status
        if status is TaskStatus.RUNNING:
            return Status.RUNNING
        outcome = self.handle.outcome
        if outcome is not None:
            detail = f" {outcome.error_name} ({outcome.error_code})" if outcome.error_code else ""
            self.feedback_message = f"{status.value}{detail} {outcome.error_msg}".strip()
        return Status.SUCCESS if status is TaskStatus.SUCCEEDED else Status.FAILURE

    def terminate(self, new_status: Status) -> None:
        """On preemption (``INVALID``) cancel the task if it is still running."""
        handle = self.handle
        if new_status is not Status.INVALID or handle is None:
            return
        if handle.status is TaskStatus.RUNNING and not handle.cancel_requested:
            handle.cancel()
            self.feedback_message = "canceled by preemption"


class InstantCall(py_trees.behaviour.Behaviour):
    """Call a synchronous server method once per activation and succeed.

    Used for requests that complete at once, like clearing costmaps.
    """

    def __init__(self, name: str, call: Callable[[], None]) -> None:
        super().__init__(name=name)
        self._call = call

    def update(self) -> Status:
        """Make the call and return SUCCESS."""
        self._call()
        return Status.SUCCESS


class ServiceCall(py_trees.behaviour.Behaviour):
    """Call a service once per activation: SUCCESS when it reports success, else FAILURE
    with its message as the feedback message (BT.CPP's ``RosServiceNode``)."""

    def __init__(self, name: str, call: Callable[[], tuple[bool, str]]) -> None:
        super().__init__(name=name)
        self._call = call

    def update(self) -> Status:
        """Make the call; its success decides the status."""
        success, message = self._call()
        self.feedback_message = message
        return Status.SUCCESS if success else Status.FAILURE


class Constant(py_trees.behaviour.Behaviour):
    """Return the same status on every tick (BT.CPP's AlwaysSuccess / AlwaysFailure)."""

    def __init__(self, name: str, status: Status) -> None:
        super().__init__(name=name)
        self._status = status

    def update(self) -> Status:
        """The fixed status."""
        return self._status
