"""The campaign's ``outcomes.png``: how the runs turned out over the varied values.

- one varied key: its value (x) against the run's sim time (y);
- two keys: one against the other (a 2D scatter);
- three or more: one panel per key, value against sim time;
- nothing varied: run number against sim time.

Runs that went as intended are green dots, the others red crosses; runs that could not run
(``INVALID``, ``ERROR``) are grey and drawn at sim time 0. Text values (a ``choice`` of
locations, say) are placed in order of first appearance, spread a little sideways so that
repeats do not hide each other. matplotlib (Agg) is imported only when drawing.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes

PLOT_FILE = "outcomes.png"
JITTER = 0.12
"""Sideways spread of repeated text values (in category widths)."""
_STYLES = (
    ("as intended", "#2e8b57", "o"),
    ("not as intended", "#c0392b", "x"),
    ("could not run", "#7f7f7f", "s"),
)


def _outcome(row: Mapping[str, Any]) -> str:
    if row["intended"]:
        return _STYLES[0][0]
    if row["result"] in ("INVALID", "ERROR"):
        return _STYLES[2][0]
    return _STYLES[1][0]


class _Axis:
    """Positions of one key's values on an axis: numbers as they are, text as categories."""

    def __init__(self, key: str, values: Sequence[Any]) -> None:
        self.key = key
        numeric = all(isinstance(v, int | float) and not isinstance(v, bool) for v in values)
        self.categories: list[str] | None = None
        if numeric:
            self.positions = np.asarray(values, dtype=float)
            return
        labels = [str(v) for v in values]
        self.categories = list(dict.fromkeys(labels))
        spread = np.random.default_rng(0).uniform(-JITTER, JITTER, len(labels))
        self.positions = np.array([self.categories.index(s) for s in labels], float) + spread

    def label(self, axes: Axes, which: str) -> None:
        """Name the ``x`` or ``y`` axis of ``axes``; text values get one tick each."""
        getattr(axes, f"set_{which}label")(self.key)
        if self.categories is not None:
            getattr(axes, f"set_{which}ticks")(range(len(self.categories)), self.categories)
            getattr(axes, f"set_{which}lim")(-0.5, len(self.categories) - 0.5)


def save_campaign_plot(
    rows: Sequence[Mapping[str, Any]], keys: Sequence[str], title: str, path: Path
) -> Path | None:
    """Draw the outcomes of ``rows`` over the varied ``keys``; None when there are no rows."""
    if not rows:
        return None
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    outcomes = [_outcome(row) for row in rows]
    sim_times = np.array([row["sim_time"] or 0.0 for row in rows], dtype=float)
    panels = 1 if len(keys) <= 2 else len(keys)
    columns = min(panels, 3)
    lines = math.ceil(panels / columns)
    figure = Figure(figsize=(4.6 * columns + 1.4, 3.8 * lines + 0.8), dpi=110, layout="constrained")
    figure.suptitle(title, fontsize=10)
    if len(keys) == 2:
        axes = figure.add_subplot()
        across = _Axis(keys[0], [row["params"].get(keys[0]) for row in rows])
        up = _Axis(keys[1], [row["params"].get(keys[1]) for row in rows])
        _scatter(axes, across.positions, up.positions, outcomes, legend=True)
        across.label(axes, "x")
        up.label(axes, "y")
    elif not keys:
        axes = figure.add_subplot()
        runs = np.array([row["run"] for row in rows], float)
        _scatter(axes, runs, sim_times, outcomes, legend=True)
        axes.set_xlabel("run")
        axes.set_ylabel("sim time (s)")
    else:
        for index, key in enumerate(keys):
            axes = figure.add_subplot(lines, columns, index + 1)
            across = _Axis(key, [row["params"].get(key) for row in rows])
            _scatter(axes, across.positions, sim_times, outcomes, legend=index == 0)
            across.label(axes, "x")
            axes.set_ylabel("sim time (s)")
    figure.savefig(path)
    return path


def _scatter(
    axes: Axes, xs: np.ndarray, ys: np.ndarray, outcomes: Sequence[str], *, legend: bool
) -> None:
    for name, colour, marker in _STYLES:
        chosen = np.array([outcome == name for outcome in outcomes])
        if not chosen.any():
            continue
        axes.scatter(
            xs[chosen],
            ys[chosen],
            c=colour,
            marker=marker,
            s=28,
            linewidths=1.4 if marker == "x" else 0.6,
            edgecolors="white" if marker != "x" else None,
            label=f"{name} ({int(chosen.sum())})",
            zorder=3,
        )
    axes.grid(True, alpha=0.3, zorder=0)
    if legend:
        axes.legend(fontsize=8, loc="best", framealpha=0.85)
