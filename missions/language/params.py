"""Typed mission parameters, ``--set`` overrides and ``${name}`` substitution.

A parameter is declared with a type (``int``, ``float``, ``str``, ``bool`` or ``pose``), an
optional default, ``choices``, ``min``/``max`` and a description. ``--set table=5`` overrides
the default; the value is parsed by the declared type and checked against choices and bounds,
and a mistake is reported at the parameter's declaration. In the sections that take
parameters, a string that is exactly ``${table}`` becomes the typed value and
``table_${table}`` interpolates it into text; ``$${`` writes a literal ``${``.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from typing import Any, Literal

from pydantic import ConfigDict, Field, ValidationError, model_validator

from baobab.behaviours.poses import parse_pose
from baobab.missions.language.errors import MissionError, located
from baobab.sim.errors import SourceError, clip, unknown_name
from baobab.sim.yaml_models import YamlModel
from baobab.sim.yaml_source import FieldValueError, KeyPath, LocatedDocument, load_located_yaml

ParamType = Literal["int", "float", "str", "bool", "pose"]
PARAM_NAME_PATTERN = r"^[A-Za-z_][A-Za-z0-9_]*$"
_PLACEHOLDER = re.compile(r"\$(\$?)\{([^}]*)\}")
_NAME = re.compile(PARAM_NAME_PATTERN)
_TRUE = {"true", "yes", "on", "1"}
_FALSE = {"false", "no", "off", "0"}


class ParamSpec(YamlModel):
    """One declared parameter of a mission or a subtree."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    type: ParamType = Field(description="int, float, str, bool or pose")
    default: Any = Field(default=None, description="value when not set; none = must be set")
    choices: list[Any] | None = Field(
        default=None, min_length=1, description="the only values allowed"
    )
    min: float | None = Field(default=None, description="lower bound (int and float)")
    max: float | None = Field(default=None, description="upper bound (int and float)")
    description: str = ""

    @model_validator(mode="after")
    def _consistent(self) -> ParamSpec:
        numeric = self.type in ("int", "float")
        for bound in ("min", "max"):
            if getattr(self, bound) is not None and not numeric:
                raise FieldValueError((bound,), f"'{bound}' applies to int and float parameters")
        if self.min is not None and self.max is not None and self.min > self.max:
            raise FieldValueError(("max",), f"max {self.max:g} is below min {self.min:g}")
        if self.choices is not None:
            if self.type in ("bool", "pose"):
                raise FieldValueError(("choices",), f"'choices' does not apply to {self.type}")
            for index, choice in enumerate(self.choices):
                try:
                    self._typed(choice)
                except ValueError as exc:
                    raise FieldValueError(("choices", index), str(exc)) from None
            if len({repr(c) for c in self.choices}) != len(self.choices):
                raise FieldValueError(("choices",), "choices repeat a value")
        if self.default is not None:
            try:
                self.check(self.default)
            except ValueError as exc:
                raise FieldValueError(("default",), str(exc)) from None
        return self

    @property
    def required(self) -> bool:
        """True when there is no default, so the value must be given."""
        return self.default is None

    def describe_choices(self) -> str:
        """``1, 2, 3`` for messages."""
        return ", ".join(_format(choice) for choice in self.choices or [])

    def _typed(self, value: Any) -> Any:
        is_number = isinstance(value, int | float) and not isinstance(value, bool)
        if self.type == "int":
            if not isinstance(value, int) or isinstance(value, bool):
                raise ValueError(f"expected an integer, got {_shown(value)}")
            return value
        if self.type == "float":
            if not is_number or not math.isfinite(value):
                raise ValueError(f"expected a finite number, got {_shown(value)}")
            return float(value)
        if self.type == "str":
            if not isinstance(value, str):
                raise ValueError(f"expected a string, got {_shown(value)}")
            return value
        if self.type == "bool":
            if not isinstance(value, bool):
                raise ValueError(f"expected true or false, got {_shown(value)}")
            return value
        if isinstance(value, str):
            return value  # a location name, resolved where the parameter is used
        try:
            parse_pose(value)
        except ValidationError as exc:
            first = exc.errors(include_url=False)[0]
            where = ".".join(str(p) for p in first["loc"])
            detail = f"{where}: {first['msg']}" if where else first["msg"]
            raise ValueError(f"not a valid pose: {detail}") from None
        return value

    def check(self, value: Any) -> Any:
        """``value`` converted to the declared type and checked; ValueError if it does not fit."""
        typed = self._typed(value)
        if self.choices is not None and typed not in [self._typed(c) for c in self.choices]:
            raise ValueError(
                f"{_format(typed)} is not one of the choices {self.describe_choices()}"
            )
        if self.min is not None and typed < self.min:
            raise ValueError(f"{_format(typed)} is below the minimum {self.min:g}")
        if self.max is not None and typed > self.max:
            raise ValueError(f"{_format(typed)} is above the maximum {self.max:g}")
        return typed

    def parse_text(self, text: str) -> Any:
        """Parse a ``--set`` value written on the command line, then :meth:`check` it."""
        value: Any = text
        if self.type == "int":
            if not re.fullmatch(r"[+-]?\d+", text.strip()):
                raise ValueError(f"expected an integer, got '{clip(text)}'")
            value = int(text)
        elif self.type == "float":
            try:
                value = float(text)
            except ValueError:
                raise ValueError(f"expected a number, got '{clip(text)}'") from None
        elif self.type == "bool":
            word = text.strip().lower()
            if word not in _TRUE | _FALSE:
                raise ValueError(f"expected true or false, got '{clip(text)}'")
            value = word in _TRUE
        elif self.type == "pose":
            try:  # the file's limits (tags, depth, aliases, NaN) hold on the command line too
                value = load_located_yaml("--set", text=text).data
            except SourceError:
                raise ValueError(
                    f"expected a location name or a pose mapping, got '{clip(text)}'"
                ) from None
        return self.check(value)


def _shown(value: Any) -> str:
    """A value of the wrong type, for a message: ``true``, ``'text'``, ``[1, 2]``."""
    return _format(value) if isinstance(value, bool) else clip(repr(value))


def _format(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def parse_assignment(text: str) -> tuple[str, str]:
    """Split a ``--set`` argument ``KEY=VALUE``; ValueError when it has no ``=`` or no key."""
    key, sep, value = text.partition("=")
    if not sep or not key.strip():
        raise ValueError(f"expected KEY=VALUE, got '{clip(text)}'")
    return key.strip(), value


def resolve_values(
    specs: Mapping[str, ParamSpec],
    overrides: Mapping[str, str],
    document: LocatedDocument,
    base_path: KeyPath = ("params",),
) -> dict[str, Any]:
    """Each declared parameter's value: the ``--set`` text if given, else the default.

    Raises:
        MissionError: an unknown parameter (at ``params:``), a value that does not parse or fit
            (at its declaration), or a parameter with no default that was not set.
    """
    for name in overrides:
        if name not in specs:
            message = unknown_name("parameter", name, specs)
            raise located(
                document, base_path, f"--set {clip(name)}={clip(overrides[name])}: {message}"
            )
    values: dict[str, Any] = {}
    for name, spec in specs.items():
        if name in overrides:
            try:
                values[name] = spec.parse_text(overrides[name])
            except ValueError as exc:
                text = f"--set {name}={clip(overrides[name])}: {exc}"
                raise located(document, (*base_path, name), text) from None
        elif spec.required:
            text = f"parameter '{name}' has no default; give it with --set {name}=VALUE"
            raise located(document, (*base_path, name), text)
        else:
            values[name] = spec.check(spec.default)
    return values


class Substitution:
    """Replaces ``${name}`` in raw mission data, remembering where each value came from.

    Args:
        document: the mission document, to locate errors.
        values: the parameters in scope and their values.
        kinds: each parameter's declared type (``pose`` values cannot go inside text).
        scope: how messages name the scope, e.g. ``"the mission"`` or ``"subtree 'deliver'"``.
        note: appended to the origin of each substituted value (e.g. the call site).
    """

    def __init__(
        self,
        document: LocatedDocument,
        values: Mapping[str, Any],
        kinds: Mapping[str, str],
        scope: str,
        note: str = "",
    ) -> None:
        self.document = document
        self.values = values
        self.kinds = kinds
        self.scope = scope
        self.note = note
        self.origins: dict[KeyPath, str] = {}

    def apply(self, data: Any, path: KeyPath) -> Any:
        """``data`` (found at ``path``) with every placeholder replaced."""
        if isinstance(data, dict):
            return {key: self.apply(value, (*path, key)) for key, value in data.items()}
        if isinstance(data, list):
            return [self.apply(item, (*path, index)) for index, item in enumerate(data)]
        if isinstance(data, str) and "${" in data:
            return self._string(data, path)
        return data

    def _string(self, text: str, path: KeyPath) -> Any:
        if "${" in _PLACEHOLDER.sub("", text):
            raise located(self.document, path, f"unterminated '${{' in '{clip(text)}'")
        whole = _PLACEHOLDER.fullmatch(text)
        if whole is not None and not whole.group(1):
            name = self._name(whole.group(2), path)
            value = self.values[name]
            self.origins[path] = f"${{{name}}} = {_format(value)}{self.note}"
            return value
        used: list[str] = []

        def replace(match: re.Match[str]) -> str:
            if match.group(1):
                return "${" + match.group(2) + "}"
            name = self._name(match.group(2), path)
            if self.kinds.get(name) == "pose":
                raise located(
                    self.document,
                    path,
                    f"parameter '{name}' is a pose: use it as a whole value (${{{name}}}), "
                    "not inside text",
                )
            used.append(f"${{{name}}} = {_format(self.values[name])}")
            return _format(self.values[name])

        result = _PLACEHOLDER.sub(replace, text)
        if used:
            self.origins[path] = ", ".join(used) + self.note
        return result

    def _name(self, name: str, path: KeyPath) -> str:
        if not _NAME.fullmatch(name):
            raise located(
                self.document, path, f"'${{{name}}}' is not a parameter reference; write ${{name}}"
            )
        if name not in self.values:
            message = unknown_name("parameter", name, self.values, self.scope)
            raise located(self.document, path, message)
        return name


def find_placeholder(data: Any, path: KeyPath = ()) -> KeyPath | None:
    """Key path of the first ``${`` in ``data``, for sections that take no parameters."""
    if isinstance(data, dict):
        items: list[tuple[str | int, Any]] = list(data.items())
    elif isinstance(data, list):
        items = list(enumerate(data))
    else:
        return path if isinstance(data, str) and "${" in data else None
    for key, value in items:
        found = find_placeholder(value, (*path, key))
        if found is not None:
            return found
    return None


def check_no_placeholders(document: LocatedDocument, data: Any, path: KeyPath) -> None:
    """Refuse ``${...}`` in a section that is not substituted."""
    found = find_placeholder(data, path)
    if found is not None:
        raise MissionError(
            document.path,
            *document.locate(found),
            f"parameters are not substituted in '{path[0]}'; "
            "they work in start, tree, subtrees, events, timeout and expect",
        )
