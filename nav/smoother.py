"""Nav2's Simple Smoother: gradient smoothing that never moves a pose into collision.

Each sweep moves every inner point towards the original path (``w_data``) and towards the
midpoint of its neighbours (``w_smooth``), Gauss-Seidel style, until the summed change falls
below ``tolerance``. When a moved point lands on a cell costlier than ``MAX_NON_OBSTACLE``
(inscribed or lethal; unknown is allowed), the sweep is undone and the path of the previous
sweep is returned. With ``do_refinement`` the smoothed path is smoothed again, up to
``refinement_num`` more times, as Nav2 does. The end points never move.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from baobab.nav.costmap import MAX_NON_OBSTACLE, NO_INFORMATION, Costmap2D
from baobab.nav.path import Path

CONVERGED = 0
COLLISION = 1
MAX_ITERATIONS = 2


@numba.njit(cache=True, nogil=True)
def _smooth_round(
    data: np.ndarray,
    grid: np.ndarray,
    origin_x: float,
    origin_y: float,
    resolution: float,
    w_data: float,
    w_smooth: float,
    tolerance: float,
    max_its: int,
) -> tuple[int, np.ndarray]:  # pragma: no cover - compiled
    new = data.copy()
    last = data.copy()
    n = data.shape[0]
    height, width = grid.shape
    change = tolerance
    its = 0
    while change >= tolerance:
        its += 1
        change = 0.0
        if its >= max_its:
            return MAX_ITERATIONS, last
        for i in range(1, n - 1):
            for j in range(2):
                before = new[i, j]
                moved = before + w_data * (data[i, j] - before)
                moved += w_smooth * (new[i + 1, j] + new[i - 1, j] - 2.0 * before)
                new[i, j] = moved
                change += abs(moved - before)
            col = int(np.floor((new[i, 0] - origin_x) / resolution))
            row = int(np.floor((new[i, 1] - origin_y) / resolution))
            if 0 <= row < height and 0 <= col < width:
                cost = grid[row, col]
                if cost > MAX_NON_OBSTACLE and cost != NO_INFORMATION:
                    return COLLISION, last
        last[:, :] = new
    return CONVERGED, new


@dataclass(frozen=True)
class SmoothResult:
    """A smoothed path and whether every smoothing round converged without collision."""

    path: Path
    was_completed: bool


@dataclass(frozen=True)
class SimpleSmoother:
    """Nav2's ``nav2_smoother::SimpleSmoother`` with its defaults."""

    tolerance: float = 1e-10
    max_its: int = 1000
    w_data: float = 0.2
    w_smooth: float = 0.3
    do_refinement: bool = True
    refinement_num: int = 2

    def smooth(self, path: Path, costmap: Costmap2D | None = None) -> SmoothResult:
        """Smooth ``path``, keeping every moved point out of lethal and inscribed cells.

        Orientations are recomputed along the smoothed path; the last pose keeps its yaw.
        Without a costmap nothing is checked.
        """
        if len(path) < 3:
            return SmoothResult(path, True)
        if costmap is None:
            grid = np.zeros((0, 0), dtype=np.uint8)
            origin, resolution = (0.0, 0.0), 1.0
        else:
            grid, origin, resolution = costmap.data, costmap.origin, costmap.resolution
        points = np.ascontiguousarray(path.xy, dtype=float)
        completed = True
        for _ in range(1 + (self.refinement_num if self.do_refinement else 0)):
            status, points = _smooth_round(
                points,
                grid,
                origin[0],
                origin[1],
                resolution,
                self.w_data,
                self.w_smooth,
                self.tolerance,
                self.max_its,
            )
            if status != CONVERGED:
                completed = False
                break
        smoothed = Path.from_points(points, float(path.yaws[-1]), path.frame_id)
        return SmoothResult(smoothed, completed)
