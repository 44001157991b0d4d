"""Performance baselines: compare a run's key metrics with a stored JSON file.

``baobab run MISSION --baseline FILE`` reads FILE (when it exists) before the run and, after
it, checks each baseline metric the run also measured: a regression is a value above
``baseline * (1 + tolerance) + slack``, with the tolerance (default 10 %) and the absolute
slack per metric stored in the file. Each comparison is reported as an expectation named
``baseline.<metric>``; a regression makes the run "not as intended" (exit 1).

When FILE does not exist, it is created from this run ("baseline created"), but only when the
run turned out as intended: a failed run is no reference. The file is written atomically.

File format (JSON)::

    {"baobab_baseline": 1, "mission": "walls_go_to_goal", "seed": 2, "params": {},
     "tolerance": 0.1, "slack": {"sim_time": 0.5, ...}, "metrics": {"sim_time": 14.8, ...}}
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from baobab.sim.errors import SourceError, clip
from baobab.sim.input_files import read_input_file
from baobab.sim.text_positions import TextPositions

if TYPE_CHECKING:
    from baobab.missions.run.expectations import ExpectationResult
    from baobab.missions.run.metrics import MetricValue

# Reading a baseline loads nothing heavy (a bad --baseline is refused as fast as a bad
# mission); comparing and writing load the run's metrics and expectations.

FORMAT_VERSION = 1
DEFAULT_TOLERANCE = 0.10
"""Relative tolerance before a larger value counts as a regression."""
DEFAULT_SLACK: dict[str, float] = {
    "sim_time": 0.5,
    "path_length": 0.05,
    "tcp_path_length": 0.02,
    "number_of_recoveries": 0.0,
}
"""The compared metrics (lower is better) and their absolute slack (s, m, m, count)."""


class BaselineError(SourceError):
    """A baseline file that cannot be read: ``path:line:col: message``."""


@dataclass(frozen=True)
class Baseline:
    """A stored baseline.

    Attributes:
        path: the file.
        mission: the mission name it was made from.
        metrics: baseline values by metric name.
        tolerance: relative tolerance (0.1 = 10 %).
        slack: absolute slack by metric name.
        seed: the seed of the run that made it.
    """

    path: Path
    mission: str
    metrics: dict[str, float]
    tolerance: float = DEFAULT_TOLERANCE
    slack: dict[str, float] = field(default_factory=lambda: dict(DEFAULT_SLACK))
    seed: int | None = None

    def allowed(self, name: str) -> float:
        """The largest value of ``name`` that is not a regression."""
        return self.metrics[name] * (1.0 + self.tolerance) + self.slack.get(name, 0.0)


def read_baseline(path: Path, mission: str) -> Baseline | None:
    """The baseline in ``path``, or None when the file does not exist.

    Raises:
        BaselineError: unreadable JSON, a wrong shape, or a baseline of another mission.
    """
    if not os.path.lexists(path):
        return None
    raw = read_input_file(path, BaselineError, expected="a baseline JSON file")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line, column = TextPositions(raw[: exc.start].decode("utf-8")).of_index(exc.start)
        raise BaselineError(path, line, column, "not valid UTF-8 text") from None
    try:
        data = json.loads(text)
    except RecursionError:
        raise _too_deep(path, text) from None
    except json.JSONDecodeError as exc:
        raise BaselineError(path, exc.lineno, exc.colno, f"not valid JSON: {exc.msg}") from None
    except ValueError as exc:  # a number of more than 4300 digits
        raise BaselineError(path, 1, 1, f"not a usable JSON value: {exc}") from None
    if not isinstance(data, dict) or data.get("baobab_baseline") != FORMAT_VERSION:
        raise BaselineError(
            path, 1, 1, f'not a baobab baseline (expected "baobab_baseline": {FORMAT_VERSION})'
        )
    if data.get("mission") != mission:
        raise BaselineError(
            path, 1, 1, f"baseline of mission '{clip(data.get('mission'))}', not of '{mission}'"
        )
    metrics = _numbers(path, data.get("metrics"), "metrics")
    slack = {**DEFAULT_SLACK, **_numbers(path, data.get("slack", {}), "slack")}
    tolerance = data.get("tolerance", DEFAULT_TOLERANCE)
    if isinstance(tolerance, bool) or not isinstance(tolerance, int | float) or tolerance < 0:
        raise BaselineError(
            path, 1, 1, f"tolerance must be a number >= 0, got {clip(repr(tolerance))}"
        )
    seed = data.get("seed")
    return Baseline(
        path, mission, metrics, float(tolerance), slack, seed if isinstance(seed, int) else None
    )


MAX_JSON_DEPTH = 64
"""Where a baseline too deeply nested for Python's JSON parser is blamed (a baseline nests 2)."""


def _too_deep(path: Path, text: str) -> BaselineError:
    """The error for JSON that nests past the parser's recursion limit, at the bracket that
    first nests deeper than :data:`MAX_JSON_DEPTH`."""
    depth, in_string, escaped = 0, False, False
    for index, char in enumerate(text):
        if escaped:
            escaped = False
        elif in_string:
            escaped = char == "\\"
            in_string = char != '"'
        elif char == '"':
            in_string = True
        elif char in "[{":
            depth += 1
            if depth > MAX_JSON_DEPTH:
                line, column = TextPositions(text).of_index(index)
                return BaselineError(
                    path, line, column, f"JSON nested deeper than {MAX_JSON_DEPTH} levels"
                )
        elif char in "]}":
            depth -= 1
    return BaselineError(path, 1, 1, "JSON nested too deeply")


def _numbers(path: Path, value: Any, key: str) -> dict[str, float]:
    if not isinstance(value, dict):
        raise BaselineError(path, 1, 1, f"'{key}' must be an object of numbers")
    numbers: dict[str, float] = {}
    for name, item in value.items():
        is_number = isinstance(item, int | float) and not isinstance(item, bool)
        if not is_number or not math.isfinite(item):
            raise BaselineError(
                path, 1, 1, f"{key}.{clip(name)} must be a finite number, got {clip(repr(item))}"
            )
        numbers[str(name)] = float(item)
    return numbers


def compare(baseline: Baseline, metrics: Mapping[str, MetricValue]) -> list[ExpectationResult]:
    """One ``baseline.<metric>`` result per baseline metric this run measured."""
    from baobab.missions.run.expectations import ExpectationResult
    from baobab.missions.run.metrics import numeric

    results: list[ExpectationResult] = []
    for name, reference in baseline.metrics.items():
        measured = numeric(metrics.get(name))
        if measured is None:
            continue
        allowed = baseline.allowed(name)
        results.append(
            ExpectationResult(
                f"baseline.{name}",
                {"max": allowed, "baseline": reference},
                measured,
                measured <= allowed,
                f"{measured:.4g} vs baseline {reference:.4g} (allowed up to {allowed:.4g})",
            )
        )
    return results


def write_baseline(
    path: Path,
    mission: str,
    seed: int,
    params: Mapping[str, Any],
    metrics: Mapping[str, MetricValue],
) -> Baseline:
    """Store this run's baseline metrics in ``path`` (atomically) and return the baseline."""
    from baobab.missions.run.metrics import numeric
    from baobab.missions.run.trace import jsonable

    values = {
        name: round(number, 6)
        for name in DEFAULT_SLACK
        if (number := numeric(metrics.get(name))) is not None
    }
    document = {
        "baobab_baseline": FORMAT_VERSION,
        "mission": mission,
        "seed": seed,
        "params": jsonable(dict(params), None),
        "tolerance": DEFAULT_TOLERANCE,
        "slack": {name: DEFAULT_SLACK[name] for name in values},
        "metrics": values,
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    try:
        temporary.write_text(json.dumps(document, indent=2) + "\n", encoding="utf-8")
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
    return Baseline(path, mission, values, DEFAULT_TOLERANCE, dict(DEFAULT_SLACK), seed)
