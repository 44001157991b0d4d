"""Evaluate a mission's ``expect:`` block against how the run ended and what it measured.

Each expectation becomes an :class:`ExpectationResult` with the expectation's ``name``, the
value ``expected`` as written, the quantity ``measured`` that was compared with it, ``passed``,
and a one-line ``detail`` for people. Custom ``metrics:`` bounds are named ``metrics.<name>``.

Reference for ``max_path_length_ratio``: the planned path length when a navigation server
planned one, else the straight-line distance from the start to the final position.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from baobab.missions.language.errors import located
from baobab.missions.language.loader import Mission
from baobab.missions.language.models import (
    SPEED_LIMIT_TOLERANCE,
    Bounds,
    Expect,
    FinalPoseNear,
    ObjectPlaced,
)
from baobab.missions.run.metrics import MetricValue, numeric
from baobab.sim.errors import unknown_name


@dataclass(frozen=True)
class RunEnd:
    """How a run ended, as the expectations see it.

    Attributes:
        result: ``SUCCEEDED``, ``FAILED`` or ``CANCELED``.
        error_code: numeric error code (0 = none).
        error_name: the code's name (``NONE``, ``MISSION_TIMEOUT``, ``NO_VALID_PATH``...).
        sim_time: sim time at the end (s).
    """

    result: str
    error_code: int
    error_name: str
    sim_time: float


@dataclass(frozen=True)
class ExpectationResult:
    """One checked expectation."""

    name: str
    expected: Any
    measured: Any
    passed: bool
    detail: str = ""

    def as_dict(self) -> dict[str, Any]:
        """The JSON form: name, expected, measured, passed, detail."""
        return {
            "name": self.name,
            "expected": self.expected,
            "measured": self.measured,
            "passed": self.passed,
            "detail": self.detail,
        }


def check_metric_names(mission: Mission, numbers: list[str], every: list[str]) -> None:
    """Refuse ``expect: metrics:`` names that are not numeric metrics of this run.

    Args:
        mission: the mission whose ``expect`` block is checked.
        numbers: the run's numeric metrics (the ones bounds may name).
        every: all the run's metrics.

    Raises:
        MissionError: located at the first unknown or non-numeric name, before the run.
    """
    expect = mission.expect
    if expect is None or not expect.metrics:
        return
    for name in expect.metrics:
        if name in numbers:
            continue
        if name in every:
            message = f"metric '{name}' is not a number; bounds apply to: {', '.join(numbers)}"
        else:
            message = unknown_name("metric", name, numbers, f"runs of {mission.robot.name}")
        raise located(mission.document, ("expect", "metrics", name), message)


def evaluate(
    expect: Expect | None, end: RunEnd, metrics: Mapping[str, MetricValue], mission: Mission
) -> list[ExpectationResult]:
    """Check every expectation of ``expect`` (none when it is None), in the block's order."""
    if expect is None:
        return []
    checker = _Checker(end, metrics, mission)
    results: list[ExpectationResult] = []
    for key in type(expect).model_fields:
        value = getattr(expect, key)
        if value is None:
            continue
        if key == "metrics":
            results += [checker.bounds(name, bounds) for name, bounds in value.items()]
        else:
            results.append(getattr(checker, key)(value))
    return results


def _fmt(value: float | None, unit: str = "") -> str:
    if value is None:
        return "n/a"
    return f"{value:.3f}{' ' + unit if unit else ''}"


class _Checker:
    def __init__(self, end: RunEnd, metrics: Mapping[str, MetricValue], mission: Mission) -> None:
        self.end = end
        self.metrics = metrics
        self.mission = mission

    def _number(self, name: str) -> float | None:
        return numeric(self.metrics.get(name))

    def result(self, expected: str) -> ExpectationResult:
        measured = self.end.result
        return ExpectationResult(
            "result", expected, measured, measured == expected, f"ended {measured}"
        )

    def error_code(self, expected: int | str) -> ExpectationResult:
        end = self.end
        measured: int | str = end.error_code if isinstance(expected, int) else end.error_name
        return ExpectationResult(
            "error_code",
            expected,
            measured,
            measured == expected,
            f"error {end.error_code} ({end.error_name})",
        )

    def max_sim_time(self, limit: float) -> ExpectationResult:
        measured = self.end.sim_time
        return ExpectationResult(
            "max_sim_time",
            limit,
            measured,
            measured <= limit,
            f"{measured:.1f} s of sim time, at most {limit:g} s",
        )

    def final_pose_near(self, near: FinalPoseNear) -> ExpectationResult:
        expected = near.model_dump(exclude_none=True)
        final = self.metrics.get("final_pose")
        if near.location is not None:
            target = self.mission.locations[near.location]
            tx, ty, tyaw, label = target.x, target.y, target.yaw, near.location
        elif near.pose is not None:
            pose = near.pose.to_pose()
            tx, ty, tyaw, label = pose.x, pose.y, pose.yaw, f"({pose.x:.2f}, {pose.y:.2f})"
        else:  # the model requires one of the two
            return ExpectationResult("final_pose_near", expected, None, False, "no target")
        if not isinstance(final, dict):
            return ExpectationResult("final_pose_near", expected, None, False, "no final pose")
        distance = math.hypot(float(final["x"]) - tx, float(final["y"]) - ty)
        passed = distance <= near.xy_tolerance
        detail = f"{distance:.3f} m from {label} (tolerance {near.xy_tolerance:g} m)"
        if near.yaw_tolerance is not None:
            heading = abs(math.remainder(float(final["yaw"]) - tyaw, math.tau))
            passed = passed and heading <= near.yaw_tolerance
            detail += f", heading off by {heading:.3f} rad (tolerance {near.yaw_tolerance:g})"
        return ExpectationResult("final_pose_near", expected, distance, passed, detail)

    def visited_in_order(self, expected: list[str]) -> ExpectationResult:
        visited = self.metrics.get("visited")
        names = [str(v) for v in visited] if isinstance(visited, list) else []
        remaining = iter(names)
        passed = all(any(name == seen for seen in remaining) for name in expected)
        return ExpectationResult(
            "visited_in_order",
            expected,
            names,
            passed,
            f"visited {' -> '.join(names) or 'nothing'}",
        )

    def min_clearance(self, limit: float) -> ExpectationResult:
        measured = self._number("min_clearance")
        if measured is None:
            return ExpectationResult(
                "min_clearance", limit, None, True, "no obstacle came within the measuring range"
            )
        return ExpectationResult(
            "min_clearance",
            limit,
            measured,
            measured >= limit,
            f"closest {measured:.3f} m, at least {limit:g} m",
        )

    def no_contact(self, expected: bool) -> ExpectationResult:
        contacts = int(self._number("contacts") or 0)
        touched = self.metrics.get("contact_objects")
        names = ", ".join(str(n) for n in touched) if isinstance(touched, list) else ""
        detail = f"{contacts} contact samples" + (f" ({names})" if names else "")
        return ExpectationResult(
            "no_contact", expected, contacts, (contacts == 0) == expected, detail
        )

    def no_keepout_entry(self, expected: bool) -> ExpectationResult:
        clearance = self._number("min_keepout_clearance")
        if clearance is None:  # validation made sure of the mask: it has no zone
            return ExpectationResult(
                "no_keepout_entry", expected, None, expected, "no keepout zone in the mask"
            )
        entered = clearance < 0.0
        detail = (
            f"the footprint reached {-clearance:.3f} m into a keepout zone"
            if entered
            else f"the footprint stayed {clearance:.3f} m from the keepout zones"
        )
        return ExpectationResult(
            "no_keepout_entry", expected, clearance, entered != expected, detail
        )

    def within_speed_limits(self, expected: bool) -> ExpectationResult:
        excess = self._number("speed_limit_excess")
        if excess is None:
            return ExpectationResult("within_speed_limits", expected, None, False, "no speed mask")
        within = excess <= SPEED_LIMIT_TOLERANCE
        detail = (
            f"at most {excess:.3f} m/s over a speed limit (tolerance {SPEED_LIMIT_TOLERANCE:g} m/s)"
        )
        return ExpectationResult(
            "within_speed_limits", expected, excess, within == expected, detail
        )

    def max_path_length_ratio(self, limit: float) -> ExpectationResult:
        driven = self._number("path_length")
        planned = self._number("planned_path_length")
        reference, what = (
            (planned, "planned")
            if planned
            else (self._number("straight_line_distance"), "straight-line")
        )
        if driven is None or reference is None or reference < 1e-6:
            return ExpectationResult(
                "max_path_length_ratio", limit, None, False, f"no {what} distance to compare with"
            )
        ratio = driven / reference
        return ExpectationResult(
            "max_path_length_ratio",
            limit,
            ratio,
            ratio <= limit,
            f"drove {driven:.2f} m for {reference:.2f} m {what}",
        )

    def max_recoveries(self, limit: int) -> ExpectationResult:
        measured = int(self._number("number_of_recoveries") or 0)
        return ExpectationResult(
            "max_recoveries", limit, measured, measured <= limit, f"{measured} recoveries"
        )

    def object_lifted(self, height: float) -> ExpectationResult:
        lift = self._number("object_max_lift")
        passed = lift is not None and lift >= height
        return ExpectationResult(
            "object_lifted",
            height,
            lift,
            passed,
            f"lifted {_fmt(lift, 'm')}, at least {height:g} m",
        )

    def object_placed(self, placed: ObjectPlaced) -> ExpectationResult:
        expected = placed.model_dump()
        objects = self.mission.robot.scene_objects
        position = self.metrics.get(f"{objects[0]}_final_position") if objects else None
        if isinstance(placed.target, str):
            target = self.mission.locations[placed.target].position
        else:
            target = placed.target
        if not isinstance(position, list):
            return ExpectationResult("object_placed", expected, None, False, "no object")
        distance = math.dist([float(v) for v in position], target)
        return ExpectationResult(
            "object_placed",
            expected,
            distance,
            distance <= placed.tolerance,
            f"{objects[0]} {distance:.3f} m from the target (tolerance {placed.tolerance:g} m)",
        )

    def bounds(self, name: str, bounds: Bounds) -> ExpectationResult:
        expected = bounds.model_dump(exclude_none=True)
        value = self._number(name)
        if value is None:
            return ExpectationResult(
                f"metrics.{name}", expected, self.metrics.get(name), False, "not a measured number"
            )
        passed = (bounds.min is None or value >= bounds.min) and (
            bounds.max is None or value <= bounds.max
        )
        low = "" if bounds.min is None else f"{bounds.min:g} <= "
        high = "" if bounds.max is None else f" <= {bounds.max:g}"
        return ExpectationResult(
            f"metrics.{name}", expected, value, passed, f"{low}{value:.4g}{high}"
        )


def all_passed(results: list[ExpectationResult]) -> bool:
    """True when every expectation held (also for an empty list)."""
    return all(result.passed for result in results)
