"""Compiled (numba) kernels of the costmap layers: lidar ray tracing and windowed inflation.

The kernels do the same float operations, in the same order, as the straightforward
formulas they replace, so their results are bit for bit those formulas' results:

- :func:`trace_scan` finds the cell of each ray sample with precomputed cell thresholds
  (:func:`cell_thresholds`) instead of a division per sample: ``floor(u / resolution) >= n``
  holds exactly when ``u >= thresholds[n]``, so walking a sample's index to its neighbour is
  the same as dividing.
- :func:`refresh_window` rebuilds a rectangle of a layered costmap's master: the static and
  obstacle cells are combined, then every cell takes the cost of the squared distance (in
  cells) to its nearest lethal cell. That distance is exact and separable: the vertical gap to
  the nearest lethal cell of each column, then the minimum over the row neighbours within the
  inflation reach of ``dx^2 + gap^2``.
"""

from __future__ import annotations

import math

import numba
import numpy as np

# Cost values (baobab.nav.costmap), repeated as literals the compiled code can fold.
_FREE = 0
_INSCRIBED = 253
_LETHAL = 254
_UNKNOWN = 255


def cell_thresholds(count: int, resolution: float) -> np.ndarray:
    """``thresholds[n]`` (``n = 0 .. count``): the least ``u`` with ``floor(u / resolution) >= n``.

    Division by a positive number rounds monotonically, so ``floor(u / resolution) >= n``
    exactly when ``u >= thresholds[n]``.
    """
    index = np.arange(count + 1, dtype=np.float64)
    u = index * resolution
    for _ in range(64):
        below = np.nextafter(u, -np.inf)
        step_down = below / resolution >= index
        step_up = u / resolution < index
        if not (step_down.any() or step_up.any()):
            return u
        u = np.where(step_down, below, np.where(step_up, np.nextafter(u, np.inf), u))
    raise ArithmeticError("cell thresholds did not converge")  # pragma: no cover


@numba.njit(cache=True, nogil=True)
def trace_scan(
    data: np.ndarray,
    touched: np.ndarray,
    changed_index: np.ndarray,
    changed_old: np.ndarray,
    threshold_x: np.ndarray,
    threshold_y: np.ndarray,
    origin_x: float,
    origin_y: float,
    resolution: float,
    x: float,
    y: float,
    cos_h: np.ndarray,
    sin_h: np.ndarray,
    ranges: np.ndarray,
    range_min: float,
    obstacle_min: float,
    obstacle_max: float,
    raytrace_max: float,
    samples: np.ndarray,
    samples_start: float,
    samples_step: float,
    bounds: np.ndarray,
) -> int:  # pragma: no cover - compiled
    """Clear every beam's cells up to its clearing length (its hit cell excluded), mark the hits.

    A beam is valid when its range is not NaN and at least ``range_min``; a valid finite range
    is a hit, which clears up to ``min(range, raytrace_max)`` and marks its cell lethal when
    ``obstacle_min <= range < obstacle_max``; a valid infinite range clears up to
    ``raytrace_max``. The beam is sampled at ``samples[k]``, the first values of
    ``numpy.arange(samples_start, longest clearing length, samples_step)`` (``samples`` holds
    that arange up to ``raytrace_max``).

    ``touched`` (zero, shaped like ``data``) is scratch, zero again on return. The cells whose
    value changed go to ``changed_index[:n]`` (``iy * width + ix``) with their old values in
    ``changed_old[:n]``, their bounds ``(ix0, iy0, ix1, iy1)`` to ``bounds``; returns ``n``. A
    cell cleared by one beam and marked again by another keeps its value: not a change.
    """
    height, width = data.shape
    beams = ranges.shape[0]
    clear_to = np.empty(beams, dtype=np.float64)
    longest = 0.0
    for b in range(beams):
        r = ranges[b]
        if np.isnan(r) or not r >= range_min:
            clear_to[b] = 0.0
        elif np.isfinite(r):
            clear_to[b] = r if r < raytrace_max else raytrace_max
        else:
            clear_to[b] = raytrace_max
        longest = max(longest, clear_to[b])
    # numpy.arange's length: ceil((stop - start) / step), none when not positive.
    span = (longest - samples_start) / samples_step
    count = min(max(math.ceil(span), 0), samples.shape[0]) if span > 0 else 0
    n = 0
    for b in range(beams):
        r = ranges[b]
        limit = clear_to[b]
        # Samples k < kb are the ones with samples[k] < limit (samples increase).
        lo, hi = 0, count
        while lo < hi:
            mid = (lo + hi) // 2
            if samples[mid] < limit:
                lo = mid + 1
            else:
                hi = mid
        kb = lo
        if kb == 0:
            continue
        is_hit = np.isfinite(r)
        end_x, end_y = -2, -2
        if is_hit:
            end_x = int(np.floor((x + cos_h[b] * r - origin_x) / resolution))
            end_y = int(np.floor((y + sin_h[b] * r - origin_y) / resolution))
        c, s = cos_h[b], sin_h[b]
        # Indices are kept in [-1, size]: -1 stands for any cell before the grid, size after.
        ix = int(np.floor((x + c * samples[0] - origin_x) / resolution))
        iy = int(np.floor((y + s * samples[0] - origin_y) / resolution))
        ix = min(max(ix, -1), width)
        iy = min(max(iy, -1), height)
        entered = False
        for k in range(kb):
            t = samples[k]
            ux = x + c * t - origin_x
            uy = y + s * t - origin_y
            while ix < width and ux >= threshold_x[ix + 1]:
                ix += 1
            while ix >= 0 and ux < threshold_x[ix]:
                ix -= 1
            while iy < height and uy >= threshold_y[iy + 1]:
                iy += 1
            while iy >= 0 and uy < threshold_y[iy]:
                iy -= 1
            if ix < 0 or ix >= width or iy < 0 or iy >= height:
                if entered:
                    break  # a ray leaves a rectangle once
                continue
            entered = True
            if is_hit and ix == end_x and iy == end_y:
                continue
            old = data[iy, ix]
            if old != _FREE:
                if touched[iy, ix] == 0:
                    touched[iy, ix] = 1
                    changed_index[n] = iy * width + ix
                    changed_old[n] = old
                    n += 1
                data[iy, ix] = _FREE
    for b in range(beams):
        r = ranges[b]
        if not (np.isfinite(r) and r >= range_min and r < obstacle_max and r >= obstacle_min):
            continue
        ix = int(np.floor((x + cos_h[b] * r - origin_x) / resolution))
        iy = int(np.floor((y + sin_h[b] * r - origin_y) / resolution))
        if 0 <= ix < width and 0 <= iy < height:
            old = data[iy, ix]
            if old != _LETHAL:
                if touched[iy, ix] == 0:
                    touched[iy, ix] = 1
                    changed_index[n] = iy * width + ix
                    changed_old[n] = old
                    n += 1
                data[iy, ix] = _LETHAL
    kept = 0
    for e in range(n):
        index = changed_index[e]
        iy, ix = index // width, index % width
        touched[iy, ix] = 0
        if data[iy, ix] == changed_old[e]:
            continue
        changed_index[kept] = index
        changed_old[kept] = changed_old[e]
        if kept == 0:
            bounds[0], bounds[1], bounds[2], bounds[3] = ix, iy, ix + 1, iy + 1
        else:
            bounds[0] = min(bounds[0], ix)
            bounds[1] = min(bounds[1], iy)
            bounds[2] = max(bounds[2], ix + 1)
            bounds[3] = max(bounds[3], iy + 1)
        kept += 1
    return kept


@numba.njit(cache=True, nogil=True)
def base_change_bounds(
    obstacle: np.ndarray,
    changed_index: np.ndarray,
    changed_old: np.ndarray,
    count: int,
    raster: np.ndarray,
    raster_x0: int,
    raster_y0: int,
    use_static: bool,
    bounds: np.ndarray,
) -> bool:  # pragma: no cover - compiled
    """Bounds of the changed obstacle cells whose combined (static max obstacle) value changed.

    ``raster_x0, raster_y0`` is the window's lattice offset in the static raster (lethal
    beyond it). Writes ``(ix0, iy0, ix1, iy1)`` to ``bounds``; returns whether any changed.
    """
    width = obstacle.shape[1]
    raster_h, raster_w = raster.shape
    found = False
    for e in range(count):
        index = changed_index[e]
        iy, ix = index // width, index % width
        static = _FREE
        if use_static:
            sx, sy = raster_x0 + ix, raster_y0 + iy
            static = raster[sy, sx] if 0 <= sx < raster_w and 0 <= sy < raster_h else _LETHAL
        if max(static, changed_old[e]) == max(static, obstacle[iy, ix]):
            continue
        if not found:
            bounds[0], bounds[1], bounds[2], bounds[3] = ix, iy, ix + 1, iy + 1
            found = True
        else:
            bounds[0] = min(bounds[0], ix)
            bounds[1] = min(bounds[1], iy)
            bounds[2] = max(bounds[2], ix + 1)
            bounds[3] = max(bounds[3], iy + 1)
    return found


@numba.njit(cache=True, nogil=True)
def _inflate_rows(
    gap: np.ndarray,
    rows: int,
    cols: int,
    reach: int,
    row0: int,
    row1: int,
    col0: int,
    col1: int,
    table: np.ndarray,
    out: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """Inflation cost of cells ``[row0, row1) x [col0, col1)`` of a window, from column gaps.

    First ``gap[:rows, :cols]`` holds 0 on lethal cells and a positive value elsewhere; it
    becomes each cell's vertical distance to the nearest lethal cell of its column (capped at
    the largest starting value, which must be at least ``reach + 1``). The cost of a cell is
    ``table[min(d2, last)]`` for ``d2`` the squared distance to its nearest lethal cell; the
    table must be ``FREE`` for every ``d2 > reach^2``, so lethal cells more than ``reach``
    cells away in x or y do not matter. Cells within ``reach`` of the output must lie in the
    window. ``out[i - row0, j - col0]`` gets the costs.
    """
    for r in range(1, rows):
        for c in range(cols):
            gap[r, c] = min(gap[r, c], gap[r - 1, c] + 1)
    for r in range(rows - 2, -1, -1):
        for c in range(cols):
            gap[r, c] = min(gap[r, c], gap[r + 1, c] + 1)
    last = table.shape[0] - 1
    squared = np.empty(cols, dtype=np.int64)
    best = np.empty(col1 - col0, dtype=np.int64)
    for r in range(row0, row1):
        for c in range(cols):
            squared[c] = gap[r, c] * gap[r, c]
        for j in range(col1 - col0):
            best[j] = squared[col0 + j]
        for o in range(1, reach + 1):
            o2 = o * o
            for j in range(col1 - col0):
                best[j] = min(best[j], min(squared[col0 + j - o], squared[col0 + j + o]) + o2)
        for j in range(col1 - col0):
            out[r - row0, j] = table[min(best[j], last)]


@numba.njit(cache=True, nogil=True)
def inflation_costs(
    lethal: np.ndarray, reach: int, table: np.ndarray
) -> np.ndarray:  # pragma: no cover - compiled
    """``table[min(d2, last)]`` per cell, ``d2`` the squared distance (cells) to the nearest lethal.

    The table must be ``FREE`` for every ``d2 > reach^2`` (and at its last index).
    """
    h, w = lethal.shape
    gap = np.empty((h + 2 * reach, w + 2 * reach), dtype=np.int64)
    gap[:, :] = reach + 1
    for i in range(h):
        for j in range(w):
            if lethal[i, j]:
                gap[reach + i, reach + j] = 0
    out = np.empty((h, w), dtype=np.uint8)
    _inflate_rows(
        gap, h + 2 * reach, w + 2 * reach, reach, reach, reach + h, reach, reach + w, table, out
    )
    return out


@numba.njit(cache=True, nogil=True)
def refresh_window(
    master: np.ndarray,
    raster: np.ndarray,
    raster_x0: int,
    raster_y0: int,
    use_static: bool,
    obstacle: np.ndarray,
    use_obstacle: bool,
    x0: int,
    y0: int,
    x1: int,
    y1: int,
    margin: int,
    reach: int,
    table: np.ndarray,
    gap: np.ndarray,
    base: np.ndarray,
    costs: np.ndarray,
) -> None:  # pragma: no cover - compiled
    """Recompute master cells ``[x0, x1) x [y0, y1)`` from the static and obstacle layers.

    A cell's combined value is the static raster's (lethal beyond the raster; free without a
    static layer) or, where larger, the obstacle layer's (inside the window only). Its master
    value is the larger of that and its inflation cost, except that an unknown cell only takes
    an inscribed or lethal inflation (Nav2's rule). Lethal cells up to ``margin`` cells beyond
    the rectangle count. ``gap``, ``base`` and ``costs`` are scratch at least
    ``(y1 - y0 + 2 margin, x1 - x0 + 2 margin)`` big.
    """
    height, width = master.shape
    raster_h, raster_w = raster.shape
    ix0, iy0 = x0 - margin, y0 - margin
    cols, rows = x1 - x0 + 2 * margin, y1 - y0 + 2 * margin
    for r in range(rows):
        gy = iy0 + r
        sy = raster_y0 + gy
        for c in range(cols):
            gx = ix0 + c
            value = _FREE
            if use_static:
                sx = raster_x0 + gx
                value = raster[sy, sx] if 0 <= sx < raster_w and 0 <= sy < raster_h else _LETHAL
            if use_obstacle and 0 <= gx < width and 0 <= gy < height:
                value = max(value, obstacle[gy, gx])
            base[r, c] = value
            gap[r, c] = 0 if value == _LETHAL else reach + 1
    _inflate_rows(
        gap, rows, cols, reach, margin, rows - margin, margin, cols - margin, table, costs
    )
    for i in range(y1 - y0):
        for j in range(x1 - x0):
            value = base[margin + i, margin + j]
            cost = costs[i, j]
            if value == _UNKNOWN:
                master[y0 + i, x0 + j] = cost if cost >= _INSCRIBED else _UNKNOWN
            else:
                master[y0 + i, x0 + j] = max(value, cost)
