"""``rclpy.task``: a future, the result of work that completes later."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["Future"]


class Future:
    """A result to come (``rclpy.task.Future``): ``set_result``/``set_exception`` complete it."""

    def __init__(self, *, executor: object = None) -> None:
        self._done = False
        self._cancelled = False
        self._result: Any = None
        self._exception: BaseException | None = None
        self._callbacks: list[Callable[[Future], None]] = []

    def done(self) -> bool:
        """True once a result or an exception was set, or the future was cancelled."""
        return self._done or self._cancelled

    def cancelled(self) -> bool:
        """True when cancelled."""
        return self._cancelled

    def cancel(self) -> None:
        """Cancel the future unless it is done."""
        if not self._done:
            self._cancelled = True
            self._run_callbacks()

    def result(self) -> Any:
        """The result (None until set); raises the exception set instead, if any."""
        if self._exception is not None:
            raise self._exception
        return self._result

    def exception(self) -> BaseException | None:
        """The exception set, if any."""
        return self._exception

    def set_result(self, result: Any) -> None:
        """Complete with ``result``."""
        self._result, self._done = result, True
        self._run_callbacks()

    def set_exception(self, exception: BaseException) -> None:
        """Complete with ``exception``."""
        self._exception, self._done = exception, True
        self._run_callbacks()

    def add_done_callback(self, callback: Callable[[Future], None]) -> None:
        """Call ``callback(future)`` when done (at once if it already is)."""
        if self.done():
            callback(self)
        else:
            self._callbacks.append(callback)

    def _run_callbacks(self) -> None:
        callbacks, self._callbacks = self._callbacks, []
        for callback in callbacks:
            callback(self)
