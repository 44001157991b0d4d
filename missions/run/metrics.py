"""Run metrics: a small registry of named values, read when the run ends.

A metric is a name, a unit and a function that reads its value at the end of the run; the
``metrics:`` bounds of an ``expect:`` block may name any metric whose value is a number. The
probes that measure a robot inside sim callbacks are :mod:`baobab.missions.run.mobile_probe`
and :mod:`baobab.missions.run.arm_probes`; assisted teleop's totals are registered here.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from baobab.sim.errors import BaobabError

MetricValue = float | int | str | bool | list[Any] | dict[str, Any] | None
"""A metric's value: a number, or structured data (poses, lists of names); None if unknown."""


class MetricError(BaobabError):
    """A metric name registered twice."""


@dataclass(frozen=True)
class Metric:
    """One registered metric.

    Attributes:
        name: the key in ``metrics`` of result.json and in ``expect: metrics:``.
        read: returns the value (called when the run ends).
        unit: SI unit, or ``""``.
        description: one line.
        number: True when the value is a number (or None when not measured), so that
            ``expect: metrics:`` can bound it; False for structured data (poses, names).
    """

    name: str
    read: Callable[[], MetricValue]
    unit: str = ""
    description: str = ""
    number: bool = True


class MetricRegistry:
    """The metrics of one run, by name, in registration order."""

    def __init__(self) -> None:
        self._metrics: dict[str, Metric] = {}

    def add(
        self,
        name: str,
        read: Callable[[], MetricValue],
        *,
        unit: str = "",
        description: str = "",
        number: bool = True,
    ) -> None:
        """Register a metric (see :class:`Metric` for the arguments).

        Raises:
            MetricError: if ``name`` is taken.
        """
        if name in self._metrics:
            raise MetricError(f"metric '{name}' is registered twice")
        self._metrics[name] = Metric(name, read, unit, description, number)

    def __contains__(self, name: object) -> bool:
        return name in self._metrics

    def names(self) -> list[str]:
        """Registered names, in order."""
        return list(self._metrics)

    def number_names(self) -> list[str]:
        """Names of the metrics whose values are numbers (the ones bounds may name)."""
        return [name for name, metric in self._metrics.items() if metric.number]

    def values(self) -> dict[str, MetricValue]:
        """Every metric's current value."""
        return {name: metric.read() for name, metric in self._metrics.items()}

    def units(self) -> dict[str, str]:
        """Each metric's unit."""
        return {name: metric.unit for name, metric in self._metrics.items()}


def numeric(value: MetricValue) -> float | None:
    """``value`` as a float when it is a number (not a bool), else None."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value)


class TeleopTotals(Protocol):
    """What assisted teleop counts (``baobab.nav.behaviors.AssistedTeleopStats``)."""

    min_scaling: float | None
    slowed_cycles: int
    max_linear: float
    costmap_clears: int


def register_teleop_metrics(
    metrics: MetricRegistry, totals: Callable[[], TeleopTotals | None]
) -> None:
    """Add the assisted teleop metrics; ``totals()`` is None when the robot has no teleop."""

    def read(name: str) -> MetricValue:
        found = totals()
        return None if found is None else getattr(found, name)

    for metric, attribute, unit, description in (
        (
            "teleop_min_scaling",
            "min_scaling",
            "",
            "smallest factor assisted teleop applied to a teleop command (1: never slowed, "
            "0: stopped); null without one",
        ),
        (
            "teleop_slowed_cycles",
            "slowed_cycles",
            "",
            "assisted teleop cycles that scaled the command by a factor between 0 and 1",
        ),
        ("teleop_max_speed", "max_linear", "m/s", "largest forward speed assisted teleop sent"),
        ("teleop_costmap_clears", "costmap_clears", "", "costmap clearings by assisted teleop"),
    ):
        metrics.add(metric, functools.partial(read, attribute), unit=unit, description=description)


class MonitorTotals(Protocol):
    """What the collision monitor counts (``baobab.nav.collision_monitor.CollisionMonitor``)."""

    stops: int
    acting_time: float


def register_collision_monitor_metrics(
    metrics: MetricRegistry, monitor: Callable[[], MonitorTotals | None]
) -> None:
    """Add the collision monitor metrics; ``monitor()`` is None when the robot has none (0)."""

    def read(name: str) -> MetricValue:
        found = monitor()
        return 0 if found is None else getattr(found, name)

    metrics.add(
        "collision_monitor_stops",
        functools.partial(read, "stops"),
        description="times the collision monitor began to stop the robot",
    )
    metrics.add(
        "collision_monitor_time",
        functools.partial(read, "acting_time"),
        unit="s",
        description="sim time during which the collision monitor changed the commands",
    )
