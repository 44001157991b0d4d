"""Navigator feedback: distance remaining along the path, smoothed speed, time remaining.

Nav2's BT navigators fill NavigateToPose / NavigateThroughPoses feedback on every loop
(reference/nav2.md §2.2): ``distance_remaining`` is the length of the current global path from
the pose closest to the robot (searched within a window ahead of the last closest pose), and
``estimated_time_remaining`` is that distance over the odometry speed averaged over
``filter_duration``, or 0 when the robot barely moves or is almost there.
"""

from __future__ import annotations

from collections import deque

import numpy as np

from baobab.nav.path import Path


class PathProgress:
    """Where the robot is along a path, found incrementally.

    Args:
        search_window: how far along the path (m) past the last closest pose to look.
    """

    def __init__(self, search_window: float = 2.0) -> None:
        self.search_window = search_window
        self._path: Path | None = None
        self._lengths = np.zeros(1)
        self.closest_index = 0

    def distance_remaining(self, path: Path, x: float, y: float) -> float:
        """Path length (m) from the pose of ``path`` closest to ``(x, y)`` to its end."""
        if path is not self._path:
            self._path = path
            self._lengths = path.cumulative_lengths
            self.closest_index = 0
        if len(path) == 0:
            return 0.0
        begin = self.closest_index
        end = int(
            np.searchsorted(self._lengths, self._lengths[begin] + self.search_window, "right")
        )
        window = path.xy[begin : max(end, begin + 1)]
        offsets = window - (x, y)
        self.closest_index = begin + int(np.argmin(np.einsum("ij,ij->i", offsets, offsets)))
        return float(self._lengths[-1] - self._lengths[self.closest_index])


class SpeedFilter:
    """Moving average of the forward speed over the last ``filter_duration`` seconds (sim time)."""

    def __init__(self, filter_duration: float = 0.3) -> None:
        self.filter_duration = filter_duration
        self._samples: deque[tuple[float, float]] = deque()

    def add(self, now: float, speed: float) -> float:
        """Add a sample at sim time ``now`` (s) and return the average speed (m/s)."""
        samples = self._samples
        samples.append((now, speed))
        while samples and samples[0][0] < now - self.filter_duration - 1e-9:
            samples.popleft()
        return sum(value for _, value in samples) / len(samples)

    def reset(self) -> None:
        """Forget the samples."""
        self._samples.clear()


def estimated_time_remaining(distance: float, speed: float) -> float:
    """Nav2's ETA (s): ``distance / |speed|`` when moving (> 0.01 m/s) and not there (> 0.1 m)."""
    if abs(speed) > 0.01 and distance > 0.1:
        return distance / abs(speed)
    return 0.0
