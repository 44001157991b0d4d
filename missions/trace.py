"""The run's trace: sim-time stamped JSON records, and the digest that fingerprints a run.

Every record is one JSON object per line (``trace.jsonl``) whose first key is ``t``, the sim
time (s), and second ``type`` (``pose``, ``status``, ``feedback``, ``outcome``, ``event``,
``end``...). Records hold only what the simulation determines: sim times, states, node
labels and their ``line:col`` in the mission file; never wall-clock time or file paths. Floats
are rounded to :data:`DECIMALS` places (micrometres, microradians), which keeps the file
readable. The digest is the SHA-256 of the lines as written, so the same mission, parameters
and seed give the same digest in one process and across processes.
"""

from __future__ import annotations

import dataclasses
import enum
import hashlib
import json
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

DECIMALS = 6
"""Decimal places kept for floats in the trace."""


def jsonable(value: Any, decimals: int | None = DECIMALS) -> Any:
    """``value`` as plain JSON data: numpy scalars and arrays, tuples, enums, dataclasses and
    pydantic models converted; floats rounded to ``decimals`` places (None keeps them);
    non-finite floats become the strings ``"inf"``, ``"-inf"`` and ``"nan"``."""
    kind = type(value)
    # Plain floats and dicts first: they are most of every record.
    if kind is float or isinstance(value, np.floating):
        return _json_float(float(value), decimals)
    if kind is dict or isinstance(value, Mapping):
        return {str(key): jsonable(item, decimals) for key, item in value.items()}
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    if isinstance(value, enum.Enum):
        return jsonable(value.value, decimals)
    if isinstance(value, int | np.integer):
        return int(value)
    if isinstance(value, float):  # a float subclass
        return _json_float(float(value), decimals)
    if isinstance(value, list | tuple | np.ndarray):
        return [jsonable(item, decimals) for item in value]
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return jsonable(dataclasses.asdict(value), decimals)
    dump = getattr(value, "model_dump", None)
    if callable(dump):
        return jsonable(dump(), decimals)
    return str(value)


def _json_float(number: float, decimals: int | None) -> float | str:
    """``number`` rounded to ``decimals`` places, no ``-0.0``; non-finite ones as strings."""
    if not math.isfinite(number):
        return "nan" if math.isnan(number) else ("inf" if number > 0 else "-inf")
    rounded = number if decimals is None else round(number, decimals)
    return 0.0 if rounded == 0 else rounded


class Trace:
    """Collects the trace records in order and hashes them as they come."""

    def __init__(self) -> None:
        self.lines: list[str] = []
        self._hash = hashlib.sha256()

    def add(self, time: float, kind: str, **fields: Any) -> None:
        """Append the record ``{"t": time, "type": kind, **fields}``."""
        record = jsonable({"t": time, "type": kind, **fields})
        line = json.dumps(record, separators=(",", ":"), ensure_ascii=False)
        self.lines.append(line)
        self._hash.update(line.encode("utf-8"))
        self._hash.update(b"\n")

    @property
    def digest(self) -> str:
        """SHA-256 (hex) of the lines so far, each followed by a newline."""
        return self._hash.hexdigest()

    def text(self) -> str:
        """The whole trace as JSON Lines."""
        return "".join(line + "\n" for line in self.lines)
