"""The record of one Nav2 parameter baobab maps, its type and range checks, and unit converters.

A :class:`Mapped` row (the table is :mod:`baobab.nav.nav2_param_table`) says which
:class:`~baobab.nav.server.NavigationParams` fields a Nav2 parameter sets, checks a value's type
(``float`` accepts whole numbers, as users write ``inflation_radius: 1``; ``tuple`` is Nav2's
``[x, y, theta]``) and range, and converts Nav2's units to baobab's.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from baobab.sim.errors import clip

Check = Callable[[Any], str | None]
"""Returns what is wrong with a value of the right type (None: nothing)."""


def positive(value: float) -> str | None:
    """Refuses zero and negative values."""
    return None if value > 0 else f"must be positive, got {value}"


def non_negative(value: float) -> str | None:
    """Refuses negative values."""
    return None if value >= 0 else f"must not be negative, got {value}"


def non_positive(value: float) -> str | None:
    """Refuses positive values (Nav2's deceleration limits are negative)."""
    return None if value <= 0 else f"must not be positive (a deceleration), got {value}"


def each_non_negative(values: list[float]) -> str | None:
    """Refuses a negative entry."""
    return None if min(values) >= 0 else f"must not hold negative values, got {values}"


def each_non_positive(values: list[float]) -> str | None:
    """Refuses a positive entry (decelerations, lowest velocities)."""
    return None if max(values) <= 0 else f"must not hold positive values, got {values}"


def one_of(*choices: str) -> Check:
    """Refuses any text but ``choices``."""

    def check(value: str) -> str | None:
        return None if value in choices else f"must be one of {', '.join(choices)}, got '{value}'"

    return check


def tolerance_or_unlimited(value: float) -> str | None:
    """A non-negative duration, or Nav2's -1 for no limit."""
    return None if value >= 0 or value == -1 else f"must be >= 0 or -1 (no limit), got {value}"


@dataclass(frozen=True)
class Mapped:
    """A Nav2 parameter baobab uses.

    Attributes:
        name: the name Nav2 declares (inside the plugin's namespace for a plugin's rows).
        targets: the ``NavigationParams`` fields it sets (dotted; ``{costmap}`` placeholder).
        kind: ``float`` (an int is accepted too), ``int``, ``bool`` or ``str``.
        unit: its unit as Nav2 states it ("" for none).
        default: Nav2's default (code default unless nav2_bringup's file is the usual one).
        meaning: what it does in Nav2, in a few words.
        check: a range check beyond the type.
        convert: Nav2's value -> baobab's (units differ, or a sentinel such as -1).
        aliases: older names Nav2 still reads (``desired_linear_vel`` for ``max_linear_vel``).
    """

    name: str
    targets: tuple[str, ...]
    kind: type
    unit: str
    default: Any
    meaning: str
    check: Check | None = None
    convert: Callable[[Any], Any] | None = None
    aliases: tuple[str, ...] = ()

    def problem(self, value: Any) -> str | None:
        """What is wrong with ``value`` for this parameter, or None."""
        if not _has_kind(value, self.kind):
            return f"must be {_KIND_NAMES[self.kind]}, got {_shown(value)}"
        return None if self.check is None else self.check(value)

    def baobab_value(self, value: Any) -> Any:
        """``value`` (already checked) as the ``NavigationParams`` fields hold it."""
        if self.kind is float:
            value = float(value)
        return value if self.convert is None else self.convert(value)


_KIND_NAMES = {
    float: "a number",
    int: "a whole number",
    bool: "true or false",
    str: "a string",
    tuple: "three numbers [x, y, theta]",
}


def _has_kind(value: Any, kind: type) -> bool:
    if kind is tuple:
        return isinstance(value, list) and len(value) == 3 and all(map(_is_number, value))
    if isinstance(value, bool):
        return kind is bool
    if kind is float:
        return _is_number(value)
    return isinstance(value, kind)


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _shown(value: Any) -> str:
    if isinstance(value, str):
        return f"'{clip(value)}'"
    if isinstance(value, bool):
        return "true" if value else "false"
    return clip(value)


def row(
    name: str,
    targets: str | tuple[str, ...],
    kind: type,
    unit: str,
    default: Any,
    meaning: str,
    check: Check | None = None,
    **more: Any,
) -> Mapped:
    fields = (targets,) if isinstance(targets, str) else targets
    return Mapped(name, fields, kind, unit, default, meaning, check, **more)


def unlimited(value: float) -> float:
    return math.inf if value < 0 else value


def axes(values: list[float]) -> tuple[float, float]:
    """Nav2's ``[x, y, theta]`` as baobab's differential-drive ``(x, theta)``."""
    return float(values[0]), float(values[2])


def milliseconds(value: int) -> float:
    return value / 1000.0


def same_names(prefix: str, *specs: tuple[Any, ...]) -> tuple[Mapped, ...]:
    """Rows whose ``NavigationParams`` field is ``prefix`` + the Nav2 name.

    Each spec is ``(name, kind, unit, default, meaning, check)``.
    """
    return tuple(
        Mapped(name, (prefix + name,), kind, unit, default, meaning, check)
        for name, kind, unit, default, meaning, check in specs
    )
