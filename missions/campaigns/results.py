"""A campaign's results: the per-run table (SQLite), the summary, the Wilson interval.

``results.sqlite`` holds one table, ``runs``, one row per finished run, inserted and committed
as each run finishes (write-ahead log), so an interrupted campaign keeps every finished row
and the file can be read while the campaign runs. Columns: see :data:`COLUMNS`; ``params``
(the varied values), ``overrides`` (the run's ``--set``), ``metrics`` and ``expectations``
hold JSON. ``wall_time`` and ``finished_at`` are the only wall-clock columns: the rest of a
row is the same whichever executor ran it.
"""

from __future__ import annotations

import contextlib
import json
import math
import sqlite3
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

RESULTS_FILE = "results.sqlite"
SUMMARY_FILE = "summary.json"
Z_95 = 1.959963984540054
"""The standard normal quantile for a two-sided 95 % interval."""

COLUMNS: tuple[tuple[str, str], ...] = (
    ("run", "INTEGER PRIMARY KEY"),
    ("cell", "INTEGER NOT NULL"),
    ("repeat", "INTEGER NOT NULL"),
    ("seed", "INTEGER NOT NULL"),
    ("params", "TEXT NOT NULL"),
    ("overrides", "TEXT NOT NULL"),
    ("result", "TEXT NOT NULL"),
    ("error_code", "INTEGER"),
    ("error_name", "TEXT"),
    ("error_msg", "TEXT"),
    ("intended", "INTEGER NOT NULL"),
    ("exit_code", "INTEGER"),
    ("sim_time", "REAL"),
    ("path_length", "REAL"),
    ("metrics", "TEXT NOT NULL"),
    ("expectations_passed", "INTEGER NOT NULL"),
    ("expectations_failed", "INTEGER NOT NULL"),
    ("expectations", "TEXT NOT NULL"),
    ("trace_digest", "TEXT"),
    ("replay", "TEXT NOT NULL"),
    ("wall_time", "REAL NOT NULL"),
    ("finished_at", "TEXT NOT NULL"),
)
"""The ``runs`` table: (name, SQLite type)."""
JSON_COLUMNS = frozenset({"params", "overrides", "metrics", "expectations"})
BOOL_COLUMNS = frozenset({"intended"})
WALL_CLOCK_COLUMNS = frozenset({"wall_time", "finished_at"})
"""Columns that differ between two executions of the same campaign."""


class ResultsTable:
    """The ``runs`` table of ``path``, created if needed.

    Args:
        path: the SQLite file.
    """

    def __init__(self, path: Path) -> None:
        self.path = path
        self._db = sqlite3.connect(path)
        self._db.execute("PRAGMA journal_mode=WAL")
        columns = ", ".join(f'"{name}" {kind}' for name, kind in COLUMNS)
        self._db.execute(f"CREATE TABLE IF NOT EXISTS runs ({columns})")
        self._db.commit()

    def add(self, row: Mapping[str, Any]) -> None:
        """Insert and commit one row (JSON columns are encoded here)."""
        values = [
            json.dumps(row[name], ensure_ascii=False) if name in JSON_COLUMNS else row[name]
            for name, _ in COLUMNS
        ]
        names = ", ".join(f'"{name}"' for name, _ in COLUMNS)
        marks = ", ".join("?" for _ in COLUMNS)
        self._db.execute(f"INSERT INTO runs ({names}) VALUES ({marks})", values)
        self._db.commit()

    def close(self) -> None:
        """Fold the write-ahead log into the file and close: one self-contained file.

        While another connection reads the file, the log stays beside it (still valid).
        """
        with contextlib.suppress(sqlite3.OperationalError):
            self._db.execute("PRAGMA journal_mode=DELETE")
        self._db.close()


def read_rows(path: Path) -> list[dict[str, Any]]:
    """Every row of a results file, by run number, JSON columns decoded."""
    with contextlib.closing(sqlite3.connect(f"file:{path}?mode=ro", uri=True)) as db:
        db.row_factory = sqlite3.Row
        rows = db.execute("SELECT * FROM runs ORDER BY run").fetchall()
    decoded: list[dict[str, Any]] = []
    for row in rows:
        item = dict(row)
        for name in JSON_COLUMNS:
            item[name] = json.loads(item[name])
        for name in BOOL_COLUMNS:
            item[name] = bool(item[name])
        decoded.append(item)
    return decoded


def wilson_interval(successes: int, trials: int, z: float = Z_95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion (Wilson 1927; Newcombe 1998, method 3).

    ``(p + z²/2n ± z sqrt(p(1-p)/n + z²/4n²)) / (1 + z²/n)`` with ``p = successes/trials``.
    With no trials, the interval is [0, 1].

    Raises:
        ValueError: ``successes`` outside ``0..trials``.
    """
    if not 0 <= successes <= trials:
        raise ValueError(f"successes must be in 0..{trials}, got {successes}")
    if trials == 0:
        return 0.0, 1.0
    n = float(trials)
    p = successes / n
    z2 = z * z
    centre = (p + z2 / (2 * n)) / (1 + z2 / n)
    half = z / (1 + z2 / n) * math.sqrt(p * (1 - p) / n + z2 / (4 * n * n))
    return max(0.0, centre - half), min(1.0, centre + half)


def _percentiles(values: Sequence[float | None]) -> dict[str, float | None]:
    numbers = [v for v in values if v is not None]
    if not numbers:
        return {"p50": None, "p95": None}
    p50, p95 = np.percentile(numbers, [50, 95]).tolist()
    return {"p50": round(p50, 6), "p95": round(p95, 6)}


def failure_label(row: Mapping[str, Any]) -> str:
    """How a failed run is grouped: its error code and name, or what went differently."""
    if row["error_code"]:
        return f"{row['error_code']} {row['error_name']}"
    if row["result"] in ("INVALID", "ERROR"):
        return f"{row['result']} {row['error_name']}"
    failed = [e["name"] for e in row["expectations"] if not e["passed"]]
    return f"{row['result']}, expectations failed: {', '.join(failed)}" if failed else row["result"]


@dataclass
class CampaignSummary:
    """The numbers a campaign ends with (``summary.json``, ``--json``).

    Attributes:
        mission: the mission's name.
        planned: runs the campaign was to run.
        rows: the finished runs' rows.
        interrupted: SIGINT stopped the campaign early.
        extra: more top-level fields (seed, executor, files...).
    """

    mission: str
    planned: int
    rows: list[dict[str, Any]]
    interrupted: bool = False
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def runs(self) -> int:
        """Finished runs."""
        return len(self.rows)

    @property
    def successes(self) -> int:
        """Runs that went as intended."""
        return sum(1 for row in self.rows if row["intended"])

    @property
    def all_intended(self) -> bool:
        """Every planned run finished and went as intended."""
        return self.runs == self.planned and self.successes == self.runs

    def failures(self) -> list[dict[str, Any]]:
        """Each failed run: number, seed, values, result, error and replay command."""
        keys = ("run", "seed", "params", "result", "error_code", "error_name", "error_msg")
        return [
            {
                **{key: row[key] for key in keys},
                "group": failure_label(row),
                "replay": row["replay"],
            }
            for row in self.rows
            if not row["intended"]
        ]

    def failure_groups(self) -> list[dict[str, Any]]:
        """Failures grouped by :func:`failure_label`, most frequent first."""
        groups: dict[str, list[int]] = {}
        for failure in self.failures():
            groups.setdefault(failure["group"], []).append(failure["run"])
        ordered = sorted(groups.items(), key=lambda item: (-len(item[1]), item[0]))
        return [{"group": label, "count": len(runs), "runs": runs} for label, runs in ordered]

    def as_json(self) -> dict[str, Any]:
        """The summary object."""
        rate = self.successes / self.runs if self.runs else None
        low, high = wilson_interval(self.successes, self.runs)
        return {
            "mission": self.mission,
            "planned": self.planned,
            "runs": self.runs,
            "successes": self.successes,
            "success_rate": None if rate is None else round(rate, 6),
            "success_ci95": [round(low, 6), round(high, 6)],
            "interrupted": self.interrupted,
            "sim_time": _percentiles([row["sim_time"] for row in self.rows]),
            "path_length": _percentiles([row["path_length"] for row in self.rows]),
            "failure_groups": self.failure_groups(),
            "failures": self.failures(),
            **self.extra,
        }


def write_summary(folder: Path, summary: Mapping[str, Any]) -> Path:
    """Write ``summary.json`` into the campaign folder."""
    path = folder / SUMMARY_FILE
    path.write_text(json.dumps(summary, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    return path
