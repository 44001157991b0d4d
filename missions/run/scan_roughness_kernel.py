"""How rough a lidar scan is, compiled: the fault monitors' test for range noise (numba).

:func:`rough_pairs` counts the pairs of neighbouring beams that both have a return, and of
those the pairs whose ranges differ by more than a step. Walls, furniture and edges make few
rough pairs; range noise of about 0.1 m and more makes most pairs rough
(:mod:`baobab.missions.run.fault_monitors`, ``SENSOR_DEGRADED``). One compiled pass over the
beams replaces eight NumPy calls per scan; ``tests/test_scan_roughness_kernel.py`` compares it
with them.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(cache=True, nogil=True)
def rough_pairs(ranges: np.ndarray, rough_step: float) -> tuple[int, int]:  # pragma: no cover
    """``(pairs, rough)``: neighbouring beams of ``ranges`` (m; inf or NaN: no return) that
    both have a return, and of those the ones more than ``rough_step`` (m) apart."""
    pairs = 0
    rough = 0
    for index in range(1, ranges.shape[0]):
        before, after = ranges[index - 1], ranges[index]
        if math.isfinite(before) and math.isfinite(after):
            pairs += 1
            if abs(after - before) > rough_step:
                rough += 1
    return pairs, rough
