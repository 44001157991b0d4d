"""A plain-text table of a run's expectations: what was expected, what was measured, held or not.

Used by the pytest plugin's failure report; plain ASCII so it reads the same in a terminal,
a CI log and a JUnit XML file.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import Any

from baobab.missions.run.expectations import ExpectationResult

MAX_CELL = 40
"""Longest cell (characters); longer values are cut with an ellipsis."""
HEADERS = ("expectation", "expected", "measured", "held", "detail")


def format_value(value: Any) -> str:
    """A compact form of an expected or measured value (numbers to 4 significant digits)."""
    if value is None:
        return "-"
    if isinstance(value, bool | str):
        return str(value)
    if isinstance(value, float):
        return f"{value:.4g}" if math.isfinite(value) else str(value)
    if isinstance(value, dict | list | tuple):
        return json.dumps(_rounded(value), separators=(", ", ": "))
    return str(value)


def _rounded(value: Any) -> Any:
    if isinstance(value, float):
        return float(f"{value:.4g}") if math.isfinite(value) else str(value)
    if isinstance(value, dict):
        return {str(key): _rounded(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [_rounded(item) for item in value]
    return value


def _cut(text: str) -> str:
    return text if len(text) <= MAX_CELL else text[: MAX_CELL - 3] + "..."


def expectation_table(results: Sequence[ExpectationResult]) -> str:
    """The table, one row per expectation, failed rows marked ``NO``; no trailing newline."""
    rows = [
        (
            result.name,
            format_value(result.expected),
            format_value(result.measured),
            "yes" if result.passed else "NO",
            result.detail,
        )
        for result in results
    ]
    cells = [HEADERS, *[tuple(_cut(cell) for cell in row[:4]) + (row[4],) for row in rows]]
    widths = [max(len(row[column]) for row in cells) for column in range(4)]
    lines = []
    for index, row in enumerate(cells):
        padded = [cell.ljust(width) for cell, width in zip(row[:4], widths, strict=True)]
        lines.append("  ".join([*padded, row[4]]).rstrip())
        if index == 0:
            lines.append("  ".join("-" * width for width in [*widths, len(HEADERS[4])]))
    return "\n".join(lines)
