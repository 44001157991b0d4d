"""Strict JSON loading that remembers where every value came from (GeoJSON route graphs).

The values come from :func:`json.loads` (JSON's own grammar: no trailing commas, no comments,
``1e5`` is a number). A second pass over the same, already valid, text records the (line,
column) of every key path, as :class:`~baobab.sim.yaml_source.LocatedDocument` does for YAML,
so a check of the data can name ``file:line:col``. Duplicate keys, ``NaN`` / ``Infinity`` and
nesting deeper than ``MAX_DEPTH`` are refused, located.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

from baobab.sim.input_files import ErrorType, read_input_file
from baobab.sim.text_positions import TextPositions
from baobab.sim.yaml_source import MAX_DEPTH, KeyPath, LocatedDocument

_SPACE = re.compile(r"[ \t\n\r]*")
_STRING = re.compile(r'"(?:[^"\\]|\\.)*"')
_SCALAR = re.compile(r"-?(?:0|[1-9]\d*)(?:\.\d+)?(?:[eE][-+]?\d+)?|true|false|null")


def load_located_json(path: str | Path, error_type: ErrorType, *, what: str) -> LocatedDocument:
    """Load one JSON document from ``path``, keeping the position of every key path.

    Args:
        path: the file, as the user named it (messages show it so).
        error_type: the located error to raise (``WorldError`` ...).
        what: what the file should be, for messages (``a GeoJSON file``).

    Raises:
        error_type: unreadable, oversized, not UTF-8, a JSON syntax error, ``NaN`` or
            ``Infinity``, a duplicate key, or nesting deeper than ``MAX_DEPTH``.
    """
    shown = str(path)
    raw = read_input_file(path, error_type, expected=what)
    try:
        text = raw.decode("utf-8").removeprefix("\ufeff")
    except UnicodeDecodeError as exc:
        line, column = TextPositions(raw[: exc.start].decode("utf-8")).of_index(exc.start)
        raise error_type(shown, line, column, "not valid UTF-8 text") from None

    def not_finite(name: str) -> Any:
        raise ValueError(f"{name} is not a number JSON allows; expected a finite number")

    try:
        data = json.loads(text, parse_constant=not_finite)
    except json.JSONDecodeError as exc:
        raise error_type(shown, exc.lineno, exc.colno, f"JSON syntax error: {exc.msg}") from None
    except ValueError as exc:  # NaN or Infinity: locate the first one in the text
        found = re.search(r"-?\b(?:NaN|Infinity)\b", text)
        line, column = TextPositions(text).of_index(found.start() if found else 0)
        raise error_type(shown, line, column, str(exc)) from None
    except RecursionError:
        raise error_type(shown, 1, 1, f"nesting deeper than {MAX_DEPTH} levels") from None
    document = LocatedDocument(shown, data)
    _Marker(text, document, error_type).value(0, (), 0)
    return document


class _Marker:
    """Walks valid JSON text and records where each key path's value (or key) begins."""

    def __init__(self, text: str, document: LocatedDocument, error_type: ErrorType) -> None:
        self.text = text
        self.document = document
        self.positions = TextPositions(text)
        self.error_type = error_type

    def _space(self, index: int) -> int:
        match = _SPACE.match(self.text, index)
        return index if match is None else match.end()

    def _error(self, index: int, message: str) -> Exception:
        line, column = self.positions.of_index(index)
        return self.error_type(self.document.path, line, column, message)

    def _string(self, index: int) -> tuple[str, int]:
        """The JSON string starting at ``index`` (its opening quote) and the index past it."""
        match = _STRING.match(self.text, index)
        if match is None:  # json.loads accepted the text, so this cannot happen
            raise self._error(index, "unterminated JSON string")
        return str(json.loads(match.group())), match.end()

    def value(self, index: int, key_path: KeyPath, depth: int) -> int:
        """Record the value starting at or after ``index``; the index just past it."""
        index = self._space(index)
        if depth > MAX_DEPTH:
            raise self._error(index, f"nesting deeper than {MAX_DEPTH} levels")
        self.document.marks.setdefault(key_path, self.positions.of_index(index))
        opening = self.text[index]
        if opening == "{":
            return self._object(index + 1, key_path, depth)
        if opening == "[":
            return self._array(index + 1, key_path, depth)
        if opening == '"':
            return self._string(index)[1]
        match = _SCALAR.match(self.text, index)
        if match is None:  # json.loads accepted the text, so this cannot happen
            raise self._error(index, "unexpected JSON value")
        return match.end()

    def _object(self, index: int, key_path: KeyPath, depth: int) -> int:
        index = self._space(index)
        if self.text[index] == "}":
            return index + 1
        first_seen: dict[str, int] = {}
        while True:
            key_start = self._space(index)
            key, index = self._string(key_start)
            if key in first_seen:
                line = self.positions.of_index(first_seen[key])[0]
                raise self._error(
                    key_start, f"duplicate key '{key}' (first defined at line {line})"
                )
            first_seen[key] = key_start
            self.document.marks[key_path + (key,)] = self.positions.of_index(key_start)
            index = self._space(index) + 1  # past ':'
            index = self._space(self.value(index, key_path + (key,), depth + 1))
            if self.text[index] == "}":
                return index + 1
            index += 1  # past ','

    def _array(self, index: int, key_path: KeyPath, depth: int) -> int:
        index = self._space(index)
        if self.text[index] == "]":
            return index + 1
        item = 0
        while True:
            index = self._space(self.value(index, key_path + (item,), depth + 1))
            if self.text[index] == "]":
                return index + 1
            index += 1
            item += 1
