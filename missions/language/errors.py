"""Mission errors: located one-liners, and pydantic errors made readable.

A name the file gets wrong is told with its near misses (:func:`~baobab.sim.errors.unknown_name`);
a validator blames one key of its model with :class:`~baobab.sim.yaml_source.FieldValueError`.
"""

from __future__ import annotations

import types
import typing
from collections.abc import Mapping, Sequence
from typing import Any

from pydantic import BaseModel, ValidationError

from baobab.sim.errors import SourceError, clip, unknown_name
from baobab.sim.yaml_source import KeyPath, LocatedDocument


class MissionError(SourceError):
    """A mistake in a mission file or in its ``--set`` overrides: ``path:line:col: message``."""


def data_path(data: Any, loc: Sequence[str | int]) -> KeyPath:
    """Follow a pydantic ``loc`` through ``data``, keeping only the parts that exist in it.

    Pydantic inserts union tags and validator names into ``loc`` and reports errors of
    shorthand values (``wait: 5``) under the expanded field name; skipping the parts the data
    does not have leaves the deepest real key path, which the document can locate.
    """
    path: list[str | int] = []
    current = data
    for part in loc:
        in_mapping = isinstance(current, Mapping) and isinstance(part, str) and part in current
        in_list = (
            isinstance(current, list)
            and isinstance(part, int)
            and not isinstance(part, bool)
            and 0 <= part < len(current)
        )
        if in_mapping or in_list:
            current = current[part]
            path.append(part)
    return tuple(path)


def _readable(loc: Sequence[str | int]) -> list[str | int]:
    return [part for part in loc if isinstance(part, int) or not any(c in part for c in "[<( ")]


def _model_fields_at(model: Any, loc: Sequence[str | int]) -> list[str]:
    """Field names of the (nested) model that ``loc`` points into, best effort."""
    candidates: list[Any] = [model] if model is not None else []
    for part in loc:
        following: list[Any] = []
        for candidate in _expand(candidates):
            if isinstance(candidate, type) and issubclass(candidate, BaseModel):
                if isinstance(part, str) and part in candidate.model_fields:
                    following.append(candidate.model_fields[part].annotation)
            else:
                origin = typing.get_origin(candidate)
                if origin in (list, tuple, dict) or origin is not None:
                    following.extend(typing.get_args(candidate)[-1:])
        candidates = following
    for candidate in _expand(candidates):
        if isinstance(candidate, type) and issubclass(candidate, BaseModel):
            return list(candidate.model_fields)
    return []


def _expand(candidates: list[Any]) -> list[Any]:
    expanded: list[Any] = []
    for candidate in candidates:
        origin = typing.get_origin(candidate)
        if origin in (typing.Union, types.UnionType) or origin is typing.Annotated:
            expanded.extend(_expand(list(typing.get_args(candidate))))
        else:
            expanded.append(candidate)
    return expanded


def describe_validation_error(
    document: LocatedDocument,
    exc: ValidationError,
    *,
    data: Any,
    base_path: KeyPath,
    label: str,
    model: Any = None,
    origins: Mapping[KeyPath, str] | None = None,
    nouns: Mapping[tuple[str | int, ...], str] | None = None,
) -> MissionError:
    """Turn the first error of ``exc`` into a located :class:`MissionError`.

    Args:
        document: the mission document (for line and column).
        exc: the pydantic error.
        data: the value that was validated (found at ``base_path`` in the document).
        base_path: where ``data`` sits in the document.
        label: how the message names the validated thing, e.g. ``"wait"`` or ``"expect"``.
        model: the validated model (or type), to list valid keys after an unknown one.
        origins: key paths whose values came from a ``${param}``, for the message's hint.
        nouns: what an unknown key is called, by the key path of its mapping (within
            ``data``), e.g. ``{(): "parameter"}``; ``"key"`` elsewhere.
    """
    errors = exc.errors(include_url=False)
    # An unknown key usually explains a missing one (a typo), so it is the better message.
    first = next((e for e in errors if e["type"] == "extra_forbidden"), errors[0])
    loc = tuple(part for part in first["loc"] if isinstance(part, str | int))
    readable = _readable(loc)
    kind = first["type"]
    prefix = [label] if label else []
    if kind == "extra_forbidden":
        key = str(loc[-1])
        valid = [name for name in _model_fields_at(model, _readable(loc[:-1])) if name != key]
        where = ".".join(str(p) for p in [*prefix, *readable[:-1]]) or "the top level"
        word = (nouns or {}).get(tuple(readable[:-1]), "key")
        message = (
            unknown_name(word, key, valid, where) if valid else f"unknown {word} '{key}' in {where}"
        )
    elif kind == "missing":
        where = ".".join(str(p) for p in [*prefix, *readable[:-1]])
        message = f"{where + ': ' if where else ''}missing required key '{loc[-1]}'"
        loc = loc[:-1]
    else:
        message = first["msg"]
        cause = first.get("ctx", {}).get("error")
        if kind == "value_error" and isinstance(cause, ValueError):
            message = str(cause)
            loc = loc + tuple(getattr(cause, "key_path", ()))
            readable = _readable(loc)
        elif kind in ("literal_error", "enum"):
            message = f"got {clip(repr(first['input']))}; {message[0].lower()}{message[1:]}"
        where = ".".join(str(p) for p in [*prefix, *readable])
        message = f"{where}: {message}" if where else message
    path = base_path + data_path(data, loc)
    return located(document, path, message, origins)


def located(
    document: LocatedDocument,
    path: KeyPath,
    message: str,
    origins: Mapping[KeyPath, str] | None = None,
) -> MissionError:
    """A :class:`MissionError` at ``path``, noting the ``${param}`` the value came from."""
    if origins:
        for length in range(len(path), -1, -1):
            origin = origins.get(path[:length])
            if origin is not None:
                message = f"{message} ({origin})"
                break
    line, column = document.locate(path)
    return MissionError(document.path, line, column, message)
