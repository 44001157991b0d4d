"""What a campaign varies: the keys, the distributions, and parsing ``--vary``/``--grid``.

A variation is written ``KEY=DIST`` (``--vary``) or ``KEY=v1,v2,...`` (``--grid``). Keys:

- a mission parameter, ``table`` or ``params.table``: the value goes to the run as
  ``--set table=...``, checked by the parameter's declared type, choices and bounds;
- ``start.x``, ``start.y`` (m) and ``start.yaw`` (rad) of a mobile robot: offsets added to
  the mission's start pose;
- ``noise.lidar_std`` (m): the lidar's range noise (robots with a lidar);
- ``robot``: the robot, one of the bundled mobile robots the mission fits (its ``robots:``
  when it lists them) or a robot file in the mission's folder, with ``choice`` or ``--grid``:
  ``--vary robot=choice(NAME,NAME)`` (names from ``baobab list``);
- ``events.N.at``, ``events.N.duration`` and ``events.N.KIND.FIELD`` for the N-th event of
  the file's ``events:`` list (0-based), e.g. ``events.0.spawn_obstacle.x`` (m): the value
  replaces the one written.

Distributions: ``uniform(a,b)``, ``normal(mu,sigma)``, ``randint(a,b)`` (integers, both
ends included), ``choice(v1,v2,...)``, and the grid axis ``grid(a,b,n)`` (n evenly spaced
values from a to b, both included). ``--grid KEY=v1,v2,...`` is a grid axis of listed values.
Values are checked here, before anything runs: a choice or grid value a parameter refuses,
``uniform`` bounds outside a parameter's ``min``/``max``, a real-number distribution on an
``int`` or text parameter. ``normal`` draws beyond a parameter's bounds make INVALID runs.
Drawn numbers are rounded to :data:`SIGNIFICANT_DIGITS` significant digits, the value then
used, so that replay commands stay short and exact.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from baobab.missions.language.loader import Mission
from baobab.missions.language.models import (
    EVENT_KINDS,
    ObstacleMove,
    ObstacleSpawn,
    TeleopCommand,
)
from baobab.missions.language.params import ParamSpec
from baobab.robots.catalog import MOBILE_ROBOTS, robot_named
from baobab.robots.robot_file import is_robot_path
from baobab.sim.errors import BaobabError, clip, unknown_name
from baobab.sim.yaml_source import KeyPath

SIGNIFICANT_DIGITS = 6
MAX_CHECKED_INTEGERS = 10_000
"""``randint`` on a parameter with choices checks every value up to this many."""
DISTRIBUTIONS = "uniform(a,b), normal(mu,sigma), randint(a,b), choice(v1,v2,...), grid(a,b,n)"
_CALL = re.compile(r"^\s*([A-Za-z_]\w*)\s*\((.*)\)\s*$", re.DOTALL)
_EVENT_FIELDS: dict[str, tuple[str, ...]] = {
    "spawn_obstacle": tuple(k for k in ObstacleSpawn.model_fields if k not in ("name", "size")),
    "move_obstacle": tuple(k for k in ObstacleMove.model_fields if k != "name"),
    "teleop": tuple(TeleopCommand.model_fields),
}
"""Numeric fields of each event kind that a campaign can vary."""


class CampaignError(BaobabError):
    """Invalid campaign input (``--vary``, ``--grid``, ``--runs``...): one line, exit 2."""


# --- distributions --------------------------------------------------------------------------


def rounded(value: float) -> float:
    """``value`` kept to :data:`SIGNIFICANT_DIGITS` significant digits."""
    return float(f"{value:.{SIGNIFICANT_DIGITS}g}")


@dataclass(frozen=True)
class Uniform:
    """Uniform on [low, high)."""

    low: float
    high: float

    def draw(self, rng: np.random.Generator) -> float:
        """One value."""
        return rounded(rng.uniform(self.low, self.high))


@dataclass(frozen=True)
class Normal:
    """Normal with mean ``mean`` and standard deviation ``std``."""

    mean: float
    std: float

    def draw(self, rng: np.random.Generator) -> float:
        """One value."""
        return rounded(rng.normal(self.mean, self.std))


@dataclass(frozen=True)
class RandInt:
    """A whole number from ``low`` to ``high``, both included."""

    low: int
    high: int

    def draw(self, rng: np.random.Generator) -> int:
        """One value."""
        return int(rng.integers(self.low, self.high, endpoint=True))


@dataclass(frozen=True)
class Choice:
    """One of the values as written, each as likely."""

    values: tuple[str, ...]

    def draw(self, rng: np.random.Generator) -> str:
        """One value."""
        return self.values[int(rng.integers(len(self.values)))]


Distribution = Uniform | Normal | RandInt | Choice


# --- what a key points at -------------------------------------------------------------------


@dataclass(frozen=True)
class Target:
    """What a variation key changes in the mission.

    Attributes:
        key: the key as shown in results (``table``, ``start.x``, ``events.0.at``...).
        kind: ``param`` (a ``--set`` value), ``start`` (an offset), ``data`` (a value written
            into the mission file's data) or ``robot`` (the ``robot:`` written into it).
        path: the parameter name, the start axis, or the key path in the mission data.
        spec: the parameter's declaration (``param`` only).
    """

    key: str
    kind: Literal["param", "start", "data", "robot"]
    path: KeyPath
    spec: ParamSpec | None = None
    choices: tuple[str, ...] = ()
    """The robots a ``robot`` target takes."""

    @property
    def numeric_only(self) -> bool:
        """True when the value must be a number."""
        if self.kind == "robot":
            return False
        return self.spec is None or self.spec.type in ("int", "float")

    def typed(self, value: str | float) -> Any:
        """The value this target receives (a parameter's typed value, else a float).

        Raises:
            ValueError: the value does not fit.
        """
        if self.spec is not None:
            return self.spec.parse_text(format_value(value))
        if self.kind == "robot":
            return robot_value(str(value), self.choices)
        try:
            number = float(value)
        except ValueError:
            number = math.nan
        if not math.isfinite(number):
            raise ValueError(f"expected a finite number (m or rad), got '{value}'")
        return number


def robot_value(value: str, choices: Sequence[str]) -> str:
    """The robot ``value`` names (a bundled one's name, or a robot file), if it is one of
    ``choices`` (a robot file is allowed when they are the bundled mobile robots).

    Raises:
        ValueError: a robot the mission does not fit.
    """
    if is_robot_path(value) and set(choices) >= set(MOBILE_ROBOTS):
        return value
    robot = robot_named(value)
    if robot is None or robot.name not in choices:
        raise ValueError(f"the mission fits {', '.join(choices)}, not '{value}'")
    return robot.name


def format_value(value: str | float) -> str:
    """A value as ``--set`` text: whole floats without ``.0``, other floats exactly."""
    if isinstance(value, str):
        return value
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return repr(value)


def variable_keys(mission: Mission) -> dict[str, Target]:
    """Every key this mission can vary, by key."""
    targets: dict[str, Target] = {}
    specs = _param_specs(mission)
    for name, spec in specs.items():
        targets[name] = Target(name, "param", (name,), spec)
    if mission.robot.mobile:
        for axis in ("x", "y", "yaw"):
            targets[f"start.{axis}"] = Target(f"start.{axis}", "start", (axis,))
    if mission.robot.has_lidar:
        targets["noise.lidar_std"] = Target("noise.lidar_std", "data", ("noise", "lidar_std"))
    if mission.robot.mobile and "robot" not in targets:  # a parameter of that name wins
        fits = mission.supported_robots or MOBILE_ROBOTS
        targets["robot"] = Target("robot", "robot", ("robot",), choices=tuple(fits))
    raw_events = mission.document.data.get("events") or []
    for index, event in enumerate(raw_events if isinstance(raw_events, list) else []):
        if not isinstance(event, dict):
            continue
        fields: list[KeyPath] = [("at",)]
        for kind in EVENT_KINDS:
            if kind in event:
                if kind == "teleop":
                    fields.append(("duration",))
                fields += [(kind, name) for name in _EVENT_FIELDS.get(kind, ())]
        for sub in fields:
            key = ".".join(["events", str(index), *map(str, sub)])
            targets[key] = Target(key, "data", ("events", index, *sub))
    return targets


def _param_specs(mission: Mission) -> dict[str, ParamSpec]:
    raw = mission.document.data.get("params") or {}
    return {name: ParamSpec.model_validate(spec) for name, spec in raw.items()}


def find_target(key: str, targets: Mapping[str, Target], option: str) -> Target:
    """The target of ``key`` (``params.NAME`` is the same as ``NAME``).

    Raises:
        CampaignError: an unknown key, with the closest valid one.
    """
    name = key.removeprefix("params.")
    if name in targets:
        return targets[name]
    raise CampaignError(f"{option}: {unknown_name('key', key, targets)}")


# --- parsing --------------------------------------------------------------------------------


@dataclass(frozen=True)
class Variation:
    """A random variation: ``--vary KEY=DIST``."""

    target: Target
    distribution: Distribution


@dataclass(frozen=True)
class GridAxis:
    """A grid axis: its key's values, in order, as text."""

    target: Target
    values: tuple[str, ...]


def split_assignment(text: str, option: str) -> tuple[str, str]:
    """``KEY=VALUE`` -> (key, value); CampaignError when there is no ``=`` or no key."""
    key, sep, value = text.partition("=")
    if not sep or not key.strip() or not value.strip():
        raise CampaignError(
            f"{option} '{text}': expected KEY=VALUE, e.g. start.x=uniform(-0.2,0.2)"
        )
    return key.strip(), value.strip()


def parse_vary(
    text: str, targets: Mapping[str, Target], max_points: int | None = None
) -> Variation | GridAxis:
    """Parse one ``--vary KEY=DIST`` (a ``grid(a,b,n)`` gives a grid axis).

    Args:
        text: the option's value.
        targets: the keys the mission can vary.
        max_points: the most values a grid axis may have (checked before its values are made).

    Raises:
        CampaignError: bad syntax, an unknown key or distribution, numbers that do not fit,
            a grid of more than ``max_points`` values.
    """
    option = f"--vary {clip(text)}"
    key, dist = split_assignment(text, "--vary")
    target = find_target(key, targets, option)
    call = _CALL.match(dist)
    if call is None:
        raise CampaignError(f"{option}: expected a distribution: {DISTRIBUTIONS}")
    name, inside = call.group(1), call.group(2)
    args = [part.strip() for part in inside.split(",")] if inside.strip() else []
    if any(not arg for arg in args):
        raise CampaignError(f"{option}: an empty value in '{dist}'")
    if name == "choice":
        if not args:
            raise CampaignError(f"{option}: choice needs at least one value")
        _check_values(target, args, option)
        return Variation(target, Choice(tuple(args)))
    if name == "grid":
        low, high, count = _numbers(args, 3, "grid(a,b,n)", option)
        if not count.is_integer() or count < 2:
            raise CampaignError(f"{option}: n in grid(a,b,n) is a whole number >= 2")
        _check_points(count, max_points, option)
        values = tuple(
            format_value(rounded(v)) for v in np.linspace(low, high, int(count)).tolist()
        )
        _check_values(target, values, option)
        return GridAxis(target, values)
    if name == "uniform":
        low, high = _numbers(args, 2, "uniform(a,b)", option)
        if not low < high:
            raise CampaignError(f"{option}: uniform(a,b) needs a < b")
        _check_continuous(target, option, "uniform", (low, high))
        return Variation(target, Uniform(low, high))
    if name == "normal":
        mean, std = _numbers(args, 2, "normal(mu,sigma)", option)
        if not std > 0:
            raise CampaignError(f"{option}: normal(mu,sigma) needs sigma > 0")
        _check_continuous(target, option, "normal", None)
        return Variation(target, Normal(mean, std))
    if name == "randint":
        low, high = _numbers(args, 2, "randint(a,b)", option)
        if not target.numeric_only:
            raise CampaignError(f"{option}: '{target.key}' is not a number; use choice or grid")
        if not (low.is_integer() and high.is_integer()) or low > high:
            raise CampaignError(f"{option}: randint(a,b) needs whole numbers a <= b")
        span = range(int(low), int(high) + 1)
        every = target.spec is not None and target.spec.choices is not None
        ends = span if every and len(span) <= MAX_CHECKED_INTEGERS else (span[0], span[-1])
        _check_values(target, [str(value) for value in ends], option)
        return Variation(target, RandInt(int(low), int(high)))
    raise CampaignError(f"{option}: {unknown_name('distribution', name, _DIST_NAMES)}")


_DIST_NAMES = ("uniform", "normal", "randint", "choice", "grid")


def parse_grid(text: str, targets: Mapping[str, Target], max_points: int | None = None) -> GridAxis:
    """Parse one ``--grid KEY=v1,v2,...``.

    Raises:
        CampaignError: bad syntax, an unknown key, a value that does not fit, a repeat, more
            than ``max_points`` values.
    """
    option = f"--grid {clip(text)}"
    key, listed = split_assignment(text, "--grid")
    target = find_target(key, targets, option)
    _check_points(listed.count(",") + 1, max_points, option)
    values = [part.strip() for part in listed.split(",")]
    if any(not value for value in values):
        raise CampaignError(f"{option}: an empty value in '{listed}'")
    if len(set(values)) != len(values):
        raise CampaignError(f"{option}: a value is listed twice")
    _check_values(target, values, option)
    return GridAxis(target, tuple(values))


def _check_points(count: float, max_points: int | None, option: str) -> None:
    if max_points is not None and count > max_points:
        raise CampaignError(
            f"{option}: {count:.0f} grid values; at most {max_points} fit in one campaign with "
            "the other grid axes and --runs (MAX_RUNS)"
        )


def _numbers(args: Sequence[str], count: int, form: str, option: str) -> list[float]:
    if len(args) != count:
        raise CampaignError(f"{option}: {form} takes {count} numbers, got {len(args)}")
    numbers: list[float] = []
    for arg in args:
        try:
            number = float(arg)
        except ValueError:
            raise CampaignError(f"{option}: '{arg}' is not a number in {form}") from None
        if not math.isfinite(number):
            raise CampaignError(f"{option}: '{arg}' is not a finite number in {form}")
        numbers.append(number)
    return numbers


def _check_values(target: Target, values: Sequence[str], option: str) -> None:
    for value in values:
        try:
            target.typed(value)
        except ValueError as exc:
            raise CampaignError(f"{option}: {target.key}={value}: {exc}") from None


def _check_continuous(
    target: Target, option: str, name: str, interval: tuple[float, float] | None
) -> None:
    spec = target.spec
    if spec is None:
        return
    if spec.type != "float":
        other = "randint(a,b), choice or grid" if spec.type == "int" else "choice or --grid"
        raise CampaignError(
            f"{option}: '{target.key}' is {'an' if spec.type == 'int' else 'a'} {spec.type} "
            f"parameter; {name} draws real numbers, "
            f"use {other}"
        )
    if spec.choices is not None:
        raise CampaignError(
            f"{option}: '{target.key}' takes only {spec.describe_choices()}; use choice or grid"
        )
    if interval is not None:
        low, high = interval
        if (spec.min is not None and low < spec.min) or (spec.max is not None and high > spec.max):
            bounds = f"[{'-inf' if spec.min is None else f'{spec.min:g}'}, " + (
                f"{'inf' if spec.max is None else f'{spec.max:g}'}]"
            )
            raise CampaignError(f"{option}: reaches outside {target.key}'s bounds {bounds}")
