"""Compiled (numba) lidar ray tracing of the costmap's obstacle layer.

Compiled because the straightforward formula samples every beam every half cell: for a
360-beam scan and a 3 m clearing range that is 43,000 samples, each divided into a cell index,
per scan and costmap. :func:`trace_scan` gives the same cells with far less work: clearing
only changes cells that are not free, so only those (a few dozen, near walls and obstacles)
are tested, each against the few beams whose direction meets it. Whether a ray sample lies in
a cell is decided with precomputed cell thresholds (:func:`cell_thresholds`):
``floor(u / resolution) == n`` holds exactly when ``thresholds[n] <= u < thresholds[n + 1]``,
so the result is the formula's cell for cell. The tests compare the two on random scans
(``tests/test_costmap_kernels.py``).

The kernel reads named records (:mod:`baobab.sim.records`): the grid's geometry
(:data:`~baobab.nav.costmap.GRID`), the scan (:data:`~baobab.sim.lidar.SCAN`), the layer's
ranges (:data:`OBSTACLE_RANGES`), and the layer's tables and scratch (:class:`RayTracer`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np

from baobab.nav.costmap import FREE_SPACE, LETHAL_OBSTACLE
from baobab.sim.records import Record

OBSTACLE_RANGES = np.dtype(
    [
        ("obstacle_max_range", np.float64),  # hits nearer than this mark their cell (m)
        ("obstacle_min_range", np.float64),  # and not nearer than this (m)
        ("raytrace_max_range", np.float64),  # beams clear up to here at most (m)
        ("raytrace_min_range", np.float64),  # and from here on (m)
    ]
)
"""The obstacle layer's ranges, one field per :class:`~baobab.nav.layers.ObstacleParams` field."""

_BEAM = np.dtype(
    [
        ("heading", np.float64),  # map frame (rad)
        ("cos", np.float64),  # of the heading
        ("sin", np.float64),
        ("reach", np.int64),  # samples it clears: those below its clearing length
        ("end_x", np.int64),  # its hit cell; -1 / size for any cell before / after the grid
        ("end_y", np.int64),
    ]
)
"""One beam of a scan, as :func:`trace_scan` works with it."""


class RayTracer(NamedTuple):
    """An obstacle layer's tables and scratch for :func:`trace_scan`, and its report of changes."""

    threshold_x: np.ndarray
    """:func:`cell_thresholds` of the grid's columns."""
    threshold_y: np.ndarray
    """:func:`cell_thresholds` of its rows."""
    samples: np.ndarray
    """Distances (m) from the sensor at which a beam is sampled, up to the longest clearing
    length: ``numpy.arange(max(raytrace_min_range, 0), raytrace_max_range, resolution / 2)``."""
    touched: np.ndarray
    """``uint8`` shaped like the cells, zero between calls."""
    changed_index: np.ndarray
    """Out: ``iy * width + ix`` of each changed cell (``int64``, one slot per cell)."""
    changed_old: np.ndarray
    """Out: the old value of each changed cell (``uint8``, one slot per cell)."""
    bounds: np.ndarray
    """Out: the changed cells' bounds ``(ix0, iy0, ix1, iy1)``, end exclusive (``int64``)."""


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
    cells: np.ndarray,
    grid: np.ndarray,
    scan: np.ndarray,
    ranges: np.ndarray,
    obstacle_ranges: np.ndarray,
    tracer: RayTracer,
) -> int:  # pragma: no cover - compiled
    """Clear every beam's cells up to its clearing length (its hit cell excluded), mark the hits.

    A beam is valid when its range is not NaN and at least ``max(range_min, 0)``; a valid
    finite range is a hit, which clears up to ``min(range, raytrace_max_range)`` and marks its
    cell lethal when ``obstacle_min_range <= range < obstacle_max_range``; a valid infinite
    range clears up to ``raytrace_max_range``. Beam ``b`` points along ``heading = yaw +
    (angle_min + b * angle_increment)``; it clears the grid cells of its samples
    ``x + cos(heading) * t``, ``y + sin(heading) * t`` for ``t`` in ``tracer.samples`` below its
    own clearing length.

    Args:
        cells: the layer's ``uint8`` cells ``[iy, ix]``, updated in place.
        grid: the layer's :data:`~baobab.nav.costmap.GRID` record.
        scan: a :data:`~baobab.sim.lidar.SCAN` record.
        ranges: the scan's ranges (m), one per beam.
        obstacle_ranges: an :data:`OBSTACLE_RANGES` record.
        tracer: the layer's :class:`RayTracer`; receives the changed cells.

    Returns:
        ``n``, the number of cells whose value changed: ``tracer.changed_index[:n]`` and
        ``tracer.changed_old[:n]``, their bounds in ``tracer.bounds``. A cell cleared by one
        beam and marked again by another keeps its value: not a change.
    """
    g, sc, o = grid[0], scan[0], obstacle_ranges[0]
    height, width = cells.shape
    samples = tracer.samples
    range_min = max(sc.range_min, 0.0)
    start, step = max(o.raytrace_min_range, 0.0), g.resolution / 2
    beams = np.empty(ranges.shape[0], dtype=_BEAM)
    clear_to = np.empty(ranges.shape[0], dtype=np.float64)
    longest = 0.0
    for b in range(ranges.shape[0]):
        r = ranges[b]
        if np.isnan(r) or not r >= range_min:
            clear_to[b] = 0.0
        elif np.isfinite(r):
            clear_to[b] = min(r, o.raytrace_max_range)
        else:
            clear_to[b] = o.raytrace_max_range
        longest = max(longest, clear_to[b])
    # numpy.arange's length: ceil((stop - start) / step), none when not positive.
    span = (longest - start) / step
    count = min(max(math.ceil(span), 0), samples.shape[0]) if span > 0 else 0
    per_cell = 1.0 / g.resolution
    for b in range(ranges.shape[0]):
        beam = beams[b]
        beam.heading = sc.yaw + (sc.angle_min + sc.angle_increment * b)
        beam.cos, beam.sin = math.cos(beam.heading), math.sin(beam.heading)
        beam.reach = _samples_below(samples, count, clear_to[b], start, step)
        beam.end_x, beam.end_y = -1, -1
        r = ranges[b]
        if np.isfinite(r) and r >= range_min:
            beam.end_x = _cell_of(sc.x + beam.cos * r - g.origin_x, per_cell, tracer.threshold_x)
            beam.end_y = _cell_of(sc.y + beam.sin * r - g.origin_y, per_cell, tracer.threshold_y)
    n = 0
    if count > 0:
        n = _clear_cells(cells, g, sc, beams, tracer, (start, step, samples[count - 1]))
    changed_index, changed_old = tracer.changed_index, tracer.changed_old
    for b in range(ranges.shape[0]):
        r = ranges[b]
        if not (np.isfinite(r) and r >= range_min):
            continue
        if not (o.obstacle_min_range <= r < o.obstacle_max_range):
            continue
        ix, iy = beams[b].end_x, beams[b].end_y
        if 0 <= ix < width and 0 <= iy < height:
            old = cells[iy, ix]
            if old != LETHAL_OBSTACLE:
                if tracer.touched[iy, ix] == 0:
                    tracer.touched[iy, ix] = 1
                    changed_index[n] = iy * width + ix
                    changed_old[n] = old
                    n += 1
                cells[iy, ix] = LETHAL_OBSTACLE
    kept = 0
    for e in range(n):
        index = changed_index[e]
        iy, ix = index // width, index % width
        tracer.touched[iy, ix] = 0
        if cells[iy, ix] == changed_old[e]:
            continue
        changed_index[kept] = index
        changed_old[kept] = changed_old[e]
        include_cell(tracer.bounds, ix, iy, kept == 0)
        kept += 1
    return kept


@numba.njit(cache=True, nogil=True, inline="always")
def _samples_below(
    samples: np.ndarray, count: int, limit: float, start: float, step: float
) -> int:  # pragma: no cover - compiled
    """How many of the first ``count`` samples lie below ``limit`` (m)."""
    k = 0
    if limit > start:
        k = min(int((limit - start) / step), count)
    while k < count and samples[k] < limit:
        k += 1
    while k > 0 and not samples[k - 1] < limit:
        k -= 1
    return k


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
    cells: np.ndarray,
    g: Record,
    sc: Record,
    beams: np.ndarray,
    tracer: RayTracer,
    sampling: tuple[float, float, float],
) -> int:  # pragma: no cover - compiled
    """Free every non-free cell that a sample of some beam falls in (see :func:`trace_scan`).

    ``sampling`` is the first sample, the step between samples and the farthest sample
    taken (m). Returns how many cells it recorded in ``tracer.changed_index`` /
    ``tracer.changed_old``.
    """
    height, width = cells.shape
    farthest = sampling[2]
    threshold_x, threshold_y = tracer.threshold_x, tracer.threshold_y
    # Beams by direction: angular bins of width about half the beam spacing.
    count = beams.shape[0]
    bins = 2 * count
    per_bin = bins / (2.0 * np.pi)
    first, by_bin = _beams_by_bin(beams, bins)
    # Margins that make every test below a superset of the exact sample test: the float
    # sample points lie within ~1e-13 m of the ideal ray, far inside these.
    eps = 1e-9 + 1e-12 * (abs(sc.x) + abs(sc.y) + abs(g.origin_x) + abs(g.origin_y) + farthest)
    half_diagonal = 0.5 * g.resolution * math.sqrt(2.0) + 2.0 * eps
    sensor_u = sc.x - g.origin_x
    sensor_v = sc.y - g.origin_y
    # Every sample lies within ``farthest`` of the sensor.
    ix0 = max(int(np.floor((sensor_u - farthest) / g.resolution)) - 1, 0)
    iy0 = max(int(np.floor((sensor_v - farthest) / g.resolution)) - 1, 0)
    ix1 = min(int(np.floor((sensor_u + farthest) / g.resolution)) + 2, width)
    iy1 = min(int(np.floor((sensor_v + farthest) / g.resolution)) + 2, height)
    n = 0
    for iy in range(iy0, iy1):
        for ix in range(ix0, ix1):
            old = cells[iy, ix]
            if old == FREE_SPACE:
                continue
            exact = (threshold_x[ix], threshold_x[ix + 1], threshold_y[iy], threshold_y[iy + 1])
            box = (exact[0] - eps, exact[1] + eps, exact[2] - eps, exact[3] + eps)
            dx = 0.5 * (box[0] + box[1]) - sensor_u
            dy = 0.5 * (box[2] + box[3]) - sensor_v
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
                    beam = beams[by_bin[e]]
                    if beam.reach == 0 or (ix == beam.end_x and iy == beam.end_y):
                        continue
                    if _sample_in_cell(beam, sc, g, box, exact, tracer.samples, sampling):
                        cleared = True
                        break
                if cleared:
                    break
            if cleared:
                tracer.touched[iy, ix] = 1
                tracer.changed_index[n] = iy * width + ix
                tracer.changed_old[n] = old
                n += 1
                cells[iy, ix] = FREE_SPACE
    return n


@numba.njit(cache=True, nogil=True)
def _beams_by_bin(
    beams: np.ndarray, bins: int
) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - compiled
    """The beams sorted into ``bins`` equal angular bins of their headings.

    Returns ``first`` (bins + 1,) and ``by_bin``: the beams of bin ``k`` are
    ``by_bin[first[k]:first[k + 1]]``. Approximate bins are fine: a cell looks one bin beyond
    its angular extent.
    """
    count = beams.shape[0]
    per_bin = bins / (2.0 * np.pi)
    per_turn = 1.0 / (2.0 * np.pi)
    first = np.zeros(bins + 1, dtype=np.int64)
    beam_bin = np.empty(count, dtype=np.int64)
    for b in range(count):
        heading = beams[b].heading
        angle = heading - 2.0 * np.pi * np.floor(heading * per_turn)
        k = min(max(int(angle * per_bin), 0), bins - 1)
        beam_bin[b] = k
        first[k + 1] += 1
    for k in range(bins):
        first[k + 1] += first[k]
    fill = first[:-1].copy()
    by_bin = np.empty(count, dtype=np.int64)
    for b in range(count):
        by_bin[fill[beam_bin[b]]] = b
        fill[beam_bin[b]] += 1
    return first, by_bin


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
    beam: Record,
    sc: Record,
    g: Record,
    box: tuple[float, float, float, float],
    exact: tuple[float, float, float, float],
    samples: np.ndarray,
    sampling: tuple[float, float, float],
) -> bool:  # pragma: no cover - compiled
    """Whether one of the first ``beam.reach`` samples of a beam falls in a cell.

    ``box`` ``(u0, u1, v0, v1)`` is the cell grown by a margin, to find the samples to test;
    ``exact`` ``[u0, u1) x [v0, v1)`` are its exact thresholds; both relative to the grid's
    origin (m).
    """
    start, step = sampling[0], sampling[1]
    count = beam.reach
    c, s = beam.cos, beam.sin
    tx0, tx1 = _slab(sc.x - g.origin_x, c, box[0], box[1])
    ty0, ty1 = _slab(sc.y - g.origin_y, s, box[2], box[3])
    t0, t1 = max(tx0, ty0), min(tx1, ty1)
    if t0 > t1 or t1 < start:
        return False
    k0 = 0
    if t0 > start:
        k0 = int((t0 - start) / step) - 1
        if k0 >= count:
            return False
        k0 = max(k0, 0)
    k1 = count - 1
    if t1 < samples[k1]:
        k1 = min(int((t1 - start) / step) + 1, count - 1)
    for k in range(k0, k1 + 1):
        t = samples[k]
        u = sc.x + c * t - g.origin_x
        if not (exact[0] <= u < exact[1]):
            continue
        v = sc.y + s * t - g.origin_y
        if exact[2] <= v < exact[3]:
            return True
    return False
