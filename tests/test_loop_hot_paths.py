"""Code on the run loop's 20 Hz path, rewritten for speed, against the code it replaced."""

from __future__ import annotations

import math

import numpy as np

from baobab.nav.feedback import PathTracking, path_tracking
from baobab.nav.path import Path, wrap_angle


def _path_tracking_reference(
    path: Path, closest: int, x: float, y: float, yaw: float
) -> PathTracking:
    """``path_tracking`` as it was before issue 28 (numpy scalars read one by one)."""
    poses = path.poses
    count = len(poses)
    if count == 0:
        return PathTracking(0.0, 0.0, 0)
    closest = min(max(closest, 0), count - 1)
    candidates = [i for i in (closest - 1, closest) if i >= 0 and i + 1 < count]
    best: tuple[float, float, int] | None = None
    for start in candidates:
        ax, ay = float(poses[start, 0]), float(poses[start, 1])
        dx, dy = float(poses[start + 1, 0]) - ax, float(poses[start + 1, 1]) - ay
        length = math.hypot(dx, dy)
        if length < 1e-9:
            continue
        along = min(max(((x - ax) * dx + (y - ay) * dy) / length, 0.0), length)
        gap = math.hypot(x - (ax + dx * along / length), y - (ay + dy * along / length))
        if best is None or gap < best[0]:
            cross = (dx * (y - ay) - dy * (x - ax)) / length
            best = (gap, cross, start)
    if best is None:
        ax, ay, heading = (float(value) for value in poses[closest])
        cross = math.cos(heading) * (y - ay) - math.sin(heading) * (x - ax)
        return PathTracking(cross, wrap_angle(heading - yaw), closest)
    _, cross, start = best
    heading = math.atan2(
        float(poses[start + 1, 1] - poses[start, 1]), float(poses[start + 1, 0] - poses[start, 0])
    )
    return PathTracking(cross, wrap_angle(heading - yaw), start)


def test_path_tracking_equals_the_replaced_code_bit_for_bit() -> None:
    rng = np.random.default_rng(3)
    for trial in range(400):
        count = int(rng.integers(0, 8))
        poses = np.column_stack(
            [rng.uniform(-3, 3, count), rng.uniform(-3, 3, count), rng.uniform(-4, 4, count)]
        )
        if count > 2 and trial % 5 == 0:
            poses[1, :2] = poses[0, :2]  # a zero-length segment
        path = Path(poses)
        closest = int(rng.integers(-2, count + 2))
        x, y, yaw = rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-4, 4)
        assert path_tracking(path, closest, x, y, yaw) == _path_tracking_reference(
            path, closest, x, y, yaw
        )
