"""Line and column of a place in a text, with line breaks counted as editors count them.

PyYAML reads YAML 1.1, where U+0085 (next line), U+2028 (line separator) and U+2029
(paragraph separator) also break lines; YAML 1.2, editors and ``str.splitlines``'s narrower
cousins count only ``\\n``, ``\\r\\n`` and ``\\r``. PyYAML's marks would then name a line one
too far after each such character. A mark's ``index`` (in characters, for both the
pure-Python and the libyaml parser) does not depend on that choice, so positions are
recomputed from it whenever the text holds one of those characters.
"""

from __future__ import annotations

import bisect
import re
from typing import Any

YAML11_ONLY_BREAKS = ("\x85", "\u2028", "\u2029")
"""Characters that break lines for PyYAML but not in YAML 1.2 or in an editor."""
_LINE_BREAK = re.compile(r"\r\n|\r|\n")


class TextPositions:
    """Turns character indices (and PyYAML marks) of one text into 1-based (line, column)."""

    def __init__(self, text: str) -> None:
        self._text = text
        self._starts: list[int] | None = None
        self.has_yaml11_breaks = any(char in text for char in YAML11_ONLY_BREAKS)
        """True when the text holds a character only YAML 1.1 counts as a line break."""

    def of_mark(self, mark: Any) -> tuple[int, int]:
        """(line, column) of a PyYAML mark (``line``, ``column``, ``index``, 0-based)."""
        if not self.has_yaml11_breaks:
            return mark.line + 1, mark.column + 1
        return self.of_index(mark.index)

    def of_index(self, index: int) -> tuple[int, int]:
        """(line, column) of the character at ``index`` (0-based)."""
        if self._starts is None:
            self._starts = [0] + [found.end() for found in _LINE_BREAK.finditer(self._text)]
        line = bisect.bisect_right(self._starts, index)
        return line, index - self._starts[line - 1] + 1
