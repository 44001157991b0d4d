"""Safe YAML loading that remembers where every value came from.

PyYAML's safe loader composes nodes that carry start marks; we turn the node graph into plain
Python data and keep a table from each value's key path to its (line, column). Pydantic's error
``loc`` tuples index that table, so every validation error can name ``file:line:col``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml
from pydantic import ValidationError

from baobab.sim.errors import BaobabError, SourceError, clip
from baobab.sim.input_files import MAX_INPUT_BYTES, read_input_file
from baobab.sim.text_positions import TextPositions
from baobab.sim.yaml11 import scalar_surprise, unquoted_break
from baobab.sim.yaml_limits import (
    ScanProblem,
    events_at_most,
    libyaml_available,
    scan_limits,
)

MAX_FILE_BYTES = MAX_INPUT_BYTES
MAX_DEPTH = 64
MAX_ALIASES = 100
MAX_NODES = 20_000

KeyPath = tuple[str | int, ...]


@dataclass
class LocatedDocument:
    """Plain data from a YAML file plus the (line, column) of every key path in it."""

    path: str
    data: Any
    marks: dict[KeyPath, tuple[int, int]] = field(default_factory=dict)

    def locate(self, key_path: Sequence[str | int]) -> tuple[int, int]:
        """Return the 1-based (line, column) of the deepest known prefix of ``key_path``."""
        parts = tuple(key_path)
        while parts:
            if parts in self.marks:
                return self.marks[parts]
            parts = parts[:-1]
        return self.marks.get((), (1, 1))

    def error(
        self,
        key_path: Sequence[str | int],
        message: str,
        error_type: Callable[[str, int, int, str], SourceError] = SourceError,
    ) -> SourceError:
        """Build a located error for the value at ``key_path``."""
        line, column = self.locate(key_path)
        return error_type(self.path, line, column, message)


class FieldValueError(BaobabError, ValueError):
    """Raised inside a pydantic validator to blame a value below the model being validated.

    A model validator sees the whole model, so pydantic locates its errors at the model itself;
    ``key_path`` (relative to that model) lets :func:`describe_validation_error` point at the
    offending key instead, e.g. ``("locations", "door")``.
    """

    def __init__(self, key_path: KeyPath, message: str) -> None:
        super().__init__(message)
        self.key_path = key_path


def empty_list() -> list[Any]:
    """``default_factory`` of the list fields of models read from YAML.

    Equal to ``list``, but pydantic inspects a factory's signature, and ``list``'s exists only
    as text: parsing it compiles the tokenizer's regular expressions, some milliseconds of
    every command's start-up.
    """
    return []


def describe_validation_error(
    document: LocatedDocument,
    exc: ValidationError,
    prefix: KeyPath = (),
    error_type: Callable[[str, int, int, str], SourceError] = SourceError,
) -> SourceError:
    """Turn the first error of a pydantic ``ValidationError`` into a located error."""
    first = exc.errors(include_url=False)[0]
    loc = prefix + tuple(part for part in first["loc"] if isinstance(part, str | int))
    message = first["msg"]
    cause = first.get("ctx", {}).get("error")
    if first["type"] == "value_error" and isinstance(cause, ValueError):
        message = str(cause)  # without pydantic's "Value error, " prefix
        if isinstance(cause, FieldValueError):
            loc += cause.key_path
    dotted = ".".join(str(part) for part in loc) or "document"
    if first["type"] == "extra_forbidden":
        message = f"unknown key '{loc[-1]}'"
        parent = loc[:-1]
        return document.error(parent + (loc[-1],), f"{message} in {_dotted(parent)}", error_type)
    if first["type"] == "missing":
        return document.error(loc[:-1], f"missing required key '{loc[-1]}'", error_type)
    return document.error(loc, f"{dotted}: {message}", error_type)


def _dotted(parts: Iterable[str | int]) -> str:
    text = ".".join(str(part) for part in parts)
    return text or "the document"


def load_located_yaml(
    path: str | Path,
    error_type: Callable[[str, int, int, str], SourceError] = SourceError,
    text: str | None = None,
) -> LocatedDocument:
    """Load one YAML document safely, keeping marks; every problem is a located error.

    Rejects: unreadable, oversized, binary or non-UTF-8 files and anything but a regular
    file (:func:`read_yaml_text`); syntax errors; several documents; duplicate keys;
    non-string keys; non-finite numbers; the YAML 1.1 readings YAML 1.2 dropped (``yes``/``no``/
    ``on``/``off`` as booleans, base-60 ``1:30``, octal ``010``); more than ``MAX_ALIASES``
    aliases; nesting deeper than ``MAX_DEPTH``; more than ``MAX_NODES`` values. Lines and
    columns count line breaks as YAML 1.2 and editors do (:mod:`baobab.sim.text_positions`).
    """
    shown = str(path)
    if text is None:
        text = read_yaml_text(path, error_type)
    text = text.removeprefix("\ufeff")  # the parsers skip it, but only one counts it in marks
    positions = TextPositions(text)
    if positions.has_yaml11_breaks:
        found = unquoted_break(text)
        if found is not None:
            raise error_type(shown, *positions.of_index(found[0]), found[1])
    fast = _load_with_libyaml(shown, text, positions, error_type)
    if fast is not None:
        return fast
    try:
        loader = yaml.SafeLoader(text)
        try:
            root = loader.get_single_node()
        finally:
            loader.dispose()
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line, column = positions.of_mark(mark) if mark else (1, 1)
        problem = exc.problem or exc.context or "invalid YAML"
        raise error_type(shown, line, column, f"YAML syntax error: {problem}") from None
    except yaml.reader.ReaderError as exc:  # a control character; str(exc) spans two lines
        line, column = positions.of_index(exc.position)
        raise error_type(
            shown, line, column, f"character #x{exc.character:04x} is not allowed in YAML text"
        ) from None
    except yaml.YAMLError as exc:
        raise error_type(shown, 1, 1, f"YAML syntax error: {exc}") from None
    except RecursionError:
        raise error_type(shown, 1, 1, f"nesting deeper than {MAX_DEPTH} levels") from None
    document = LocatedDocument(shown, None)
    if root is None:
        raise error_type(shown, 1, 1, "the file is empty; expected a YAML mapping")
    try:
        document.data = _Builder(document, positions, error_type).build_root(root)
    except _SizeLimitError as exc:
        raise exc.error from None
    return document


class _SizeLimitError(Exception):
    """Carries the located error for a document with more than ``MAX_NODES`` values."""

    def __init__(self, error: SourceError) -> None:
        super().__init__(str(error))
        self.error = error


_LIBYAML_DEPTH_BOUND = 1000
"""Largest nesting bound for which libyaml's recursive composer is safe on the C stack."""
_PURE_RETRY_CHARS = 8_192
"""Up to this length, a text libyaml refuses is read again by pure-Python PyYAML for its exact
error; beyond, that second pass would cost up to seconds, and libyaml's error is reported."""
_QUICK_COUNT_CHARS = 400_000
"""Up to this length, a long text's events are first counted in C: most such texts are under
the value limit, and then need no event-by-event scan."""


def _load_with_libyaml(
    shown: str,
    text: str,
    positions: TextPositions,
    error_type: Callable[[str, int, int, str], SourceError],
) -> LocatedDocument | None:
    """The document through libyaml (~15x faster than pure-Python PyYAML), or None.

    Texts that could hold more than ``MAX_NODES`` values, and texts whose nesting could be
    deep, are first scanned for the value and depth limits (:mod:`baobab.sim.yaml_limits`),
    which stops early on a huge document. Errors in texts longer than ``_PURE_RETRY_CHARS`` (or
    deep) are reported as libyaml finds them, since a second, pure-Python pass over a long text
    costs seconds. A shorter text that fails here (characters PyYAML's reader rejects, syntax,
    duplicate keys) returns None, and the pure-Python path then gives exactly its located error.
    """
    if not libyaml_available() or yaml.reader.Reader.NON_PRINTABLE.search(text):
        return None
    deep = _nesting_bound(text) > _LIBYAML_DEPTH_BOUND
    trust_libyaml = deep or len(text) > _PURE_RETRY_CHARS
    few = len(text) <= MAX_NODES or (
        not deep and len(text) <= _QUICK_COUNT_CHARS and events_at_most(text, MAX_NODES)
    )
    if deep or not few:
        # After the scan the nesting is at most MAX_DEPTH: safe for libyaml's composer.
        found = scan_limits(text, MAX_NODES, MAX_DEPTH)
        if isinstance(found, ScanProblem):
            raise error_type(shown, found.line, found.column, found.message)
    try:
        loader = yaml.CSafeLoader(text)
        try:
            root = loader.get_single_node()
        finally:
            loader.dispose()
        if root is None:
            return None
        document = LocatedDocument(shown, None)
        document.data = _Builder(document, positions, error_type).build_root(root)
    except _SizeLimitError as exc:
        # Refusing a huge document must not cost a second, pure-Python pass over it.
        raise exc.error from None
    except yaml.MarkedYAMLError as exc:
        if not trust_libyaml:
            return None
        mark = exc.problem_mark or exc.context_mark
        line, column = positions.of_mark(mark) if mark else (1, 1)
        problem = exc.problem or exc.context or "invalid YAML"
        raise error_type(shown, line, column, f"YAML syntax error: {problem}") from None
    except SourceError:
        if trust_libyaml:
            raise
        return None
    except (yaml.YAMLError, RecursionError):
        return None
    return document


def _nesting_bound(text: str) -> int:
    """An upper bound on how deeply ``text`` can nest YAML collections.

    Flow collections open with ``[`` or ``{``; block collections nest by indentation or by
    the ``-``, ``?`` and ``:`` indicators on one line.
    """
    flow = text.count("[") + text.count("{")
    block = max(
        (
            len(line) - len(line.lstrip(" ")) + sum(line.count(c) for c in "-?:")
            for line in text.splitlines()
        ),
        default=0,
    )
    return flow + block + 1


def read_yaml_text(
    path: str | Path, error_type: Callable[[str, int, int, str], SourceError] = SourceError
) -> str:
    """The text of a YAML file: a regular file of at most ``MAX_FILE_BYTES``, UTF-8, no NUL.

    Raises:
        error_type: located at the problem (1:1 for the file itself, the first undecodable
            byte for bad UTF-8).
    """
    shown = str(path)
    raw = read_input_file(path, error_type, expected="a YAML file", limit=MAX_FILE_BYTES)
    if b"\x00" in raw:
        raise error_type(shown, 1, 1, "binary data (NUL byte); expected a YAML text file")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        before = raw[: exc.start].decode("utf-8")  # valid up to the first bad byte
        line, column = TextPositions(before).of_index(len(before))
        raise error_type(shown, line, column, "not valid UTF-8 text") from None


_PLAIN_TAGS = {"tag:yaml.org,2002:map", "tag:yaml.org,2002:seq"}
_CONSTRUCTOR = yaml.SafeLoader.__new__(yaml.SafeLoader)
yaml.constructor.SafeConstructor.__init__(_CONSTRUCTOR)
_STR_TAG = "tag:yaml.org,2002:str"
_INT_TAG = "tag:yaml.org,2002:int"
_FLOAT_TAG = "tag:yaml.org,2002:float"
_DECIMAL_CHARACTERS = frozenset("0123456789.eE+-")
_PLAIN_SCALAR_CONSTRUCTORS = {
    f"tag:yaml.org,2002:{name}": yaml.SafeLoader.yaml_constructors[f"tag:yaml.org,2002:{name}"]
    for name in ("null", "bool", "int", "float")
}
"""Constructors that build a value straight from a scalar node, without PyYAML's bookkeeping."""


class _Builder:
    """Turns a composed node graph into plain data, recording marks and enforcing limits."""

    def __init__(
        self,
        document: LocatedDocument,
        positions: TextPositions,
        error_type: Callable[[str, int, int, str], SourceError],
    ) -> None:
        self.document = document
        self.marks = document.marks
        self.where = positions.of_mark
        self.error_type = error_type
        self.nodes = 0
        self.aliases = 0
        self.seen: set[int] = set()  # ids of the nodes built so far (the graph keeps them alive)

    def build_root(self, root: yaml.Node) -> Any:
        """The data of the whole document."""
        self.marks[()] = self.where(root.start_mark)
        return self.build(root, (), 0)

    def _error(self, mark: Any, message: str) -> SourceError:
        return self.error_type(self.document.path, *self.where(mark), message)

    def build(self, node: yaml.Node, key_path: KeyPath, depth: int) -> Any:
        """The data of ``node`` at ``key_path``, ``depth`` collections below the root."""
        mark = node.start_mark
        self.nodes += 1
        if self.nodes > MAX_NODES:
            raise _SizeLimitError(self._error(mark, f"more than {MAX_NODES} values"))
        if depth > MAX_DEPTH:
            raise self._error(mark, f"nesting deeper than {MAX_DEPTH} levels")
        identity = id(node)
        if identity in self.seen:
            self.aliases += 1
            if self.aliases > MAX_ALIASES:
                raise self._error(mark, f"more than {MAX_ALIASES} aliases (alias bomb?)")
        else:
            self.seen.add(identity)
        self.marks.setdefault(key_path, self.where(mark))
        kind = type(node)
        if kind is yaml.ScalarNode:
            return self.scalar(node)
        if node.tag not in _PLAIN_TAGS:
            raise self._error(mark, f"unsupported YAML tag {node.tag}")
        if kind is yaml.MappingNode:
            return self._mapping(node, key_path, depth)
        return [
            self.build(item, key_path + (index,), depth + 1)
            for index, item in enumerate(node.value)
        ]

    def _mapping(self, node: yaml.Node, key_path: KeyPath, depth: int) -> dict[str, Any]:
        result: dict[str, Any] = {}
        for key_node, value_node in node.value:
            key_mark = key_node.start_mark
            if key_node.tag == "tag:yaml.org,2002:merge":
                raise self._error(key_mark, "merge keys (<<) are not supported; write the keys out")
            key = self.scalar(key_node)
            if not isinstance(key, str | int) or isinstance(key, bool):
                raise self._error(key_mark, f"mapping key {clip(repr(key))} must be a string")
            key = str(key)
            path = key_path + (key,)
            if key in result:
                first = self.marks.get(path, (0, 0))
                raise self._error(
                    key_mark, f"duplicate key '{key}' (first defined at line {first[0]})"
                )
            self.marks[path] = self.where(key_mark)
            result[key] = self.build(value_node, path, depth + 1)
        return result

    def scalar(self, node: yaml.Node) -> Any:
        """The value of a scalar node (a located error for anything else)."""
        if type(node) is yaml.ScalarNode and node.tag == _STR_TAG:
            return node.value
        line, column = self.where(node.start_mark)
        try:
            return _scalar(node)
        except ValueError as exc:
            raise self.error_type(self.document.path, line, column, str(exc)) from None


def _scalar(node: yaml.Node) -> Any:
    """The value of a scalar node that is not a plain string.

    Raises:
        ValueError: the message of a located error (the caller knows where).
    """
    if not isinstance(node, yaml.ScalarNode):
        raise ValueError("expected a plain value here")
    plain = _PLAIN_SCALAR_CONSTRUCTORS.get(node.tag)
    text = node.value
    value: Any
    try:
        plain_decimal = text.isascii() and text.isdigit() and (text[0] != "0" or text == "0")
        if node.tag == _INT_TAG and plain_decimal:
            value = int(text)  # what PyYAML's constructor returns, without its base handling
        elif node.tag == _FLOAT_TAG and _DECIMAL_CHARACTERS.issuperset(text):
            value = float(text)  # no '_', ':', inf or nan: PyYAML's result, faster
        elif plain is not None:
            value = plain(_CONSTRUCTOR, node)
        else:
            value = _CONSTRUCTOR.construct_object(node, deep=True)
    except Exception as exc:  # an explicit tag (!!int abc, !!timestamp x, !x) makes PyYAML's
        # constructors raise anything from ValueError to AttributeError; all mean a bad value.
        problem = getattr(exc, "problem", None) or f"{clip(repr(text))} is not a valid {node.tag}"
        raise ValueError(f"invalid value: {problem}") from None
    finally:
        # construct_object remembers every node it built: a process loading many files
        # would keep them all (and their marks) alive.
        _CONSTRUCTOR.constructed_objects.clear()
        _CONSTRUCTOR.recursive_objects.clear()
    surprise = scalar_surprise(node.tag, text, value)
    if surprise is not None:
        raise ValueError(surprise)
    if isinstance(value, float) and not math.isfinite(value):
        raise ValueError(f"non-finite number {clip(repr(text))}; expected a finite one")
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) > 10**15:
        raise ValueError(f"number {clip(text)} is too large")
    if not isinstance(value, str | int | float | bool | type(None)):
        # Timestamps, binary blobs and the like: keep the text as written.
        return text
    return value
