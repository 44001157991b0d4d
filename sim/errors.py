"""The root of baobab's exceptions and the ones raised below the mission layer."""

from __future__ import annotations

from pathlib import Path


class BaobabError(Exception):
    """Root of every error baobab raises on purpose."""


class SourceError(BaobabError):
    """A mistake in a user file, located as ``path:line:col: message``.

    Lines and columns are 1-based, as editors count them.
    """

    def __init__(self, path: str | Path, line: int, column: int, message: str) -> None:
        self.path = str(path)
        self.line = line
        self.column = column
        # One line whatever the file holds: a key or value may contain a line break.
        self.message = message.replace("\r", "\\r").replace("\n", "\\n")
        super().__init__(f"{self.path}:{line}:{column}: {self.message}")

    def __reduce__(self) -> tuple[type[SourceError], tuple[str, int, int, str]]:
        """Pickle by the located fields (``args`` holds only the formatted line)."""
        return type(self), (self.path, self.line, self.column, self.message)


class WorldError(SourceError):
    """A world description that cannot be loaded or built."""


class SimulationError(BaobabError):
    """The physics went somewhere it must not: a MuJoCo warning or a non-finite state."""


class RenderingError(BaobabError):
    """A frame could not be rendered or a video could not be written."""
