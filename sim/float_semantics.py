"""Python's and NumPy's own float results, reproduced in numba-compiled code.

A kernel that replaces Python code keeps its results bit for bit only if it does the same
float operations. Where Python or NumPy do not do what the obvious compiled code does, these
functions do what they do:

- :func:`python_hypot`: CPython's ``math.hypot`` (its own correctly rounded algorithm, not
  the C library's ``hypot``);
- :func:`pairwise_sum`: ``numpy.sum``'s pairwise summation with eight accumulators;
- :func:`py_max`, :func:`py_min`: the builtins' choice between equal values (the first
  argument wins a tie, which keeps the sign of a zero).
"""

from __future__ import annotations

import math

import numba
import numpy as np

_SPLIT = 134217729.0  # 2**27 + 1: Dekker's split of a double into two halves
_DBL_MIN = 2.2250738585072014e-308


@numba.njit(cache=True, nogil=True)
def _norm_scaled(ax: float, ay: float, biggest: float) -> float:  # pragma: no cover - compiled
    """CPython's ``vector_norm`` for two non-negative finite values, ``biggest`` > 0 normal."""
    max_e = math.frexp(biggest)[1]
    scale = math.ldexp(1.0, -max_e)
    csum, frac1, frac2, frac3 = 1.0, 0.0, 0.0, 0.0
    for value in (ax, ay):
        x = value * scale
        t = x * _SPLIT
        hi = t - (t - x)
        lo = x - hi
        x = hi * hi
        oldcsum = csum
        csum += x
        frac1 += (oldcsum - csum) + x
        x = 2.0 * hi * lo
        oldcsum = csum
        csum += x
        frac2 += (oldcsum - csum) + x
        frac3 += lo * lo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2 + frac3))
    x = h
    t = x * _SPLIT
    hi = t - (t - x)
    lo = x - hi
    x = -hi * hi
    oldcsum = csum
    csum += x
    frac1 += (oldcsum - csum) + x
    x = -2.0 * hi * lo
    oldcsum = csum
    csum += x
    frac2 += (oldcsum - csum) + x
    x = -lo * lo
    oldcsum = csum
    csum += x
    frac3 += (oldcsum - csum) + x
    x = csum - 1.0 + (frac1 + frac2 + frac3)
    return (h + x / (2.0 * h)) / scale


@numba.njit(cache=True, nogil=True)
def python_hypot(x: float, y: float) -> float:  # pragma: no cover - compiled
    """``math.hypot(x, y)`` exactly as CPython 3.11 computes it."""
    ax, ay = abs(x), abs(y)
    biggest = 0.0
    if ax > biggest:
        biggest = ax
    if ay > biggest:
        biggest = ay
    if math.isinf(biggest):
        return biggest
    if math.isnan(ax) or math.isnan(ay):
        return math.nan
    if biggest == 0.0:
        return biggest
    if math.frexp(biggest)[1] < -1023:
        # Subnormal: CPython scales up by DBL_MIN first.
        return _DBL_MIN * _norm_scaled(ax / _DBL_MIN, ay / _DBL_MIN, biggest / _DBL_MIN)
    return _norm_scaled(ax, ay, biggest)


@numba.njit(cache=True, nogil=True)
def _block_sum(values: np.ndarray, start: int, n: int) -> float:  # pragma: no cover - compiled
    """numpy's pairwise sum of at most 128 values: eight accumulators, then the rest."""
    if n < 8:
        total = -0.0
        for i in range(start, start + n):
            total += values[i]
        return total
    r0, r1, r2, r3 = values[start], values[start + 1], values[start + 2], values[start + 3]
    r4, r5, r6, r7 = values[start + 4], values[start + 5], values[start + 6], values[start + 7]
    i = 8
    while i < n - (n % 8):
        j = start + i
        r0 += values[j]
        r1 += values[j + 1]
        r2 += values[j + 2]
        r3 += values[j + 3]
        r4 += values[j + 4]
        r5 += values[j + 5]
        r6 += values[j + 6]
        r7 += values[j + 7]
        i += 8
    total = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        total += values[start + i]
        i += 1
    return total


@numba.njit(cache=True, nogil=True)
def pairwise_sum(values: np.ndarray, start: int, n: int) -> float:  # pragma: no cover - compiled
    """``numpy.sum`` of ``values[start:start + n]`` (contiguous float64), same rounding.

    numpy splits more than 128 values in two halves (the first a multiple of 8 long) and
    adds the halves' sums; the recursion runs here on an explicit stack (numba's cache
    cannot load recursive functions).
    """
    if n <= 128:
        return _block_sum(values, start, n)
    starts = np.empty(128, np.int64)
    sizes = np.empty(128, np.int64)
    combine = np.empty(128, np.bool_)
    sums = np.empty(128)
    top, done = 0, 0
    starts[0], sizes[0], combine[0] = start, n, False
    while top >= 0:
        first, size, join = starts[top], sizes[top], combine[top]
        top -= 1
        if join:
            done -= 1
            sums[done - 1] = sums[done - 1] + sums[done]
        elif size <= 128:
            sums[done] = _block_sum(values, first, size)
            done += 1
        else:
            half = size // 2
            half -= half % 8
            # Pushed in reverse: the first half is summed first, then the second, then both.
            starts[top + 1], sizes[top + 1], combine[top + 1] = first, size, True
            starts[top + 2], sizes[top + 2], combine[top + 2] = first + half, size - half, False
            starts[top + 3], sizes[top + 3], combine[top + 3] = first, half, False
            top += 3
    return sums[0]


@numba.njit(cache=True, nogil=True, inline="always")
def py_max(a: float, b: float) -> float:  # pragma: no cover - compiled
    """Python's ``max(a, b)``: ``a`` unless ``b`` is strictly larger."""
    return b if b > a else a


@numba.njit(cache=True, nogil=True, inline="always")
def py_min(a: float, b: float) -> float:  # pragma: no cover - compiled
    """Python's ``min(a, b)``: ``a`` unless ``b`` is strictly smaller."""
    return b if b < a else a
