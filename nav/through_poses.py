"""ComputePathThroughPoses: one planner leg per goal, joined, with unchanged legs reused.

Nav2's planner server plans a path through several goals leg by leg: from the start to the
first goal, then from each goal to the next. NavigateThroughPoses replans every 3 s, so the
same goal-to-goal legs are planned again and again; with the farm's 41 goals that is most of
the navigation's work. A leg between two goals is reused while the costmap is unchanged
wherever a path of the same cost could run:

every step of the A* costs at least ``408 * w_min`` per cell of length (``w_min``: the weight
of free space), so any path no dearer than the leg's optimal cost ``C`` is at most
``L = C / (408 * w_min)`` cells long, and every cell it visits lies within ``L / 2`` of the
midpoint between start and goal. The reuse check compares that disc's bounding box (plus the
goal tolerance, the start's escape zone and a cell) with the cells stored when the leg was
planned. If they match, no cheaper path can exist and the search would return a leg of the same
cost (the stored one, unless another of exactly equal cost wins the tie).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from baobab.nav.costmap import Costmap2D
from baobab.nav.errors import ComputePathThroughPosesError, NavigationError
from baobab.nav.grid_search import CARDINAL_STEP
from baobab.nav.path import Path
from baobab.nav.planner import GlobalPlanner
from baobab.sim.world import Pose2D

_MAX_LEGS = 4096
"""Stored legs before the store is emptied (a bound on memory, never reached in practice)."""


@dataclass(frozen=True)
class _Leg:
    path: Path
    rows: slice
    cols: slice
    cells: np.ndarray


class ThroughPosesPlanner:
    """Plans through a list of goals with a :class:`GlobalPlanner`, reusing unchanged legs.

    Args:
        planner: the point-to-point planner.
    """

    def __init__(self, planner: GlobalPlanner) -> None:
        self.planner = planner
        self._legs: dict[tuple[float, ...], _Leg] = {}
        self.legs_planned = 0
        self.legs_reused = 0

    def plan(self, start: Pose2D, goals: Sequence[Pose2D], costmap: Costmap2D) -> Path:
        """A path from ``start`` through ``goals`` in order.

        Raises:
            NavigationError: ComputePathThroughPoses codes (3xx), the leg's index in the message.
        """
        codes = ComputePathThroughPosesError
        if not goals:
            raise NavigationError(codes.NO_VIAPOINTS_GIVEN, "no goals to plan through")
        pieces: list[np.ndarray] = []
        previous = start
        for index, goal in enumerate(goals):
            try:
                leg = self._leg(previous, goal, costmap, reuse=index > 0)
            except NavigationError as error:
                name = error.code_name
                code = codes[name] if name in codes.__members__ else codes.UNKNOWN
                raise NavigationError(code, f"goal {index}: {error.message}") from error
            pieces.append(leg.poses if not pieces else leg.poses[1:])
            previous = goal
        return Path(np.vstack(pieces))

    def _leg(self, start: Pose2D, goal: Pose2D, costmap: Costmap2D, *, reuse: bool) -> Path:
        key = (start.x, start.y, start.yaw, goal.x, goal.y, goal.yaw)
        stored = self._legs.get(key) if reuse else None
        if stored is not None and np.array_equal(
            costmap.data[stored.rows, stored.cols], stored.cells
        ):
            self.legs_reused += 1
            return stored.path
        raw = self.planner.search(start, goal, costmap)
        path = self.planner.path_of(raw, goal, costmap)
        self.legs_planned += 1
        if reuse and not raw.goal_substituted:
            if len(self._legs) >= _MAX_LEGS:
                self._legs.clear()
            rows, cols = self._region(start, goal, raw.cost, costmap)
            self._legs[key] = _Leg(path, rows, cols, costmap.data[rows, cols].copy())
        return path

    def _region(
        self, start: Pose2D, goal: Pose2D, cost: int, costmap: Costmap2D
    ) -> tuple[slice, slice]:
        """Rows and columns of the cells any path no dearer than ``cost`` could touch."""
        weights = self.planner.weights
        cheapest = int(weights[weights > 0].min())
        res = costmap.resolution
        longest = cost / (CARDINAL_STEP * cheapest)  # cells
        margin = (self.planner.params.tolerance + costmap.inscribed_radius) / res + 3
        reach = longest / 2 + margin
        mid_x = ((start.x + goal.x) / 2 - costmap.origin_x) / res
        mid_y = ((start.y + goal.y) / 2 - costmap.origin_y) / res
        cols = slice(
            max(math.floor(mid_x - reach), 0), min(math.ceil(mid_x + reach) + 1, costmap.size_x)
        )
        rows = slice(
            max(math.floor(mid_y - reach), 0), min(math.ceil(mid_y + reach) + 1, costmap.size_y)
        )
        return rows, cols
