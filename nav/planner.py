"""The global planner: cost-aware A* on the global costmap, Nav2 Smac 2D style.

Moving into a cell costs ``length * (1 + cost_travel_multiplier * cost / 252)`` (Smac 2D's
traversal cost; ``length`` is 1 or sqrt(2) cells), so paths keep away from obstacles where
room allows. Cells at or above ``INSCRIBED_INFLATED_OBSTACLE`` are closed to a circular robot;
unknown cells are open when ``allow_unknown``. The search itself is the compiled, exact A* of
:mod:`baobab.nav.grid_search`.

Start and goal follow Nav2's planner server: outside the map and in lethal space are errors
with their own codes; a start inside the inscribed band may leave it (the planners clear the
robot's cell); a goal that is blocked or unreachable is replaced by the reachable cell nearest
to it within ``tolerance`` (NavFn's 0.5 m). A robot with a polygon footprint is planned for
by its inscribed radius, as Nav2's 2D planners do, and its goal pose is checked with the
footprint at the goal's yaw, as Smac's Hybrid-A* checks its goal: an outline on a lethal cell
is GOAL_OCCUPIED (the robot could never stand there). The raw cell path is then smoothed
(Nav2's Simple Smoother) and each pose faces along the path, the last one taking the goal's
yaw.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from baobab.nav.costmap import (
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    MAX_NON_OBSTACLE,
    NO_INFORMATION,
    Costmap2D,
)
from baobab.nav.errors import ComputePathToPoseError, NavigationError
from baobab.nav.footprint import in_collision
from baobab.nav.grid_search import BUDGET_SPENT, EXHAUSTED, GridSearch
from baobab.nav.path import Path
from baobab.nav.smoother import SimpleSmoother
from baobab.sim.world import Pose2D


@dataclass(frozen=True)
class PlannerParams:
    """Global planner settings: Nav2 NavFn's tolerance, Smac 2D's cost and budget."""

    tolerance: float = 0.5
    cost_travel_multiplier: float = 2.0
    allow_unknown: bool = True
    max_iterations: int = 1_000_000
    use_final_approach_orientation: bool = False


@dataclass(frozen=True)
class RawPlan:
    """The unsmoothed result of one search.

    Attributes:
        cells: ``(N, 2)`` array of ``(ix, iy)`` from the start cell to the end cell.
        points: ``(N, 2)`` map positions (m): the exact start, cell centres, and the exact goal
            when the goal's own cell was reached.
        cost: the optimal path cost in the search's integer units.
        expansions: cells the search expanded.
        goal_substituted: True when tolerance replaced a blocked or unreachable goal cell.
    """

    cells: np.ndarray
    points: np.ndarray
    cost: int
    expansions: int
    goal_substituted: bool


class GlobalPlanner:
    """Plans from a start pose to a goal pose on a costmap.

    Args:
        params: search settings.
        smoother: path smoother, or None for the raw cell path.
    """

    def __init__(
        self, params: PlannerParams | None = None, smoother: SimpleSmoother | None = None
    ) -> None:
        self.params = params or PlannerParams()
        self.smoother = smoother if smoother is not None else SimpleSmoother()
        self.weights = step_weights(self.params.cost_travel_multiplier, self.params.allow_unknown)
        self._search = GridSearch()

    def create_plan(self, start: Pose2D, goal: Pose2D, costmap: Costmap2D) -> Path:
        """A smoothed path from ``start`` to ``goal``; poses face along the path.

        Raises:
            NavigationError: with a :class:`ComputePathToPoseError` code (START_OUTSIDE_MAP,
                GOAL_OUTSIDE_MAP, START_OCCUPIED, GOAL_OCCUPIED, NO_VALID_PATH, TIMEOUT).
        """
        return self.path_of(self.search(start, goal, costmap), goal, costmap)

    def path_of(self, raw: RawPlan, goal: Pose2D, costmap: Costmap2D) -> Path:
        """The path :meth:`create_plan` makes of a search result: smoothed, poses oriented.

        The search's points are smoothed as they are (the smoother reads no orientation) and
        the poses are oriented once, on the smoothed points.
        """
        points = raw.points
        if self.smoother is not None:
            points = self.smoother.smooth_points(points, costmap).points
        path = Path.from_points(points, goal.yaw)
        if self.params.use_final_approach_orientation and len(path) > 1:
            path = Path.from_points(path.xy, float(path.yaws[-2]))
        return path

    def search(self, start: Pose2D, goal: Pose2D, costmap: Costmap2D) -> RawPlan:
        """The optimal cell path from ``start`` to ``goal`` (or the tolerance substitute)."""
        codes = ComputePathToPoseError
        start_cell = costmap.world_to_map(start.x, start.y)
        if start_cell is None:
            raise NavigationError(codes.START_OUTSIDE_MAP, f"start {_xy(start)} is off the map")
        goal_cell = costmap.world_to_map(goal.x, goal.y)
        if goal_cell is None:
            raise NavigationError(codes.GOAL_OUTSIDE_MAP, f"goal {_xy(goal)} is off the map")
        grid = costmap.data
        start_cost = int(grid[start_cell[1], start_cell[0]])
        unknown_blocked = start_cost == NO_INFORMATION and not self.params.allow_unknown
        if start_cost == LETHAL_OBSTACLE or unknown_blocked:
            raise NavigationError(codes.START_OCCUPIED, f"start {_xy(start)} is in an obstacle")
        if start_cost == INSCRIBED_INFLATED_OBSTACLE:
            grid = _open_escape(grid, costmap, start.x, start.y)
        if costmap.has_polygon and in_collision(costmap, goal.x, goal.y, yaw=goal.yaw):
            raise NavigationError(
                codes.GOAL_OCCUPIED,
                f"goal {_xy(goal)} puts the robot's footprint on an obstacle at yaw "
                f"{goal.yaw:.2f} rad",
            )
        targets = self._goal_candidates(grid, costmap, goal)
        if len(targets) == 0:
            raise NavigationError(
                codes.GOAL_OCCUPIED,
                f"goal {_xy(goal)} is in an obstacle with no free cell within "
                f"{self.params.tolerance} m",
            )
        goal_rc = (goal_cell[1], goal_cell[0])
        start_rc = (start_cell[1], start_cell[0])
        first = (int(targets[0][1]), int(targets[0][0]))
        result = self._search.search(
            grid, self.weights, start_rc, first, self.params.max_iterations
        )
        if result.status == BUDGET_SPENT:
            raise NavigationError(
                codes.TIMEOUT, f"no path within {self.params.max_iterations} expansions"
            )
        end_rc = first
        if result.status == EXHAUSTED:
            reached = self._search.reached()
            hits = reached[targets[:, 1], targets[:, 0]]
            if not hits.any():
                reach = f"no path from {_xy(start)} to within {self.params.tolerance} m of the goal"
                if self.weights[grid[goal_rc]] == 0:
                    raise NavigationError(
                        codes.GOAL_OCCUPIED, f"goal {_xy(goal)} is in an obstacle and {reach}"
                    )
                raise NavigationError(codes.NO_VALID_PATH, f"{reach} {_xy(goal)}")
            nearest = targets[int(np.argmax(hits))]
            end_rc = (int(nearest[1]), int(nearest[0]))
        rows_cols = self._search.path_to(end_rc)
        cells = rows_cols[:, ::-1].copy()
        xs, ys = costmap.map_to_world_array(cells[:, 0], cells[:, 1])
        points = np.column_stack([xs, ys])
        points[0] = (start.x, start.y)
        substituted = end_rc != goal_rc
        if not substituted:
            if len(points) == 1:
                points = np.vstack([points, [(goal.x, goal.y)]])
            else:
                points[-1] = (goal.x, goal.y)
        return RawPlan(cells, points, self._search.cost_to(end_rc), result.expansions, substituted)

    def _goal_candidates(self, grid: np.ndarray, costmap: Costmap2D, goal: Pose2D) -> np.ndarray:
        """Open cells ``(ix, iy)`` within tolerance of the goal, nearest first.

        The goal's own cell comes first whenever it is open, even when its centre is farther
        from the goal point than a neighbour's.
        """
        return _goal_candidates(
            grid, self.weights, costmap.pack(), goal.x, goal.y, self.params.tolerance
        )


@numba.njit(cache=True, nogil=True)
def _goal_candidates(
    cells: np.ndarray,
    weights: np.ndarray,
    grid: np.ndarray,
    goal_x: float,
    goal_y: float,
    tolerance: float,
) -> np.ndarray:  # pragma: no cover - compiled
    """Open cells ``(ix, iy)`` within ``tolerance`` (m) of the goal ``(goal_x, goal_y)`` (m),
    ordered by distance, then ``ix``, then ``iy``; the goal's own cell counts as distance -1.

    ``grid`` is the costmap's :data:`~baobab.nav.costmap.GRID` record; the goal lies on it.
    """
    g = grid[0]
    origin_x, origin_y, resolution = g.origin_x, g.origin_y, g.resolution
    size_y, size_x = cells.shape
    gx = math.floor((goal_x - origin_x) / resolution)
    gy = math.floor((goal_y - origin_y) / resolution)
    reach = math.ceil(tolerance / resolution) + 1
    x0, x1 = max(gx - reach, 0), min(gx + reach + 1, size_x)
    y0, y1 = max(gy - reach, 0), min(gy + reach + 1, size_y)
    count = max(x1 - x0, 0) * max(y1 - y0, 0)
    found_cells = np.empty((count, 2), np.int64)
    distances = np.empty(count)
    found = 0
    # Columns outer, rows inner: a stable sort by distance then orders ties by ix, then iy.
    for ix in range(x0, x1):
        for iy in range(y0, y1):
            if ix == gx and iy == gy:
                distance = -1.0
            else:
                cx = origin_x + (ix + 0.5) * resolution
                cy = origin_y + (iy + 0.5) * resolution
                distance = math.hypot(cx - goal_x, cy - goal_y)
            if distance <= tolerance and weights[cells[iy, ix]] > 0:
                found_cells[found, 0], found_cells[found, 1] = ix, iy
                distances[found] = distance
                found += 1
    order = np.argsort(distances[:found], kind="mergesort")
    return found_cells[:found][order]


def step_weights(cost_travel_multiplier: float, allow_unknown: bool) -> np.ndarray:
    """Integer step weights by cost value: ``252 + multiplier * cost``; 0 closes the cell.

    That is Smac 2D's ``1 + multiplier * cost / 252`` scaled by 252, so free space weighs 252.
    """
    costs = np.arange(256, dtype=float)
    weights = np.rint(MAX_NON_OBSTACLE + cost_travel_multiplier * costs).astype(np.int64)
    weights[INSCRIBED_INFLATED_OBSTACLE:NO_INFORMATION] = 0
    if not allow_unknown:
        weights[NO_INFORMATION] = 0
    return weights


def _open_escape(grid: np.ndarray, costmap: Costmap2D, x: float, y: float) -> np.ndarray:
    """A copy of ``grid`` where the inscribed cells around a start inside the band are open.

    A robot whose centre sits within the inscribed radius of an obstacle may drive out of
    it: inscribed cells within one inscribed radius plus one cell of the start become
    passable at the highest non-lethal cost.
    """
    reach = costmap.inscribed_radius + costmap.resolution
    res = costmap.resolution
    x0 = max(math.floor((x - reach - costmap.origin_x) / res), 0)
    x1 = min(math.floor((x + reach - costmap.origin_x) / res) + 1, costmap.size_x)
    y0 = max(math.floor((y - reach - costmap.origin_y) / res), 0)
    y1 = min(math.floor((y + reach - costmap.origin_y) / res) + 1, costmap.size_y)
    rows, cols = np.mgrid[y0:y1, x0:x1]
    cx, cy = costmap.map_to_world_array(cols, rows)
    near = np.hypot(cx - x, cy - y) <= reach
    opened = grid.copy()
    window = opened[y0:y1, x0:x1]
    window[near & (window == INSCRIBED_INFLATED_OBSTACLE)] = MAX_NON_OBSTACLE
    # The start's own cell is always open (Nav2 planners clear the robot's cell).
    cell = costmap.world_to_map(x, y)
    if cell is not None and opened[cell[1], cell[0]] == INSCRIBED_INFLATED_OBSTACLE:
        opened[cell[1], cell[0]] = MAX_NON_OBSTACLE
    return opened


def _xy(pose: Pose2D) -> str:
    return f"({pose.x:.2f}, {pose.y:.2f})"
