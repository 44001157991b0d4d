"""Live progress of a run and its closing summary: rich on a terminal, plain lines otherwise.

:class:`LiveProgress` redraws one status block (current leaf, distance remaining, ETA, task
i/n, sim time and speed-up) at most ten times per wall-clock second. :class:`LineProgress`
writes a line when the running leaf changes and every ``every`` seconds of sim time, for logs
and pipes. Both write to the stream they are given (stderr when ``--json`` owns stdout). Each
splits ``update`` into ``due`` (which snapshots are shown) and ``draw``, so a run in another
process sends only the snapshots that are shown (:mod:`baobab.missions.run.child_process`). Between
snapshots, ``phase`` says what the run is doing (loading the simulator, compiling kernels,
writing the run folder): on a terminal only, so logs and ``--json`` get nothing extra.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import IO, Any, Protocol


@dataclass(frozen=True)
class ProgressSnapshot:
    """What a progress display shows, once per tick.

    Attributes:
        sim_time: s.
        wall_time: s since the loop started.
        timeout: the mission timeout (s of sim time).
        leaf: label of the running leaf (the first in tree order), or "".
        distance_remaining: from the running task's feedback (m), if it reports one.
        eta: estimated time remaining (s of sim time), if known.
        step: (index of the running task leaf, number of task leaves), 1-based, if any runs.
        waypoint: the task's current waypoint (1-based), if it reports one.
    """

    sim_time: float
    wall_time: float
    timeout: float
    leaf: str
    distance_remaining: float | None
    eta: float | None
    step: tuple[int, int] | None
    waypoint: int | None


class ProgressSink(Protocol):
    """Receives a snapshot after every tick (and throttles its own output)."""

    def update(self, snapshot: ProgressSnapshot) -> None:
        """Show progress."""
        ...


REDRAW_PERIOD = 0.1
"""Least wall time between two redraws of the live display (s)."""


def describe(snapshot: ProgressSnapshot) -> str:
    """One line: ``t=12.3 s x48 | go_to_goal goal_open | task 1/1 | 2.31 m left | ETA 11 s``."""
    speedup = snapshot.sim_time / snapshot.wall_time if snapshot.wall_time > 0 else 0.0
    parts = [f"t={snapshot.sim_time:7.1f} s x{speedup:<5.0f}", snapshot.leaf or "-"]
    if snapshot.step is not None:
        parts.append(f"task {snapshot.step[0]}/{snapshot.step[1]}")
    if snapshot.waypoint is not None:
        parts.append(f"waypoint {snapshot.waypoint}")
    if snapshot.distance_remaining is not None:
        parts.append(f"{snapshot.distance_remaining:.2f} m left")
    if snapshot.eta is not None:
        parts.append(f"ETA {snapshot.eta:.0f} s")
    return " | ".join(parts)


class ProgressSchedule(Protocol):
    """Decides which snapshots a display shows (kept apart from the display: plain data)."""

    def due(self, snapshot: ProgressSnapshot) -> bool:
        """Whether ``snapshot`` is shown."""
        ...


class LineSchedule:
    """When a progress line is due: on a new leaf, or every ``every`` s of sim time.

    Plain data, so that the run's process can decide what to send (``baobab run``).
    """

    def __init__(self, every: float = 10.0) -> None:
        self.every = every
        self._leaf: str | None = None
        self._next = 0.0

    def due(self, snapshot: ProgressSnapshot) -> bool:
        """Whether ``snapshot`` gets a line (a new leaf, or ``every`` s of sim time passed)."""
        if snapshot.leaf == self._leaf and snapshot.sim_time < self._next:
            return False
        self._leaf = snapshot.leaf
        self._next = snapshot.sim_time + self.every
        return True


class RedrawSchedule:
    """When a live redraw is due: :data:`REDRAW_PERIOD` of wall time since the last one."""

    def __init__(self) -> None:
        self._last = 0.0

    def due(self, _snapshot: ProgressSnapshot) -> bool:
        """Whether a redraw is due now."""
        now = time.monotonic()
        if now - self._last < REDRAW_PERIOD:
            return False
        self._last = now
        return True


class LineProgress:
    """Plain progress lines on ``stream``.

    Args:
        stream: where lines go.
        every: sim time between two lines while the leaf stays the same (s).
    """

    def __init__(self, stream: IO[str], every: float = 10.0) -> None:
        self.stream = stream
        self.schedule = LineSchedule(every)
        self._closed = False  # the reader went away (`baobab run ... | head`)

    def update(self, snapshot: ProgressSnapshot) -> None:
        """Write a line on a new leaf or when ``every`` s of sim time have passed."""
        if self.schedule.due(snapshot):
            self.draw(snapshot)

    def draw(self, snapshot: ProgressSnapshot) -> None:
        """Write the line of ``snapshot``; nothing once the stream's reader has gone."""
        if self._closed:
            return
        try:
            self.stream.write(describe(snapshot) + "\n")
            self.stream.flush()
        except BrokenPipeError:
            self._closed = True  # the run goes on and writes its folder

    def phase(self, _text: str) -> None:
        """Nothing: logs and pipes get no start-up or writing lines."""

    def close(self) -> None:
        """Nothing to tidy up."""


class LiveProgress:
    """A rich live display on a terminal ``stream``.

    Args:
        stream: the terminal.
        title: shown above the status line.
    """

    def __init__(self, stream: IO[str], title: str) -> None:
        from rich.console import Console
        from rich.live import Live

        self.console = Console(file=stream)
        self.title = title
        self._live = Live(console=self.console, auto_refresh=False, transient=True)
        self._live.start()
        self.schedule = RedrawSchedule()

    def update(self, snapshot: ProgressSnapshot) -> None:
        """Redraw, at most every :data:`REDRAW_PERIOD` of wall time."""
        if self.schedule.due(snapshot):
            self.draw(snapshot)

    def draw(self, snapshot: ProgressSnapshot) -> None:
        """Redraw the status block with ``snapshot``."""
        from rich.text import Text

        fraction = min(1.0, snapshot.sim_time / snapshot.timeout) if snapshot.timeout else 0.0
        text = Text()
        text.append(self.title, style="bold")
        text.append(f"  (timeout {snapshot.timeout:g} s: {fraction:4.0%} used)\n", style="dim")
        text.append(describe(snapshot))
        self._live.update(text, refresh=True)

    def phase(self, text: str) -> None:
        """Show what happens while no snapshot comes (loading, compiling, writing the folder)."""
        from rich.text import Text

        shown = Text()
        shown.append(self.title, style="bold")
        shown.append(f"\n{text}", style="dim")
        self._live.update(shown, refresh=True)

    def close(self) -> None:
        """Remove the live display."""
        self._live.stop()


def summary_rows(result: Mapping[str, Any]) -> list[tuple[str, str, str]]:
    """(label, value, mark) rows of the closing summary."""
    sim_time, wall_time = float(result["sim_time"]), float(result["wall_time"])
    speedup = sim_time / wall_time if wall_time > 0 else 0.0
    rows = [
        ("result", str(result["result"]), ""),
        ("sim time", f"{sim_time:.2f} s", ""),
        ("wall time", f"{wall_time:.2f} s", ""),
        ("speed-up", f"x{speedup:.1f}", ""),
    ]
    if result.get("error_code"):
        rows.append(("error", f"{result['error_code']} {result['error_name']}", ""))
    if result.get("error_msg"):
        rows.append(("message", str(result["error_msg"]), ""))
    for expectation in result.get("expectations", []):
        mark = "ok" if expectation["passed"] else "FAILED"
        rows.append((f"expect {expectation['name']}", str(expectation.get("detail", "")), mark))
    baseline = result.get("baseline")
    if isinstance(baseline, dict):
        rows.append(("baseline", f"{baseline.get('status')}: {baseline.get('file')}", ""))
    rows.append(("run folder", str(result.get("run_folder", "")), ""))
    return rows


def print_summary(stream: IO[str], result: Mapping[str, Any], *, rich: bool) -> None:
    """Write the summary table: rich when ``rich``, else aligned plain text."""
    rows = summary_rows(result)
    if rich:
        from rich.console import Console
        from rich.table import Table

        table = Table(title=f"baobab run: {result['mission']}", show_header=False)
        table.add_column(style="bold")
        table.add_column()
        table.add_column()
        for label, value, mark in rows:
            style = "green" if mark == "ok" else ("red" if mark else "")
            table.add_row(label, value, f"[{style}]{mark}[/]" if mark else "")
        Console(file=stream).print(table)
        return
    width = max(len(label) for label, _, _ in rows)
    stream.write(f"baobab run: {result['mission']}\n")
    for label, value, mark in rows:
        stream.write(f"  {label:<{width}}  {value}{'  [' + mark + ']' if mark else ''}\n")
    stream.flush()
