"""The compiled scan roughness against the NumPy code it replaced in the fault monitors."""

from __future__ import annotations

import numpy as np

from baobab.missions.run.scan_roughness_kernel import rough_pairs


def _numpy_reference(ranges: np.ndarray, rough_step: float) -> tuple[int, int]:
    """The fault monitors' NumPy version (before issue 28): pairs with two returns, rough ones."""
    finite = np.isfinite(ranges)
    pairs = np.logical_and(finite[1:], finite[:-1])
    differences = np.zeros(len(ranges) - 1)
    np.subtract(ranges[1:], ranges[:-1], out=differences, where=pairs)
    rough = np.greater(np.abs(differences), rough_step)
    return int(np.count_nonzero(pairs)), int(np.count_nonzero(rough))


def test_the_kernel_counts_what_numpy_counted() -> None:
    rng = np.random.default_rng(28)
    for trial in range(300):
        beams = int(rng.integers(2, 400))
        ranges = rng.uniform(0.12, 3.5, beams) + rng.normal(0, [0.0, 0.02, 0.2][trial % 3], beams)
        ranges[rng.random(beams) < 0.2] = np.inf
        ranges[rng.random(beams) < 0.02] = np.nan
        step = float(rng.choice([0.05, 0.1, 0.3]))
        assert rough_pairs(ranges, step) == _numpy_reference(ranges, step)


def test_a_noisy_scan_is_rough_and_a_wall_is_not() -> None:
    angles = np.linspace(-np.pi / 4, np.pi / 4, 91)
    wall = 1.0 / np.cos(angles)  # a flat wall 1 m ahead
    assert rough_pairs(wall, 0.1) == (90, 0)
    noisy = wall + np.random.default_rng(1).normal(0, 0.3, 91)
    pairs, rough = rough_pairs(noisy, 0.1)
    assert pairs == 90 and rough > 60
