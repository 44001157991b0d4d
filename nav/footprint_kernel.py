"""The cost of a polygon footprint at a pose, compiled: Nav2's ``footprintCostAtPose``.

Nav2's ``FootprintCollisionChecker`` lays the footprint's outline on the costmap at the pose
and takes the highest cost of the cells its edges cross (``lineCost`` over each edge, the last
vertex joined to the first); the controller and the behaviours call a pose in collision when
that cost is ``LETHAL_OBSTACLE``. Here each edge is sampled every half cell (as the obstacle
layer samples its beams): the cells of the samples are the cells the edge crosses. Cells off
the grid and unknown cells are left out of the maximum and reported apart, so the caller
decides what unknown space means, as it does for a circular robot's centre.

The Regulated Pure Pursuit kernel (:mod:`baobab.nav.rpp_kernel`) calls :func:`footprint_cost`
for every projected pose; :func:`footprint_collisions` checks many poses at once for the
behaviours and the planner (:mod:`baobab.nav.footprint`).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from baobab.nav.costmap import LETHAL_OBSTACLE, NO_INFORMATION
from baobab.sim.records import Record

UNSEEN = -1
""":func:`footprint_cost` when no cell under the outline is known."""


@numba.njit(cache=True, nogil=True)
def footprint_cost(
    cells: np.ndarray, grid: Record, outline: np.ndarray, x: float, y: float, yaw: float
) -> tuple[int, bool]:  # pragma: no cover - compiled
    """The highest known cost under ``outline`` (``(N, 2)`` in ``base_link``, m) placed at
    ``(x, y, yaw)`` (m, rad), or :data:`UNSEEN`, and whether any of it lies on unknown cells
    or off the grid.

    ``grid`` is the costmap's :data:`~baobab.nav.costmap.GRID` record.
    """
    cos_yaw, sin_yaw = math.cos(yaw), math.sin(yaw)
    step = grid.resolution / 2
    size_y, size_x = cells.shape
    highest, unknown = UNSEEN, False
    count = outline.shape[0]
    for i in range(count):
        j = (i + 1) % count
        x0 = x + cos_yaw * outline[i, 0] - sin_yaw * outline[i, 1]
        y0 = y + sin_yaw * outline[i, 0] + cos_yaw * outline[i, 1]
        x1 = x + cos_yaw * outline[j, 0] - sin_yaw * outline[j, 1]
        y1 = y + sin_yaw * outline[j, 0] + cos_yaw * outline[j, 1]
        samples = max(math.ceil(math.hypot(x1 - x0, y1 - y0) / step), 1)
        for k in range(samples):
            t = k / samples
            ix = math.floor((x0 + t * (x1 - x0) - grid.origin_x) / grid.resolution)
            iy = math.floor((y0 + t * (y1 - y0) - grid.origin_y) / grid.resolution)
            if not (0 <= ix < size_x and 0 <= iy < size_y):
                unknown = True
                continue
            cost = int(cells[iy, ix])
            if cost == NO_INFORMATION:
                unknown = True
            elif cost > highest:
                highest = cost
    return highest, unknown


@numba.njit(cache=True, nogil=True)
def footprint_collides(
    cells: np.ndarray,
    grid: Record,
    outline: np.ndarray,
    x: float,
    y: float,
    yaw: float,
    unknown_is_collision: bool,
) -> bool:  # pragma: no cover - compiled
    """True when the outline at the pose touches a lethal cell (or unknown space, when
    ``unknown_is_collision``)."""
    highest, unknown = footprint_cost(cells, grid, outline, x, y, yaw)
    return highest >= LETHAL_OBSTACLE or (unknown_is_collision and unknown)


@numba.njit(cache=True, nogil=True)
def footprint_collisions(
    cells: np.ndarray,
    grid: np.ndarray,
    outline: np.ndarray,
    poses: np.ndarray,
    unknown_is_collision: bool,
) -> np.ndarray:  # pragma: no cover - compiled
    """:func:`footprint_collides` for each row ``(x, y, yaw)`` of ``poses``; ``grid`` is the
    one-element :data:`~baobab.nav.costmap.GRID` array."""
    g = grid[0]
    hits = np.zeros(poses.shape[0], dtype=np.bool_)
    for k in range(poses.shape[0]):
        hits[k] = footprint_collides(
            cells, g, outline, poses[k, 0], poses[k, 1], poses[k, 2], unknown_is_collision
        )
    return hits
