"""Compiled (numba) kernels of the costmap layers: lidar ray tracing and windowed inflation.

The kernels do the same float operations, in the same order, as the straightforward
formulas they replace, so their results are bit for bit those formulas' results:

- :func:`trace_scan` tests whether a ray sample lies in a cell with precomputed cell
  thresholds (:func:`cell_thresholds`): ``floor(u / resolution) == n`` holds exactly when
  ``thresholds[n] <= u < thresholds[n + 1]``. Clearing only changes cells that are not free,
  so only those (a few dozen, near walls and obstacles) are tested, each against the few
  beams whose direction meets it, instead of walking every sample of every beam.
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
    headings: np.ndarray,
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
    ``raytrace_max``. Beam ``b`` (direction ``headings[b]``, whose cosine and sine are
    ``cos_h[b]``, ``sin_h[b]``) clears the grid cells of its samples ``x + cos_h[b] * t``,
    ``y + sin_h[b] * t`` for ``t`` in ``samples[k]``, the values of
    ``numpy.arange(samples_start, longest clearing length, samples_step)`` below its own
    clearing length (``samples`` holds that arange up to ``raytrace_max``).

    Clearing only changes cells that are not free, so rather than walking every sample of
    every beam, each such cell near the sensor asks the few beams whose direction meets it
    whether one of their samples falls in it.

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
    # Per beam: how many samples it clears (those below its length), its hit cell.
    reach = np.zeros(beams, dtype=np.int64)
    # Hit cells, -1 / size standing for any cell before / after the grid.
    end_x = np.full(beams, -1, dtype=np.int64)
    end_y = np.full(beams, -1, dtype=np.int64)
    per_step = 1.0 / samples_step
    per_cell = 1.0 / resolution
    for b in range(beams):
        limit = clear_to[b]
        kb = 0
        if limit > samples_start:
            kb = min(int((limit - samples_start) * per_step), count)
        while kb < count and samples[kb] < limit:
            kb += 1
        while kb > 0 and not samples[kb - 1] < limit:
            kb -= 1
        reach[b] = kb
        r = ranges[b]
        if np.isfinite(r) and r >= range_min:
            end_x[b] = _cell_of(x + cos_h[b] * r - origin_x, per_cell, threshold_x)
            end_y[b] = _cell_of(y + sin_h[b] * r - origin_y, per_cell, threshold_y)
    n = 0
    if count > 0:
        n = _clear_cells(
            data,
            touched,
            changed_index,
            changed_old,
            threshold_x,
            threshold_y,
            origin_x,
            origin_y,
            resolution,
            x,
            y,
            headings,
            cos_h,
            sin_h,
            reach,
            end_x,
            end_y,
            samples,
            samples_start,
            samples_step,
            samples[count - 1],
        )
    for b in range(beams):
        r = ranges[b]
        if not (np.isfinite(r) and r >= range_min and r < obstacle_max and r >= obstacle_min):
            continue
        ix, iy = end_x[b], end_y[b]
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


@numba.njit(cache=True, nogil=True, inline="always")
def _cell_of(u: float, per_cell: float, thresholds: np.ndarray) -> int:  # pragma: no cover
    """``floor(u / resolution)`` clamped to ``[-1, size]`` (``size + 1`` thresholds), exactly.

    The product with ``per_cell = 1 / resolution`` is off by at most one cell; the thresholds
    settle it.
    """
    size = thresholds.shape[0] - 1
    guess = u * per_cell
    if not guess > -1.0:
        index = -1
    elif guess >= size:
        index = size
    else:
        index = int(np.floor(guess))
    while index < size and u >= thresholds[index + 1]:
        index += 1
    while index >= 0 and u < thresholds[index]:
        index -= 1
    return index


@numba.njit(cache=True, nogil=True)
def _clear_cells(
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
    headings: np.ndarray,
    cos_h: np.ndarray,
    sin_h: np.ndarray,
    reach: np.ndarray,
    end_x: np.ndarray,
    end_y: np.ndarray,
    samples: np.ndarray,
    samples_start: float,
    samples_step: float,
    farthest: float,
) -> int:  # pragma: no cover - compiled
    """Free every non-free cell that a sample of some beam falls in (see :func:`trace_scan`).

    Returns how many cells it recorded in ``changed_index`` / ``changed_old``.
    """
    height, width = data.shape
    beams = headings.shape[0]
    # Beams by direction: angular bins of width about half the beam spacing.
    bins = 2 * beams
    bin_width = 2.0 * np.pi / bins
    per_bin = 1.0 / bin_width
    per_turn = 1.0 / (2.0 * np.pi)
    first = np.zeros(bins + 1, dtype=np.int64)
    beam_bin = np.empty(beams, dtype=np.int64)
    for b in range(beams):
        # Approximate bins are fine: a cell looks one bin beyond its angular extent.
        angle = headings[b] - 2.0 * np.pi * np.floor(headings[b] * per_turn)
        k = min(max(int(angle * per_bin), 0), bins - 1)
        beam_bin[b] = k
        first[k + 1] += 1
    for k in range(bins):
        first[k + 1] += first[k]
    fill = first[:-1].copy()
    by_bin = np.empty(beams, dtype=np.int64)
    for b in range(beams):
        by_bin[fill[beam_bin[b]]] = b
        fill[beam_bin[b]] += 1
    # Margins that make every test below a superset of the exact sample test: the float
    # sample points lie within ~1e-13 m of the ideal ray, far inside these.
    eps = 1e-9 + 1e-12 * (abs(x) + abs(y) + abs(origin_x) + abs(origin_y) + farthest)
    half_diagonal = 0.5 * resolution * math.sqrt(2.0) + 2.0 * eps
    sensor_u = x - origin_x
    sensor_v = y - origin_y
    # Every sample lies within ``farthest`` of the sensor.
    ix0 = max(int(np.floor((sensor_u - farthest) / resolution)) - 1, 0)
    iy0 = max(int(np.floor((sensor_v - farthest) / resolution)) - 1, 0)
    ix1 = min(int(np.floor((sensor_u + farthest) / resolution)) + 2, width)
    iy1 = min(int(np.floor((sensor_v + farthest) / resolution)) + 2, height)
    n = 0
    for iy in range(iy0, iy1):
        for ix in range(ix0, ix1):
            old = data[iy, ix]
            if old == _FREE:
                continue
            u0, u1 = threshold_x[ix] - eps, threshold_x[ix + 1] + eps
            v0, v1 = threshold_y[iy] - eps, threshold_y[iy + 1] + eps
            dx = 0.5 * (u0 + u1) - sensor_u
            dy = 0.5 * (v0 + v1) - sensor_v
            distance = math.sqrt(dx * dx + dy * dy)
            if distance > farthest + half_diagonal:
                continue
            if distance <= 2.0 * half_diagonal:
                bin_lo, bin_hi = 0, bins - 1
            else:
                half = half_diagonal / (distance - half_diagonal) + 1e-9
                centre = math.atan2(dy, dx)
                bin_lo = int(np.floor((centre - half) * per_bin)) - 1
                bin_hi = int(np.floor((centre + half) * per_bin)) + 1
                if bin_hi - bin_lo >= bins:
                    bin_lo, bin_hi = 0, bins - 1
            cleared = False
            for kb in range(bin_lo, bin_hi + 1):
                k = kb % bins
                for e in range(first[k], first[k + 1]):
                    b = by_bin[e]
                    if reach[b] == 0 or (ix == end_x[b] and iy == end_y[b]):
                        continue
                    if _sample_in_cell(
                        cos_h[b],
                        sin_h[b],
                        reach[b],
                        x,
                        y,
                        origin_x,
                        origin_y,
                        sensor_u,
                        sensor_v,
                        u0,
                        u1,
                        v0,
                        v1,
                        threshold_x[ix],
                        threshold_x[ix + 1],
                        threshold_y[iy],
                        threshold_y[iy + 1],
                        samples,
                        samples_start,
                        samples_step,
                    ):
                        cleared = True
                        break
                if cleared:
                    break
            if cleared:
                touched[iy, ix] = 1
                changed_index[n] = iy * width + ix
                changed_old[n] = old
                n += 1
                data[iy, ix] = _FREE
    return n


@numba.njit(cache=True, nogil=True, inline="always")
def _slab(origin: float, direction: float, lo: float, hi: float) -> tuple[float, float]:
    """Parameters ``t`` where ``origin + direction * t`` lies in ``[lo, hi]`` (may be empty)."""
    if abs(direction) < 1e-12:
        if lo <= origin <= hi:
            return -np.inf, np.inf
        return np.inf, -np.inf
    a = (lo - origin) / direction
    b = (hi - origin) / direction
    return (a, b) if a <= b else (b, a)


@numba.njit(cache=True, nogil=True)
def _sample_in_cell(
    c: float,
    s: float,
    count: int,
    x: float,
    y: float,
    origin_x: float,
    origin_y: float,
    sensor_u: float,
    sensor_v: float,
    u0: float,
    u1: float,
    v0: float,
    v1: float,
    cell_u0: float,
    cell_u1: float,
    cell_v0: float,
    cell_v1: float,
    samples: np.ndarray,
    samples_start: float,
    samples_step: float,
) -> bool:  # pragma: no cover - compiled
    """Whether one of the first ``count`` samples of a beam falls in a cell.

    ``[u0, u1] x [v0, v1]`` is the cell grown by a margin, to find the samples to test;
    ``[cell_u0, cell_u1) x [cell_v0, cell_v1)`` are its exact thresholds.
    """
    tx0, tx1 = _slab(sensor_u, c, u0, u1)
    ty0, ty1 = _slab(sensor_v, s, v0, v1)
    t0, t1 = max(tx0, ty0), min(tx1, ty1)
    if t0 > t1 or t1 < samples_start:
        return False
    k0 = 0
    if t0 > samples_start:
        k0 = int((t0 - samples_start) / samples_step) - 1
        if k0 >= count:
            return False
        k0 = max(k0, 0)
    k1 = count - 1
    if t1 < samples[k1]:
        k1 = min(int((t1 - samples_start) / samples_step) + 1, count - 1)
    for k in range(k0, k1 + 1):
        t = samples[k]
        u = x + c * t - origin_x
        if not (cell_u0 <= u < cell_u1):
            continue
        v = y + s * t - origin_y
        if cell_v0 <= v < cell_v1:
            return True
    return False


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
    cap = reach + 1
    # Static cells where the rectangle meets the raster (lethal elsewhere), obstacle cells
    # where it meets the window, as row slices.
    rx0 = raster_x0 + ix0
    static_c0, static_c1 = max(-rx0, 0), min(raster_w - rx0, cols)
    obstacle_c0, obstacle_c1 = max(-ix0, 0), min(width - ix0, cols)
    for r in range(rows):
        gy = iy0 + r
        sy = raster_y0 + gy
        row = base[r]
        if use_static:
            row[:cols] = _LETHAL
            if 0 <= sy < raster_h and static_c0 < static_c1:
                row[static_c0:static_c1] = raster[sy, rx0 + static_c0 : rx0 + static_c1]
        else:
            row[:cols] = _FREE
        if use_obstacle and 0 <= gy < height and obstacle_c0 < obstacle_c1:
            cells = obstacle[gy, ix0 + obstacle_c0 : ix0 + obstacle_c1]
            for c in range(obstacle_c1 - obstacle_c0):
                row[obstacle_c0 + c] = max(row[obstacle_c0 + c], cells[c])
        lethal_gap = gap[r]
        for c in range(cols):
            lethal_gap[c] = 0 if row[c] == _LETHAL else cap
    _inflate_rows(
        gap, rows, cols, reach, margin, rows - margin, margin, cols - margin, table, costs
    )
    for i in range(y1 - y0):
        values = base[margin + i, margin : margin + x1 - x0]
        inflated = costs[i]
        out = master[y0 + i, x0:x1]
        for j in range(x1 - x0):
            value, cost = values[j], inflated[j]
            if value == _UNKNOWN:
                out[j] = cost if cost >= _INSCRIBED else _UNKNOWN
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
    dix: int,
    diy: int,
    raster: np.ndarray,
    raster_x0: int,
    raster_y0: int,
    use_static: bool,
    bounds: np.ndarray,
) -> bool:  # pragma: no cover - compiled
    """Bounds of the obstacle cells a window move by ``(dix, diy)`` drops that raised a cell.

    A dropped cell matters when it made its combined cell (static max obstacle) larger than
    the static cell alone. ``raster_x0, raster_y0`` is the window's lattice offset in the
    static raster before the move. Bounds ``(ix0, iy0, ix1, iy1)`` go to ``bounds`` in the
    window's cells before the move; returns whether there are any.
    """
    height, width = obstacle.shape
    raster_h, raster_w = raster.shape
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
                if value == _FREE:
                    continue
                static = _FREE
                if use_static:
                    sx, sy = raster_x0 + ix, raster_y0 + iy
                    inside = 0 <= sx < raster_w and 0 <= sy < raster_h
                    static = raster[sy, sx] if inside else _LETHAL
                if value <= static:
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
def refresh_window_static(
    master: np.ndarray,
    raster: np.ndarray,
    static_costs: np.ndarray,
    raster_x0: int,
    raster_y0: int,
    use_static: bool,
    obstacle: np.ndarray,
    use_obstacle: bool,
    x0: int,
    y0: int,
    x1: int,
    y1: int,
    reach: int,
    table: np.ndarray,
    costs: np.ndarray,
) -> bool:  # pragma: no cover - compiled
    """:func:`refresh_window` from the static layer's own inflation plus the obstacles'.

    ``static_costs`` is the inflation cost of the static raster by itself (lethal beyond the
    raster). With a cost table that never rises with the distance, the cost of the nearest
    lethal cell of the union is the larger of the static cost and the cost of the nearest
    obstacle that makes a free static cell lethal, so only those obstacles are stamped in.
    Returns False, changing nothing, when an obstacle cell above lethal (unknown) lies within
    ``reach`` of the rectangle: it would hide a static lethal cell, so the caller must use
    :func:`refresh_window`. ``costs`` is scratch of at least the rectangle's size.
    """
    height, width = master.shape
    raster_h, raster_w = raster.shape
    last = table.shape[0] - 1
    # The obstacles within reach of the rectangle, checked first: nothing changes on False.
    ox0, oy0 = max(x0 - reach, 0), max(y0 - reach, 0)
    ox1, oy1 = min(x1 + reach, width), min(y1 + reach, height)
    if use_obstacle:
        for oy in range(oy0, oy1):
            for ox in range(ox0, ox1):
                if obstacle[oy, ox] > _LETHAL:
                    return False
    for i in range(y1 - y0):
        sy = raster_y0 + y0 + i
        inside_y = 0 <= sy < raster_h
        row = costs[i]
        for j in range(x1 - x0):
            sx = raster_x0 + x0 + j
            if not use_static:
                row[j] = _FREE
            elif inside_y and 0 <= sx < raster_w:
                row[j] = static_costs[sy, sx]
            else:
                row[j] = table[0]
    if use_obstacle:
        for oy in range(oy0, oy1):
            for ox in range(ox0, ox1):
                value = obstacle[oy, ox]
                if value != _LETHAL:
                    continue
                static = _FREE
                if use_static:
                    sx, sy = raster_x0 + ox, raster_y0 + oy
                    inside = 0 <= sx < raster_w and 0 <= sy < raster_h
                    static = raster[sy, sx] if inside else _LETHAL
                if static >= _LETHAL:
                    continue  # already lethal in the static costs, or hidden by unknown
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
            value = _FREE
            if use_static:
                sx = raster_x0 + gx
                value = raster[sy, sx] if inside_y and 0 <= sx < raster_w else _LETHAL
            if use_obstacle:
                value = max(value, obstacle[gy, gx])
            cost = row[j]
            if value == _UNKNOWN:
                out[gx] = cost if cost >= _INSCRIBED else _UNKNOWN
            else:
                out[gx] = max(value, cost)
    return True
