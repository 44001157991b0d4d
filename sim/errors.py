"""The root of baobab's exceptions and the ones raised below the mission layer."""

from __future__ import annotations

import unicodedata
from pathlib import Path

MAX_MESSAGE_CHARS = 1000
"""A message longer than this is cut in its middle (a huge value echoed, a long list)."""
MAX_VALUE_CHARS = 60
"""A user's value echoed in a message is cut to this many characters (:func:`clip`)."""


def one_line(text: str, limit: int | None = MAX_MESSAGE_CHARS) -> str:
    r"""``text`` as one printable line: line breaks and control characters escaped.

    A line feed becomes ``\n``, a carriage return ``\r``; other control and format characters,
    the Unicode line and paragraph separators (U+0085, U+2028, U+2029: terminals and editors
    may break lines there) and the lone surrogates that stand for undecodable bytes of a file
    name or argument (``\xff``) are written as escapes. A text longer than ``limit``
    characters keeps its start and end around a note of how much was cut.
    """
    if not text.isprintable():
        text = "".join(_escaped(char) if not char.isprintable() else char for char in text)
    if limit is not None and len(text) > limit:
        keep = (limit - 40) // 2
        cut = len(text) - 2 * keep
        text = f"{text[:keep]}...[{cut} characters cut]...{text[-keep:]}"
    return text


def _escaped(char: str) -> str:
    if char == "\n":
        return "\\n"
    if char == "\r":
        return "\\r"
    if char in " \t":
        return char
    code = ord(char)
    if 0xDC80 <= code <= 0xDCFF:  # os.fsdecode's stand-in for an undecodable byte
        return f"\\x{code - 0xDC00:02x}"
    if unicodedata.category(char) == "Zs":
        return char  # a space other than U+0020: harmless on one line
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}"


def clip(value: object, limit: int = MAX_VALUE_CHARS) -> str:
    """``str(value)`` for a message: one line, at most ``limit`` characters and a length note."""
    text = one_line(str(value), None)
    if len(text) <= limit:
        return text
    return f"{text[: limit - 3]}... ({len(text)} characters)"


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
        # One line whatever the file or its name holds: a key, a value or a path may contain
        # a line break or a huge value.
        self.message = one_line(message)
        super().__init__(f"{one_line(self.path, None)}:{line}:{column}: {self.message}")

    def __reduce__(self) -> tuple[type[SourceError], tuple[str, int, int, str]]:
        """Pickle by the located fields (``args`` holds only the formatted line)."""
        return type(self), (self.path, self.line, self.column, self.message)


class WorldError(SourceError):
    """A world description that cannot be loaded or built."""


class SimulationError(BaobabError):
    """The physics went somewhere it must not: a MuJoCo warning or a non-finite state."""


class RenderingError(BaobabError):
    """A frame could not be rendered or a video could not be written."""
