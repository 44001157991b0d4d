"""A task handle for a server whose task state is advanced in compiled code.

The arm's control loop checks its tasks at 1 kHz inside MuJoCo's step
(:mod:`baobab.robots.panda.native_loop`) and only records how a task ended. A
:class:`SyncedTaskHandle` asks the server to turn those records into outcomes and feedback
before anyone reads the handle, so a reader sees what it would have seen had the server's
Python run after every control step.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus


class SyncedTaskHandle(TaskHandle):
    """A :class:`TaskHandle` that calls ``sync`` before its status, outcome or feedback is read
    and before a cancel.

    Args:
        name: task name.
        on_cancel: the server's cancel hook.
        sync: brings the server's tasks up to date (finishes this handle if it has ended).
    """

    def __init__(
        self, name: str, on_cancel: Callable[[TaskHandle], None], sync: Callable[[], None]
    ) -> None:
        self._sync = sync
        self._feedback: dict[str, Any] = {}
        super().__init__(name, on_cancel)

    @property
    def status(self) -> TaskStatus:
        """RUNNING until the server finishes the task."""
        self._sync()
        return super().status

    @property
    def outcome(self) -> TaskOutcome | None:
        """The result once the task has ended, else None."""
        self._sync()
        return super().outcome

    @property
    def feedback(self) -> dict[str, Any]:
        """The server's latest feedback (a live dict; the server updates it)."""
        self._sync()
        return self._feedback

    @feedback.setter
    def feedback(self, value: dict[str, Any]) -> None:
        self._feedback = value

    @property
    def live_feedback(self) -> dict[str, Any]:
        """The feedback dict without syncing: for the server itself."""
        return self._feedback

    def cancel(self) -> None:
        """Ask the server to stop the task, unless it has ended already."""
        self._sync()
        super().cancel()
