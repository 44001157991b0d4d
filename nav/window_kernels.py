"""Compiled (numba) windowed refresh of a layered costmap's master: combine and inflate.

:func:`refresh_window` rebuilds a rectangle of the master: the static and obstacle cells are
combined, then every cell takes the cost of the squared distance (in cells) to its nearest
lethal cell. That distance is exact and separable: the vertical gap to the nearest lethal
cell of each column, then the minimum over the row neighbours within the inflation reach of
``dx^2 + gap^2``.

Compiled instead of ``scipy.ndimage.distance_transform_edt`` (the reference the tests compare
every cell with, ``tests/test_costmap_kernels.py``) because a costmap update touches a few
small rectangles around the changed cells: scipy would transform the whole window each time,
and the combining and table lookups around it would be a dozen numpy passes per rectangle.

The kernels read named records (:mod:`baobab.sim.records`): the window's placement and
settings (:data:`WINDOW`), the layers' arrays (:class:`Layers`) and scratch (:class:`Scratch`).
A rectangle of cells is ``(x0, y0, x1, y1)``, end exclusive.
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from baobab.nav.costmap import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
)
from baobab.nav.raytrace_kernels import include_cell
from baobab.sim.records import Record

WINDOW = np.dtype(
    [
        ("raster_x0", np.int64),  # the window's lattice offset in the static raster (cells)
        ("raster_y0", np.int64),
        ("use_static", np.bool_),  # the costmap has a static layer
        ("use_obstacle", np.bool_),  # and an obstacle layer
        ("margin", np.int64),  # cells a lethal cell's inflation reaches
        ("reach", np.int64),  # cells beyond which the cost table is free (<= margin)
    ],
    align=True,
)
"""Where a layered costmap's window lies and which layers it combines."""

Rect = tuple[int, int, int, int]
"""A rectangle of cells ``(x0, y0, x1, y1)``, end exclusive."""


class Layers(NamedTuple):
    """The arrays a master refresh reads and writes (cells ``[iy, ix]``, ``uint8``)."""

    master: np.ndarray
    """The combined, inflated costmap: written."""
    raster: np.ndarray
    """The static layer's whole raster (lethal beyond it)."""
    obstacle: np.ndarray
    """The obstacle layer's cells, shaped like the master."""
    table: np.ndarray
    """Inflation cost by squared cell distance; free at its last index and beyond ``reach``."""


class Scratch(NamedTuple):
    """Work space of :func:`refresh_window`, each at least the window grown by ``margin`` on
    every side."""

    gap: np.ndarray
    """``int32``."""
    base: np.ndarray
    """``uint8``."""
    costs: np.ndarray
    """``uint8``."""


@numba.njit(cache=True, nogil=True, inline="always")
def _static_cost(raster: np.ndarray, w: Record, sx: int, sy: int) -> int:  # pragma: no cover
    """The static layer's cost at raster cell (``sx``, ``sy``): lethal beyond the raster, free
    when the costmap has no static layer (``w`` a :data:`WINDOW` record)."""
    if not w.use_static:
        return FREE_SPACE
    raster_h, raster_w = raster.shape
    if 0 <= sx < raster_w and 0 <= sy < raster_h:
        return raster[sy, sx]
    return LETHAL_OBSTACLE


@numba.njit(cache=True, nogil=True, inline="always")
def combined_cost(static: int, obstacle: int) -> int:  # pragma: no cover - compiled
    """A cell's cost from the static layer's and the obstacle layer's: Nav2's ``updateWithMax``.

    An unknown obstacle cell adds nothing; a known one raises the cell, and replaces an
    unknown static cell (so a lidar hit on an unknown map cell is lethal, as in Nav2). A free
    obstacle cell adds nothing either: baobab's obstacle layer does not track unknown space,
    so free there may mean never seen, and it does not free an unknown map cell.
    """
    if obstacle in (NO_INFORMATION, FREE_SPACE):
        return static
    if static == NO_INFORMATION:
        return obstacle
    return max(static, obstacle)


@numba.njit(cache=True, nogil=True)
def base_change_bounds(
    obstacle: np.ndarray,
    raster: np.ndarray,
    window: np.ndarray,
    changed_index: np.ndarray,
    changed_old: np.ndarray,
    bounds: np.ndarray,
) -> bool:  # pragma: no cover - compiled
    """Bounds of the changed obstacle cells whose combined value (:func:`combined_cost`)
    changed.

    ``changed_index`` holds ``iy * width + ix`` of each changed cell, ``changed_old`` its old
    value; ``window`` is the :data:`WINDOW` record. Writes ``(ix0, iy0, ix1, iy1)`` to
    ``bounds``; returns whether any changed.
    """
    w = window[0]
    width = obstacle.shape[1]
    found = False
    for e in range(changed_index.shape[0]):
        index = changed_index[e]
        iy, ix = index // width, index % width
        static = _static_cost(raster, w, w.raster_x0 + ix, w.raster_y0 + iy)
        if combined_cost(static, changed_old[e]) == combined_cost(static, obstacle[iy, ix]):
            continue
        include_cell(bounds, ix, iy, not found)
        found = True
    return found


@numba.njit(cache=True, nogil=True)
def _inflate_rows(
    gap: np.ndarray,
    size: tuple[int, int],
    reach: int,
    rect: Rect,
    table: np.ndarray,
    out: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """Inflation cost of the cells ``rect`` of a window, from column gaps.

    First ``gap[:rows, :cols]`` (``size = (cols, rows)``) holds 0 on lethal cells and a
    positive value elsewhere; it becomes each cell's vertical distance to the nearest lethal
    cell of its column (capped at the largest starting value, which must be at least
    ``reach + 1``). The cost of a cell is ``table[min(d2, last)]`` for ``d2`` the squared
    distance to its nearest lethal cell; the table must be ``FREE`` for every ``d2 > reach^2``,
    so lethal cells more than ``reach`` cells away in x or y do not matter. Cells within
    ``reach`` of ``rect`` must lie in the window. ``out[iy - y0, ix - x0]`` gets the costs.
    """
    cols, rows = size
    col0, row0, col1, row1 = rect
    for r in range(1, rows):
        above, row = gap[r - 1], gap[r]
        for c in range(cols):
            row[c] = min(row[c], above[c] + 1)
    for r in range(rows - 2, -1, -1):
        below, row = gap[r + 1], gap[r]
        for c in range(cols):
            row[c] = min(row[c], below[c] + 1)
    last = table.shape[0] - 1
    span = col1 - col0
    squared = np.empty(cols, dtype=np.int32)
    best = np.empty(span, dtype=np.int32)
    for r in range(row0, row1):
        row = gap[r]
        for c in range(cols):
            squared[c] = row[c] * row[c]
        best[:] = squared[col0:col1]
        for o in range(1, reach + 1):
            o2 = np.int32(o * o)
            left = squared[col0 - o : col1 - o]
            right = squared[col0 + o : col1 + o]
            for j in range(span):
                best[j] = min(best[j], min(left[j], right[j]) + o2)
        costs = out[r - row0]
        for j in range(span):
            costs[j] = table[min(best[j], last)]


@numba.njit(cache=True, nogil=True)
def inflation_costs(
    lethal: np.ndarray, reach: int, table: np.ndarray
) -> np.ndarray:  # pragma: no cover - compiled
    """``table[min(d2, last)]`` per cell, ``d2`` the squared distance (cells) to the nearest lethal.

    The table must be ``FREE`` for every ``d2 > reach^2`` (and at its last index).
    """
    h, w = lethal.shape
    gap = np.empty((h + 2 * reach, w + 2 * reach), dtype=np.int32)
    gap[:, :] = reach + 1
    for i in range(h):
        for j in range(w):
            if lethal[i, j]:
                gap[reach + i, reach + j] = 0
    out = np.empty((h, w), dtype=np.uint8)
    size, inner = (w + 2 * reach, h + 2 * reach), (reach, reach, reach + w, reach + h)
    _inflate_rows(gap, size, reach, inner, table, out)
    return out


@numba.njit(cache=True, nogil=True)
def refresh_window(
    layers: Layers, window: np.ndarray, rect: Rect, scratch: Scratch
) -> None:  # pragma: no cover - compiled
    """Recompute the master cells ``rect`` from the static and obstacle layers.

    A cell's combined value is the static raster's (lethal beyond the raster; free without a
    static layer) raised by the obstacle layer's (inside the window only; :func:`combined_cost`).
    Its master value is the larger of that and its inflation cost, except that an unknown cell
    only takes an inscribed or lethal inflation (Nav2's rule). Lethal cells up to ``margin``
    cells beyond the rectangle count. ``window`` is the :data:`WINDOW` record.
    """
    w = window[0]
    master, raster, obstacle = layers.master, layers.raster, layers.obstacle
    gap, base, costs = scratch.gap, scratch.base, scratch.costs
    x0, y0, x1, y1 = rect
    margin = w.margin
    height, width = master.shape
    raster_h, raster_w = raster.shape
    ix0, iy0 = x0 - margin, y0 - margin
    cols, rows = x1 - x0 + 2 * margin, y1 - y0 + 2 * margin
    cap = w.reach + 1
    # Static cells where the rectangle meets the raster (lethal elsewhere), obstacle cells
    # where it meets the window, as row slices.
    rx0 = w.raster_x0 + ix0
    static_c0, static_c1 = max(-rx0, 0), min(raster_w - rx0, cols)
    obstacle_c0, obstacle_c1 = max(-ix0, 0), min(width - ix0, cols)
    for r in range(rows):
        gy = iy0 + r
        sy = w.raster_y0 + gy
        row = base[r]
        if w.use_static:
            row[:cols] = LETHAL_OBSTACLE
            if 0 <= sy < raster_h and static_c0 < static_c1:
                row[static_c0:static_c1] = raster[sy, rx0 + static_c0 : rx0 + static_c1]
        else:
            row[:cols] = FREE_SPACE
        if w.use_obstacle and 0 <= gy < height and obstacle_c0 < obstacle_c1:
            cells = obstacle[gy, ix0 + obstacle_c0 : ix0 + obstacle_c1]
            for c in range(obstacle_c1 - obstacle_c0):
                row[obstacle_c0 + c] = combined_cost(row[obstacle_c0 + c], cells[c])
        lethal_gap = gap[r]
        for c in range(cols):
            lethal_gap[c] = 0 if row[c] == LETHAL_OBSTACLE else cap
    inner = (margin, margin, cols - margin, rows - margin)
    _inflate_rows(gap, (cols, rows), w.reach, inner, layers.table, costs)
    for i in range(y1 - y0):
        values = base[margin + i, margin : margin + x1 - x0]
        inflated = costs[i]
        out = master[y0 + i, x0:x1]
        for j in range(x1 - x0):
            value, cost = values[j], inflated[j]
            if value == NO_INFORMATION:
                out[j] = cost if cost >= INSCRIBED_INFLATED_OBSTACLE else NO_INFORMATION
            else:
                out[j] = max(value, cost)


@numba.njit(cache=True, nogil=True)
def shift_grid(data: np.ndarray, dix: int, diy: int, fill: int) -> None:  # pragma: no cover
    """Move a grid's content in place: cell ``(ix, iy)`` takes the value of cell
    ``(ix + dix, iy + diy)``, or ``fill`` where that lies outside the grid."""
    height, width = data.shape
    rows = range(height - 1, -1, -1) if diy < 0 else range(height)
    for iy in rows:
        sy = iy + diy
        if sy < 0 or sy >= height:
            for ix in range(width):
                data[iy, ix] = fill
            continue
        if dix < 0:
            for ix in range(width - 1, -1, -1):
                sx = ix + dix
                data[iy, ix] = data[sy, sx] if sx >= 0 else fill
        else:
            for ix in range(width):
                sx = ix + dix
                data[iy, ix] = data[sy, sx] if sx < width else fill


@numba.njit(cache=True, nogil=True)
def dropped_base_bounds(
    obstacle: np.ndarray,
    raster: np.ndarray,
    window: np.ndarray,
    dix: int,
    diy: int,
    bounds: np.ndarray,
) -> bool:  # pragma: no cover - compiled
    """Bounds of the obstacle cells a window move by ``(dix, diy)`` drops that raised a cell.

    A dropped cell matters when it made its combined cell (:func:`combined_cost`) differ from
    the static cell alone. ``window`` is the :data:`WINDOW` record before the move. Bounds
    ``(ix0, iy0, ix1, iy1)`` go to ``bounds`` in the window's cells before the move; returns
    whether there are any.
    """
    w = window[0]
    height, width = obstacle.shape
    kept_x0, kept_x1 = max(dix, 0), width + min(dix, 0)
    kept_y0, kept_y1 = max(diy, 0), height + min(diy, 0)
    found = False
    for iy in range(height):
        # A kept row drops only the cells left and right of the kept columns.
        kept_row = kept_y0 <= iy < kept_y1
        for segment in range(2):
            if kept_row:
                c0, c1 = (0, kept_x0) if segment == 0 else (kept_x1, width)
            else:
                c0, c1 = (0, width) if segment == 0 else (0, 0)
            for ix in range(c0, c1):
                value = obstacle[iy, ix]
                if value == FREE_SPACE:
                    continue
                static = _static_cost(raster, w, w.raster_x0 + ix, w.raster_y0 + iy)
                if combined_cost(static, value) == static:
                    continue
                include_cell(bounds, ix, iy, not found)
                found = True
    return found


@numba.njit(cache=True, nogil=True)
def refresh_window_static(
    layers: Layers, static_costs: np.ndarray, window: np.ndarray, rect: Rect, costs: np.ndarray
) -> None:  # pragma: no cover - compiled
    """:func:`refresh_window` from the static layer's own inflation plus the obstacles'.

    ``static_costs`` is the inflation cost of the static raster by itself (lethal beyond the
    raster). The combined lethal cells are the static ones and the obstacle layer's
    (:func:`combined_cost`); with a cost table that never rises with the distance, the cost
    of the nearest lethal cell of the union is the larger of the static cost and the cost of
    the nearest obstacle that makes a static cell lethal, so only those obstacles are stamped
    in. ``costs`` is scratch of at least the rectangle's size.
    """
    w = window[0]
    master, raster, obstacle, table = layers.master, layers.raster, layers.obstacle, layers.table
    x0, y0, x1, y1 = rect
    reach, raster_x0, raster_y0 = w.reach, w.raster_x0, w.raster_y0
    use_static, use_obstacle = w.use_static, w.use_obstacle
    height, width = master.shape
    raster_h, raster_w = raster.shape
    last = table.shape[0] - 1
    ox0, oy0 = max(x0 - reach, 0), max(y0 - reach, 0)
    ox1, oy1 = min(x1 + reach, width), min(y1 + reach, height)
    for i in range(y1 - y0):
        sy = raster_y0 + y0 + i
        inside_y = 0 <= sy < raster_h
        row = costs[i]
        for j in range(x1 - x0):
            sx = raster_x0 + x0 + j
            if not use_static:
                row[j] = FREE_SPACE
            elif inside_y and 0 <= sx < raster_w:
                row[j] = static_costs[sy, sx]
            else:
                row[j] = table[0]
    if use_obstacle:
        for oy in range(oy0, oy1):
            for ox in range(ox0, ox1):
                value = obstacle[oy, ox]
                if value != LETHAL_OBSTACLE:
                    continue
                static = _static_cost(raster, w, raster_x0 + ox, raster_y0 + oy)
                if static == LETHAL_OBSTACLE:
                    continue  # already lethal in the static costs
                for i in range(max(oy - reach, y0), min(oy + reach + 1, y1)):
                    dy = i - oy
                    row = costs[i - y0]
                    for j in range(max(ox - reach, x0), min(ox + reach + 1, x1)):
                        dx = j - ox
                        cost = table[min(dx * dx + dy * dy, last)]
                        if cost > row[j - x0]:
                            row[j - x0] = cost
    for i in range(y1 - y0):
        gy = y0 + i
        sy = raster_y0 + gy
        inside_y = 0 <= sy < raster_h
        row = costs[i]
        out = master[gy]
        for j in range(x1 - x0):
            gx = x0 + j
            value = FREE_SPACE
            if use_static:
                sx = raster_x0 + gx
                value = raster[sy, sx] if inside_y and 0 <= sx < raster_w else LETHAL_OBSTACLE
            if use_obstacle:
                value = combined_cost(value, obstacle[gy, gx])
            cost = row[j]
            if value == NO_INFORMATION:
                out[gx] = cost if cost >= INSCRIBED_INFLATED_OBSTACLE else NO_INFORMATION
            else:
                out[gx] = max(value, cost)
