"""Compiled (numba) lidar ray tracing of the costmap's obstacle layer.

The kernels do the same float operations, in the same order, as the straightforward formula
they replace, so their results are bit for bit that formula's: :func:`trace_scan` tests
whether a ray sample lies in a cell with precomputed cell thresholds
(:func:`cell_thresholds`): ``floor(u / resolution) == n`` holds exactly when
``thresholds[n] <= u < thresholds[n + 1]``. Clearing only changes cells that are not free, so
only those (a few dozen, near walls and obstacles) are tested, each against the few beams
whose direction meets it, instead of walking every sample of every beam.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from baobab.nav.costmap import FREE_SPACE, LETHAL_OBSTACLE


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


@numba.njit(cache=True, nogil=True, inline="always")
def include_cell(bounds: np.ndarray, ix: int, iy: int, first: bool) -> None:  # pragma: no cover
    """Grow the cell rectangle ``bounds`` (x0, y0, x1, y1; end exclusive) to hold cell
    (``ix``, ``iy``); the ``first`` cell starts it."""
    if first:
        bounds[0], bounds[1], bounds[2], bounds[3] = ix, iy, ix + 1, iy + 1
    else:
        bounds[0] = min(bounds[0], ix)
        bounds[1] = min(bounds[1], iy)
        bounds[2] = max(bounds[2], ix + 1)
        bounds[3] = max(bounds[3], iy + 1)


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
            if old != LETHAL_OBSTACLE:
                if touched[iy, ix] == 0:
                    touched[iy, ix] = 1
                    changed_index[n] = iy * width + ix
                    changed_old[n] = old
                    n += 1
                data[iy, ix] = LETHAL_OBSTACLE
    kept = 0
    for e in range(n):
        index = changed_index[e]
        iy, ix = index // width, index % width
        touched[iy, ix] = 0
        if data[iy, ix] == changed_old[e]:
            continue
        changed_index[kept] = index
        changed_old[kept] = changed_old[e]
        include_cell(bounds, ix, iy, kept == 0)
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
            if old == FREE_SPACE:
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
                data[iy, ix] = FREE_SPACE
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
