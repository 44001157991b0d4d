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
from typing import NamedTuple

import numba
import numpy as np

from baobab.nav.costmap import GRID, MAX_NON_OBSTACLE, NO_INFORMATION, Costmap2D
from baobab.nav.path import Path
from baobab.sim.records import record

CONVERGED = 0
COLLISION = 1
MAX_ITERATIONS = 2


SMOOTHER = np.dtype(
    [
        ("tolerance", np.float64),  # a sweep that moves the points less in all (m) converged
        ("max_its", np.int64),  # sweeps before giving up
        ("w_data", np.float64),  # pull towards the original path
        ("w_smooth", np.float64),  # pull towards the neighbours' midpoint
    ]
)
"""One smoothing round's settings, one field per :class:`SimpleSmoother` field of the same name."""


@numba.njit(cache=True, nogil=True)
def _smooth_round(
    data: np.ndarray, cells: np.ndarray, grid: np.ndarray, settings: np.ndarray
) -> tuple[int, np.ndarray]:  # pragma: no cover - compiled
    """Sweep until converged; on a collision, the points as they were before that sweep.

    ``data`` is the path's points (N, 2) (m); ``cells`` and ``grid`` (a
    :data:`~baobab.nav.costmap.GRID` record) the costmap (no cells: nothing collides);
    ``settings`` a :data:`SMOOTHER` record. The neighbours travel in registers from one point
    to the next (the point before was just moved, the point after not yet), so a sweep waits
    on no memory round trip; the sweep's old values are kept for the undo.
    """
    g, s = grid[0], settings[0]
    w_data, w_smooth, tolerance, max_its = s.w_data, s.w_smooth, s.tolerance, s.max_its
    origin_x, origin_y, resolution = g.origin_x, g.origin_y, g.resolution
    new = data.copy()
    n = data.shape[0]
    if n < 3:
        return CONVERGED, new
    replaced = np.empty_like(data)
    height, width = cells.shape
    change = tolerance
    its = 0
    while change >= tolerance:
        its += 1
        change = 0.0
        if its >= max_its:
            return MAX_ITERATIONS, new
        prev_x, prev_y = new[0, 0], new[0, 1]
        cur_x, cur_y = new[1, 0], new[1, 1]
        for i in range(1, n - 1):
            next_x, next_y = new[i + 1, 0], new[i + 1, 1]
            moved_x = cur_x + w_data * (data[i, 0] - cur_x)
            moved_x += w_smooth * (next_x + prev_x - 2.0 * cur_x)
            change += abs(moved_x - cur_x)
            moved_y = cur_y + w_data * (data[i, 1] - cur_y)
            moved_y += w_smooth * (next_y + prev_y - 2.0 * cur_y)
            change += abs(moved_y - cur_y)
            new[i, 0], new[i, 1] = moved_x, moved_y
            replaced[i, 0], replaced[i, 1] = cur_x, cur_y
            col = int(np.floor((moved_x - origin_x) / resolution))
            row = int(np.floor((moved_y - origin_y) / resolution))
            if 0 <= row < height and 0 <= col < width:
                cost = cells[row, col]
                if cost > MAX_NON_OBSTACLE and cost != NO_INFORMATION:
                    for k in range(1, i + 1):
                        new[k, 0], new[k, 1] = replaced[k, 0], replaced[k, 1]
                    return COLLISION, new
            prev_x, prev_y = moved_x, moved_y
            cur_x, cur_y = next_x, next_y
    return CONVERGED, new


@dataclass(frozen=True)
class SmoothResult:
    """A smoothed path and whether every smoothing round converged without collision."""

    path: Path
    was_completed: bool


class SmoothedPoints(NamedTuple):
    """Smoothed points and whether every smoothing round converged without collision."""

    points: np.ndarray
    """``(N, 2)`` map positions (m)."""
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

    def pack(self) -> np.ndarray:
        """The settings of one smoothing round as a :data:`SMOOTHER` record."""
        return record(SMOOTHER, self)

    def smooth(self, path: Path, costmap: Costmap2D | None = None) -> SmoothResult:
        """Smooth ``path``, keeping every moved point out of lethal and inscribed cells.

        Orientations are recomputed along the smoothed path; the last pose keeps its yaw.
        Without a costmap nothing is checked.
        """
        if len(path) < 3:
            return SmoothResult(path, True)
        smoothed = self.smooth_points(path.xy, costmap)
        path_out = Path.from_points(smoothed.points, float(path.yaws[-1]), path.frame_id)
        return SmoothResult(path_out, smoothed.was_completed)

    def smooth_points(self, points: np.ndarray, costmap: Costmap2D | None) -> SmoothedPoints:
        """Smooth ``(N, 2)`` map points (m) as :meth:`smooth` does; the input is not changed.

        Fewer than three points come back as they are.
        """
        xy = np.ascontiguousarray(points, dtype=float)
        if xy.shape[0] < 3:
            return SmoothedPoints(xy, True)
        if costmap is None:
            cells = np.zeros((0, 0), dtype=np.uint8)
            grid = record(GRID, origin_x=0.0, origin_y=0.0, resolution=1.0, inscribed_radius=0.0)
        else:
            cells, grid = costmap.data, costmap.pack()
        settings = self.pack()
        for _ in range(1 + (self.refinement_num if self.do_refinement else 0)):
            status, xy = _smooth_round(xy, cells, grid, settings)
            if status != CONVERGED:
                return SmoothedPoints(xy, False)
        return SmoothedPoints(xy, True)
