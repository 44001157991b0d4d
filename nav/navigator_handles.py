"""The goal handles and futures a navigator exposes, shaped like rclpy's action client's.

Nav2 scripts reach past the Simple Commander API into ``navigator.goal_handle`` (``accepted``,
``status``, ``goal_id``) and ``navigator.result_future`` (``done()``, ``result().status``,
``result().result``). :class:`GoalHandle` and :class:`ResultFuture` answer the same way from
the navigation server's :class:`~baobab.sim.tasks.TaskHandle`; a rejected send has a handle
with ``accepted`` False and no result future, as in rclpy.
"""

from __future__ import annotations

import uuid
from collections.abc import Callable

import numpy as np

from baobab.nav.navigator_feedback import GoalStatus, goal_status
from baobab.nav.ros.unique_identifier_msgs.msg import UUID
from baobab.nav.rosmsg import Message
from baobab.nav.rostime import TimeMsg
from baobab.sim.tasks import TaskOutcome


class GetResultResponse:
    """What a goal's result future holds: the final ``status`` and the action ``result``."""

    __slots__ = ("result", "status")

    def __init__(self, status: int, result: Message) -> None:
        self.status = status
        self.result = result

    def __repr__(self) -> str:
        return f"GetResultResponse(status={self.status}, result={self.result!r})"


class Future:
    """A future that is already done (what rclpy's ``cancel_goal_async`` gives back here)."""

    def __init__(self, value: object = None) -> None:
        self._value = value

    def done(self) -> bool:
        """Always True."""
        return True

    def result(self) -> object:
        """The value."""
        return self._value


class ResultFuture:
    """The result future of one goal (``rclpy.task.Future``'s ``done()`` / ``result()``).

    Args:
        outcome: reads the goal's outcome, None while it runs.
        result: builds the action's result message of a finished goal.
    """

    def __init__(
        self,
        outcome: Callable[[], TaskOutcome | None],
        result: Callable[[TaskOutcome], Message],
    ) -> None:
        self._outcome = outcome
        self._result = result

    def done(self) -> bool:
        """True once the goal has ended."""
        return self._outcome() is not None

    def result(self) -> GetResultResponse | None:
        """The final status and result message; None while the goal runs."""
        outcome = self._outcome()
        if outcome is None:
            return None
        return GetResultResponse(int(goal_status(outcome)), self._result(outcome))

    def __bool__(self) -> bool:
        return True


class GoalHandle:
    """rclpy's ``ClientGoalHandle`` for one sent goal.

    Args:
        accepted: False for a goal the navigator rejected.
        stamp: when it was sent (sim time).
        outcome: reads the goal's outcome (None while it runs), for ``status``.
        result_future: the goal's result future; None when rejected.
        cancel: cancels the goal.
        number: the goal's number among the navigator's sends (its ``goal_id``).
    """

    def __init__(
        self,
        accepted: bool,
        stamp: TimeMsg,
        outcome: Callable[[], TaskOutcome | None],
        result_future: ResultFuture | None,
        cancel: Callable[[], None],
        number: int,
    ) -> None:
        self.accepted = accepted
        self.stamp = stamp
        self.goal_id = UUID(uuid=np.frombuffer(uuid.UUID(int=number).bytes, dtype=np.uint8).copy())
        self._outcome = outcome
        self._result_future = result_future
        self._cancel = cancel

    @property
    def status(self) -> int:
        """The ``action_msgs/GoalStatus`` code: UNKNOWN when rejected, EXECUTING, then final."""
        if not self.accepted:
            return int(GoalStatus.STATUS_UNKNOWN)
        return int(goal_status(self._outcome()))

    def get_result_async(self) -> ResultFuture | None:
        """The goal's result future (None for a rejected goal)."""
        return self._result_future

    def cancel_goal_async(self) -> Future:
        """Cancel the goal now; the returned future is done at once."""
        if self.accepted:
            self._cancel()
        return Future()

    def __repr__(self) -> str:
        return f"GoalHandle(accepted={self.accepted}, status={self.status})"
