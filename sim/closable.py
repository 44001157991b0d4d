"""A mixin for objects that hold a resource until ``close()``: ``with obj:`` closes on exit."""

from __future__ import annotations

from types import TracebackType
from typing import Self


class Closable:
    """Gives a class with a ``close()`` method the context-manager protocol."""

    def close(self) -> None:
        """Release the resource (subclasses implement it; idempotent)."""
        raise NotImplementedError

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.close()
