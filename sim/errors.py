"""The root of baobab's exceptions, the ones raised below the mission layer, and one-line messages.

Messages about a user's input are one line (:func:`one_line`), echo values cut to a readable
length (:func:`clip`) and name the valid choices of a wrong name with its near miss
(:func:`unknown_name`).
"""

from __future__ import annotations

import unicodedata
from collections.abc import Iterable
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


MAX_LISTED_NAMES = 40
"""An unknown name's message lists at most this many valid names."""


def unknown_name(what: str, name: str, valid: Iterable[str], where: str = "") -> str:
    """``unknown <what> '<name>' [in <where>]; did you mean '<close>'? valid: a, b, c``.

    The name is cut to a readable length (:func:`~baobab.sim.errors.clip`), and so is the list.
    """
    import difflib  # only when a name is wrong: not on every command's start-up path

    names = sorted(set(valid))
    close = (
        difflib.get_close_matches(name, names, n=1, cutoff=0.6)
        if len(name) <= MAX_VALUE_CHARS
        else []
    )
    hint = f"; did you mean '{close[0]}'?" if close else ";"
    place = f" in {where}" if where else ""
    shown = [clip(valid_name) for valid_name in names[:MAX_LISTED_NAMES]]
    if len(names) > MAX_LISTED_NAMES:
        shown.append(f"... ({len(names) - MAX_LISTED_NAMES} more)")
    return f"unknown {what} '{clip(name)}'{place}{hint} valid: {', '.join(shown) or '(none)'}"


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
