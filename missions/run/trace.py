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
from collections.abc import Callable, Mapping
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


def _flat_line(record: dict[str, Any]) -> str | None:
    """The JSON line of ``record`` when its values are all plain floats, ints, strings, bools
    or None, or dicts of those under string keys (most records: poses, statuses, feedback),
    written directly; else None. The text is what
    ``json.dumps(jsonable(record), separators=(",", ":"), ensure_ascii=False)`` writes."""
    parts = []
    for key, value in record.items():
        kind = type(value)
        if kind is float:
            text = _float_text(value)
        elif kind is str:
            text = _encode_string(value)
        elif kind is int:
            text = int.__repr__(value)
        elif kind is bool:
            text = "true" if value else "false"
        elif value is None:
            text = "null"
        elif kind is dict and all(type(inner) is str for inner in value):
            nested = _flat_line(value)
            if nested is None:
                return None
            text = nested
        else:
            return None
        parts.append(f"{_encode_string(key)}:{text}")
    return "{" + ",".join(parts) + "}"


def _float_text(number: float) -> str:
    """``number`` as :func:`_json_float` and JSON write it: ``repr(round(number, DECIMALS))``,
    no ``-0.0``, non-finite ones as strings.

    Where ``repr`` writes no exponent and the rounded value has at most 15 significant digits
    (``FIXED_RANGE``), that text is the ``%.6f`` text without its trailing zeros, which is
    cheaper: ``round`` converts exactly that decimal (``dtoa`` mode 3) back to a float, and a
    decimal of 15 digits or fewer is the shortest text of the float it converts to, the one
    ``repr`` writes (``tests/test_trace_lines.py`` compares the two).
    """
    if FIXED_RANGE[0] <= abs(number) < FIXED_RANGE[1]:
        text = (_FIXED % number).rstrip("0")
        return text + "0" if text[-1] == "." else text
    if not _isfinite(number):
        return f'"{_json_float(number, DECIMALS)}"'
    rounded = round(number, DECIMALS)
    return float.__repr__(rounded) if rounded else "0.0"


FIXED_RANGE = (1e-4, 10.0 ** (15 - DECIMALS))
"""Magnitudes whose rounded text :func:`_float_text` takes from ``%.6f``: from repr's
smallest without an exponent to the largest with 15 significant digits at :data:`DECIMALS`."""
_FIXED = f"%.{DECIMALS}f"

_encode_string: Callable[[str], str] = json.encoder.encode_basestring
"""JSON's own string encoder for ``ensure_ascii=False`` (quotes and escapes)."""
_isfinite = math.isfinite


class Trace:
    """Collects the trace records in order; hashes them, in bulk, when the digest is asked."""

    def __init__(self) -> None:
        self.lines: list[str] = []
        self._hash = hashlib.sha256()
        self._hashed = 0
        """How many of ``lines`` are in ``_hash``."""

    def add(self, time: float, kind: str, /, **fields: Any) -> None:
        """Append the record ``{"t": time, "type": kind, **fields}``."""
        record = {"t": time, "type": kind, **fields}
        line = _flat_line(record)
        if line is None:
            line = json.dumps(jsonable(record), separators=(",", ":"), ensure_ascii=False)
        self.lines.append(line)

    @property
    def digest(self) -> str:
        """SHA-256 (hex) of the lines so far, each followed by a newline."""
        fresh = self.lines[self._hashed :]
        if fresh:
            self._hash.update("".join(line + "\n" for line in fresh).encode("utf-8"))
            self._hashed += len(fresh)
        return self._hash.hexdigest()

    def text(self) -> str:
        """The whole trace as JSON Lines."""
        return "".join(line + "\n" for line in self.lines)
