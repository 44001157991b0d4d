"""The seeded plan of a campaign's runs (``baobab campaign``).

Grid axes (:class:`~baobab.missions.campaigns.vary.GridAxis`) combine as a cartesian product,
the last axis varying fastest; every cell is run ``--runs`` times (default 1), so a campaign
has ``cells x runs`` runs; without grid axes it has ``--runs`` runs. Run ``i`` is cell
``i // runs``, repeat ``i % runs``. Random draws are independent for every run, repeats
included.

Seeds: run ``i`` of a campaign with seed ``S`` uses ``SeedSequence(S, spawn_key=(i,))`` (the
i-th child of ``SeedSequence(S).spawn(...)``), split in two: the first child gives the run's
seed (32 bits, for ``baobab run --seed``), the second the generator that draws the run's
values, in ``--vary`` order. Everything is drawn in the parent before dispatch, so the plan
depends only on the command line, never on the executor, and run i keeps its seed and values
whatever ``--runs``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from baobab.missions.campaigns.vary import (
    CampaignError,
    GridAxis,
    Target,
    Variation,
    format_value,
    parse_grid,
    parse_vary,
    variable_keys,
)
from baobab.missions.language.loader import Mission
from baobab.sim.yaml_source import KeyPath

MAX_RUNS = 100_000
"""More runs than this in one campaign is refused (a mistyped grid, most likely)."""


@dataclass(frozen=True)
class RunTask:
    """Everything one run needs, picklable for any executor.

    Attributes:
        index: the run's number in the campaign (0-based).
        cell: its grid cell (0 without grid axes).
        repeat: its repeat within the cell.
        seed: the run's seed (``baobab run --seed``).
        values: each varied key's value in this run (JSON data).
        overrides: the run's ``--set`` values (the campaign's own, then the varied parameters).
        start_offset: (dx m, dy m, dyaw rad) added to the start pose, or None.
        data_changes: (key path, value) written into the mission data.
        mission_path: the mission file (resolves a world file next to it).
        mission_text: the mission file's content.
        variant_label: how messages name the run's own mission variant, if it has one.
    """

    index: int
    cell: int
    repeat: int
    seed: int
    values: dict[str, Any]
    overrides: dict[str, str]
    start_offset: tuple[float, float, float] | None
    data_changes: tuple[tuple[KeyPath, float | str], ...]
    mission_path: str
    mission_text: str
    variant_label: str

    @property
    def has_variant(self) -> bool:
        """True when the run's mission differs from the file by more than ``--set`` values."""
        return self.start_offset is not None or bool(self.data_changes)


def variant_label(index: int) -> str:
    """Where a run's mission variant is written, relative to the campaign folder."""
    return f"replay/run-{index:04d}.yaml"


@dataclass(frozen=True)
class CampaignSpec:
    """A campaign: the mission, what varies, how many runs, the seed.

    Attributes:
        mission: the mission with the campaign's own ``--set`` values.
        mission_path: its file.
        mission_text: the file's content.
        sets: the campaign's ``--set`` values, given to every run.
        axes: grid axes, in command-line order.
        variations: random variations, in command-line order.
        repeats: runs per grid cell (all runs without grid axes).
        seed: the campaign seed.
    """

    mission: Mission
    mission_path: Path
    mission_text: str
    sets: dict[str, str]
    axes: tuple[GridAxis, ...]
    variations: tuple[Variation, ...]
    repeats: int
    seed: int
    keys: tuple[str, ...] = field(init=False)

    def __post_init__(self) -> None:
        keys = tuple(a.target.key for a in self.axes) + tuple(v.target.key for v in self.variations)
        object.__setattr__(self, "keys", keys)

    @property
    def cells(self) -> int:
        """Grid cells (1 without grid axes)."""
        return math.prod(len(axis.values) for axis in self.axes)

    @property
    def total_runs(self) -> int:
        """Runs in the campaign."""
        return self.cells * self.repeats

    def tasks(self) -> Iterator[RunTask]:
        """The runs, in order."""
        return (self.task(index) for index in range(self.total_runs))

    def task(self, index: int) -> RunTask:
        """Run ``index``: its cell, seed and drawn values."""
        cell, repeat = divmod(index, self.repeats)
        seed_sequence, draw_sequence = np.random.SeedSequence(self.seed, spawn_key=(index,)).spawn(
            2
        )
        seed = int(seed_sequence.generate_state(1, np.uint32)[0])
        rng = np.random.default_rng(draw_sequence)
        chosen: list[tuple[Target, str | float]] = []
        grid_values = _cell_values(self.axes, cell)
        chosen += zip((a.target for a in self.axes), grid_values, strict=True)
        chosen += [(v.target, v.distribution.draw(rng)) for v in self.variations]
        values: dict[str, Any] = {}
        overrides = dict(self.sets)
        offset = [0.0, 0.0, 0.0]
        has_offset = False
        changes: list[tuple[KeyPath, float | str]] = []
        for target, value in chosen:
            if target.kind == "param":
                overrides[str(target.path[0])] = format_value(value)
                try:
                    values[target.key] = target.typed(value)
                except ValueError:
                    values[target.key] = value  # out of bounds: the run reports it (INVALID)
                continue
            if target.kind == "robot":
                values[target.key] = str(value)
                changes.append((target.path, str(value)))
                continue
            number = float(value)
            values[target.key] = number
            if target.kind == "start":
                offset[("x", "y", "yaw").index(str(target.path[0]))] = number
                has_offset = True
            else:
                changes.append((target.path, number))
        return RunTask(
            index=index,
            cell=cell,
            repeat=repeat,
            seed=seed,
            values=values,
            overrides=overrides,
            start_offset=(offset[0], offset[1], offset[2]) if has_offset else None,
            data_changes=tuple(changes),
            mission_path=str(self.mission_path),
            mission_text=self.mission_text,
            variant_label=variant_label(index),
        )


def _cell_values(axes: Sequence[GridAxis], cell: int) -> tuple[str, ...]:
    """The values of grid cell ``cell``: a mixed-radix number, the last axis fastest."""
    values: list[str] = []
    for axis in reversed(axes):
        cell, digit = divmod(cell, len(axis.values))
        values.append(axis.values[digit])
    return tuple(reversed(values))


def build_spec(
    mission: Mission,
    mission_path: Path,
    mission_text: str,
    sets: Mapping[str, str],
    vary: Sequence[str],
    grid: Sequence[str],
    runs: int | None,
    seed: int,
) -> CampaignSpec:
    """Check the command line's variations against the mission and plan the campaign.

    Args:
        mission: the mission loaded with ``sets``.
        mission_path: its file.
        mission_text: the file's content.
        sets: the campaign's ``--set`` values.
        vary: each ``--vary`` text.
        grid: each ``--grid`` text.
        runs: ``--runs`` (required without grid axes; repeats per cell with them).
        seed: the campaign seed (>= 0).

    Raises:
        CampaignError: the first problem, as one line.
    """
    if runs is not None and runs < 1:
        raise CampaignError(f"--runs must be >= 1, got {runs}")
    if runs is not None and runs > MAX_RUNS:
        raise CampaignError(f"--runs {runs}: at most {MAX_RUNS} runs in one campaign (MAX_RUNS)")
    targets = variable_keys(mission)
    # Each grid axis is checked against the runs the earlier axes leave before its values are
    # made: grid(0,1,100000000) must not make a hundred million values to refuse them.
    points = 1 if runs is None else runs
    parsed: list[Variation | GridAxis] = []
    for option, text in [*(("vary", text) for text in vary), *(("grid", text) for text in grid)]:
        budget = MAX_RUNS // points
        item = (
            parse_vary(text, targets, budget)
            if option == "vary"
            else parse_grid(text, targets, budget)
        )
        if isinstance(item, GridAxis):
            points *= len(item.values)
        parsed.append(item)
    seen: set[str] = set()
    for item in parsed:
        key = item.target.key
        if key in seen:
            raise CampaignError(f"'{key}' is varied twice")
        if key in sets:
            raise CampaignError(f"'{key}' is both set (--set) and varied")
        seen.add(key)
    axes = tuple(item for item in parsed if isinstance(item, GridAxis))
    variations = tuple(item for item in parsed if isinstance(item, Variation))
    if seed < 0:
        raise CampaignError(f"--seed must be >= 0, got {seed}")
    if runs is None and not axes:
        raise CampaignError("give --runs N (or grid axes, each cell then runs once)")
    spec = CampaignSpec(
        mission,
        mission_path,
        mission_text,
        dict(sets),
        axes,
        variations,
        1 if runs is None else runs,
        seed,
    )
    if spec.total_runs > MAX_RUNS:
        raise CampaignError(
            f"{spec.cells} grid cells x {spec.repeats} runs = {spec.total_runs} runs; "
            f"at most {MAX_RUNS} in one campaign (MAX_RUNS)"
        )
    return spec
