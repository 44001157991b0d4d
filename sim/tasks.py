"""Goal-style tasks: the contract between capability servers and whoever sends them goals.

A capability server (navigation, arm) accepts a goal and returns a :class:`TaskHandle` at once.
The server advances the task inside sim callbacks; the sender polls ``status`` (never blocks),
reads ``feedback``, and may ``cancel()``. When the task ends, ``outcome`` holds the result with
a Nav2-style error code and message. Behaviour-tree leaves, the BasicNavigator facade and tests
all speak this one protocol.
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


class TaskStatus(enum.Enum):
    """Where a task is in its life."""

    RUNNING = "RUNNING"
    SUCCEEDED = "SUCCEEDED"
    FAILED = "FAILED"
    CANCELED = "CANCELED"

    @property
    def done(self) -> bool:
        """True once the task has ended, whichever way."""
        return self is not TaskStatus.RUNNING


@dataclass(frozen=True)
class TaskOutcome:
    """How a task ended: status, a numeric error code (0 = none) and a message."""

    status: TaskStatus
    error_code: int = 0
    error_msg: str = ""
    error_name: str = "NONE"


class TaskHandle:
    """The sender's view of one running task.

    Servers create it, update ``feedback`` as the task runs and call :meth:`finish` once.
    ``on_cancel`` is the server's hook that stops the task; it runs once, on the first
    :meth:`cancel` while the task is running. A server that keeps time sets ``started_at``
    and ``ended_at`` (sim seconds), from which senders report the task's elapsed time.
    """

    def __init__(self, name: str, on_cancel: Callable[[TaskHandle], None]) -> None:
        self.name = name
        self.feedback: dict[str, Any] = {}
        self.started_at: float | None = None
        self.ended_at: float | None = None
        self._outcome: TaskOutcome | None = None
        self._on_cancel = on_cancel
        self._cancel_requested = False

    @property
    def status(self) -> TaskStatus:
        """RUNNING until the server finishes the task."""
        return TaskStatus.RUNNING if self._outcome is None else self._outcome.status

    @property
    def outcome(self) -> TaskOutcome | None:
        """The result once the task has ended, else None."""
        return self._outcome

    @property
    def cancel_requested(self) -> bool:
        """True once :meth:`cancel` was called."""
        return self._cancel_requested

    def cancel(self) -> None:
        """Ask the server to stop the task (idempotent; no effect once it has ended)."""
        if self._outcome is not None or self._cancel_requested:
            return
        self._cancel_requested = True
        self._on_cancel(self)

    def finish(self, outcome: TaskOutcome) -> None:
        """Record the outcome (server side). Only the first call counts."""
        if self._outcome is None:
            self._outcome = outcome
