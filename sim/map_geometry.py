"""A map's solid cells as geometry: merged into rectangles, and distances to them.

Physics gets one box per rectangle of :func:`solid_rectangles`: runs of solid cells along
each row, merged with the identical runs of the rows above (and the same with rows and columns
swapped; the fewer rectangles win). A wall drawn along x or y is then one box, and a real map
a few thousand at most. :func:`signed_distance_to_cells` is the exact distance from a point
to the nearest solid cell's square, for checking start poses.
"""

from __future__ import annotations

import math

import numpy as np

Rectangles = np.ndarray
"""``int64`` rows ``(ix0, iy0, ix1, iy1)``: cells ``[ix0, ix1) x [iy0, iy1)``."""


def solid_rectangles(solid: np.ndarray) -> Rectangles:
    """Disjoint rectangles covering exactly the true cells of ``solid`` (rows along y).

    Returns:
        ``(n, 4)`` int64 ``(ix0, iy0, ix1, iy1)`` rows, the fewer of the row-first and the
        column-first merge.
    """
    by_rows = _merged_runs(solid)
    by_columns = _merged_runs(solid.T)[:, [1, 0, 3, 2]]
    return by_rows if len(by_rows) <= len(by_columns) else by_columns


def _merged_runs(solid: np.ndarray) -> Rectangles:
    """Runs of true cells along each row, merged with identical runs in consecutive rows."""
    height, width = solid.shape
    padded = np.zeros((height, width + 2), dtype=np.int8)
    padded[:, 1:-1] = solid
    edges = np.diff(padded, axis=1)
    start_rows, starts = np.nonzero(edges == 1)
    end_rows, ends = np.nonzero(edges == -1)
    if len(starts) == 0:
        return np.empty((0, 4), dtype=np.int64)
    # nonzero lists row by row, left to right: the k-th start and the k-th end make a run.
    del end_rows
    order = np.lexsort((start_rows, ends, starts))
    rows, x0, x1 = start_rows[order], starts[order], ends[order]
    new = np.ones(len(rows), dtype=bool)
    new[1:] = (x0[1:] != x0[:-1]) | (x1[1:] != x1[:-1]) | (rows[1:] != rows[:-1] + 1)
    first = np.flatnonzero(new)
    last = np.append(first[1:], len(rows)) - 1
    return np.stack((x0[first], rows[first], x1[first], rows[last] + 1), axis=1).astype(np.int64)


def signed_distance_to_cells(
    cells: np.ndarray,
    origin: tuple[float, float],
    resolution: float,
    x: float,
    y: float,
    reach: int = 4,
) -> float:
    """Distance (m) from ``(x, y)`` to the nearest true cell's square; negative inside one.

    Inside a true cell the value is minus the distance to the nearest false cell (``-inf``
    when every cell is true). ``inf`` when no cell is true. Cells beyond the grid do not count.

    Args:
        cells: bool grid, ``cells[iy, ix]``.
        origin: map-frame position (m) of the lower-left corner of cell (0, 0).
        resolution: cell side (m).
        x: the point (m).
        y: the point (m).
        reach: cells around the point searched first (the search widens until it is sure):
            a caller that knows about how far the nearest cell is saves the widening.
    """
    ix = math.floor((x - origin[0]) / resolution)
    iy = math.floor((y - origin[1]) / resolution)
    height, width = cells.shape
    inside = 0 <= ix < width and 0 <= iy < height and bool(cells[iy, ix])
    target = ~cells if inside else cells
    distance = _nearest_square(target, origin, resolution, x, y, ix, iy, max(reach, 1))
    return -distance if inside else distance


def _nearest_square(
    cells: np.ndarray,
    origin: tuple[float, float],
    resolution: float,
    x: float,
    y: float,
    ix: int,
    iy: int,
    reach: int,
) -> float:
    """Distance (m) from ``(x, y)`` in cell ``(ix, iy)`` to the nearest true cell's square.

    Searches square windows around the point from ``reach`` cells, doubling: every cell
    outside a window of reach ``r`` cells is at least ``r`` cells away, so a hit that near is
    final.
    """
    height, width = cells.shape
    while True:
        best = math.inf
        i0, i1 = max(ix - reach, 0), min(ix + reach + 1, width)
        j0, j1 = max(iy - reach, 0), min(iy + reach + 1, height)
        if i0 < i1 and j0 < j1:
            rows, cols = np.nonzero(cells[j0:j1, i0:i1])
            if len(rows):
                left = origin[0] + (cols + i0) * resolution
                bottom = origin[1] + (rows + j0) * resolution
                gap_x = np.maximum(np.maximum(left - x, x - (left + resolution)), 0.0)
                gap_y = np.maximum(np.maximum(bottom - y, y - (bottom + resolution)), 0.0)
                best = float(np.sqrt(gap_x * gap_x + gap_y * gap_y).min())
        covers = ix - reach <= 0 and iy - reach <= 0 and ix + reach >= width - 1
        if best <= reach * resolution or (covers and iy + reach >= height - 1):
            return best
        reach *= 2
