"""The base of the pydantic models that validate data read from YAML files.

Pydantic's lax mode turns ``true`` into 1 where a number goes and 1 into ``true`` where a
boolean goes: ``seed: true`` would be seed 1, ``wait: yes`` a one-second wait,
``no_contact: 0`` false. Models built on :class:`YamlModel` refuse both, located at the value,
before pydantic converts anything.
"""

from __future__ import annotations

import math
import types
import typing
from functools import cache
from typing import Any

from pydantic import BaseModel, model_validator

from baobab.sim.yaml_source import FieldValueError, KeyPath


class YamlModel(BaseModel):
    """A model whose number fields refuse booleans and whose boolean fields refuse numbers."""

    @model_validator(mode="before")
    @classmethod
    def _no_booleans_for_numbers(cls, value: Any) -> Any:
        if type(value) is not dict:
            return value
        for name, kind, annotation in _plan(cls):
            item = value.get(name)
            held = type(item)
            if kind is _NUMBER:
                if held is not bool:
                    continue
            elif kind is _BOOLEAN:
                if held is not int and held is not float:
                    continue
            elif held not in _CHECKED_TYPES:
                continue
            found = _mistyped(annotation, item)
            if found is not None:
                raise FieldValueError((name, *found[0]), found[1])
        return value


_NUMBER, _BOOLEAN, _NESTED = "number", "boolean", "nested"
_NUMBERS = (int, float)
_CHECKED_TYPES = (bool, int, float, list, dict)


@cache
def _plan(model: type[BaseModel]) -> tuple[tuple[str, str, Any], ...]:
    """(field, kind, annotation) for each field of ``model`` that holds numbers or booleans.

    Made once per model: a pose built in a control loop pays a few dictionary look-ups.
    """
    plan = []
    for name, info in model.model_fields.items():
        annotation = info.annotation
        base = _unwrapped(annotation)
        if base in _NUMBERS:
            plan.append((name, _NUMBER, annotation))
        elif base is bool:
            plan.append((name, _BOOLEAN, annotation))
        elif _holds_numbers_or_booleans(annotation):
            plan.append((name, _NESTED, annotation))
    return tuple(plan)


def _unwrapped(annotation: Any) -> Any:
    """``float`` for ``Annotated[float, ...]``; the annotation itself otherwise."""
    while typing.get_origin(annotation) is typing.Annotated:
        annotation = typing.get_args(annotation)[0]
    return annotation


def _holds_numbers_or_booleans(annotation: Any) -> bool:
    if annotation in (*_NUMBERS, bool):
        return True
    return any(_holds_numbers_or_booleans(arg) for arg in typing.get_args(annotation))


def _mistyped(annotation: Any, value: Any) -> tuple[KeyPath, str] | None:
    """Where in ``value`` a boolean stands for a number or a number for a boolean, and why."""
    origin = typing.get_origin(annotation)
    args = typing.get_args(annotation)
    if origin is typing.Annotated:
        return _mistyped(args[0], value)
    if origin in (typing.Union, types.UnionType):
        if isinstance(value, bool) and (bool in args or Any in args):
            return None
        return next((found for arm in args if (found := _mistyped(arm, value)) is not None), None)
    if annotation in _NUMBERS and isinstance(value, bool):
        word = "true" if value else "false"
        return (), f"expected a number, got {word} (a yes/no value); write the number"
    if annotation is bool and isinstance(value, int | float) and not isinstance(value, bool):
        return (), f"expected true or false, got the number {value}"
    if origin in (tuple, list) and isinstance(value, list):
        for index, item in enumerate(value):
            if origin is list or (len(args) == 2 and args[1] is Ellipsis):
                arm = args[0]
            elif index < len(args):
                arm = args[index]
            else:
                break
            found = _mistyped(arm, item)
            if found is not None:
                return (index, *found[0]), found[1]
    if origin is dict and isinstance(value, dict) and len(args) == 2:
        for key, item in value.items():
            found = _mistyped(args[1], item)
            if found is not None:
                return (key, *found[0]), found[1]
    return None


def degrees_in_place(value: object, name: str, both: str, limit: float | None = None) -> object:
    """A model's raw input with ``<name>_deg`` (degrees) turned into ``name`` (radians).

    Args:
        value: the raw input (only a mapping that holds ``<name>_deg`` changes).
        name: the radians field.
        both: the message when both fields are given.
        limit: the largest magnitude (deg) accepted, if any.

    Raises:
        FieldValueError: both fields given, or the degrees beyond ``limit``.
    """
    key = f"{name}_deg"
    if not isinstance(value, dict) or key not in value:
        return value
    if name in value:
        raise FieldValueError((key,), both)
    value = dict(value)
    degrees = value.pop(key)
    if isinstance(degrees, int | float) and not isinstance(degrees, bool):
        if limit is not None and not abs(degrees) <= limit:
            raise FieldValueError((key,), f"{key} {degrees}: expected -{limit:g}..{limit:g}")
        value[name] = math.radians(degrees)
    else:
        value[name] = degrees  # the field's own check says what is wrong with it
    return value
