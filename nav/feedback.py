"""Navigator feedback: distance remaining, smoothed speed, time remaining, tracking errors.

Nav2's BT navigators fill NavigateToPose / NavigateThroughPoses feedback on every loop
(reference/nav2.md §2.2): ``distance_remaining`` is the length of the current global path from
the pose closest to the robot (searched within a window ahead of the last closest pose), and
``estimated_time_remaining`` is that distance over the odometry speed averaged over
``filter_duration``, or 0 when the robot barely moves or is almost there. The controller's
``TrackingFeedback`` (:func:`path_tracking`) says how far the robot is off its path; the
controller's compiled cycle computes it (:mod:`baobab.nav.tracking_kernel`, tested against this).
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from baobab.nav.path import Path, wrap_angle


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
    """Moving average of the forward speed over the last ``filter_duration`` seconds (sim time).

    The samples' times and speeds are kept apart, so the average is one ``sum`` over floats
    (the samples added oldest first, as always).
    """

    def __init__(self, filter_duration: float = 0.3) -> None:
        self.filter_duration = filter_duration
        self._times: deque[float] = deque()
        self._speeds: deque[float] = deque()

    def add(self, now: float, speed: float) -> float:
        """Add a sample at sim time ``now`` (s) and return the average speed (m/s)."""
        times, speeds = self._times, self._speeds
        times.append(now)
        speeds.append(speed)
        oldest = now - self.filter_duration - 1e-9
        while times and times[0] < oldest:
            times.popleft()
            speeds.popleft()
        return sum(speeds) / len(speeds)

    def reset(self) -> None:
        """Forget the samples."""
        self._times.clear()
        self._speeds.clear()


def estimated_time_remaining(distance: float, speed: float) -> float:
    """Nav2's ETA (s): ``distance / |speed|`` when moving (> 0.01 m/s) and not there (> 0.1 m)."""
    if abs(speed) > 0.01 and distance > 0.1:
        return distance / abs(speed)
    return 0.0


@dataclass(frozen=True)
class PathTracking:
    """How the robot sits against the path segment nearest to it.

    Attributes:
        position_error: signed distance (m) from the segment's line; positive with the robot
            to the left of the path.
        heading_error: the path's direction minus the robot's heading (rad, wrapped);
            positive with the robot rotated right (clockwise) of the path.
        index: the index of the segment's first pose.
    """

    position_error: float
    heading_error: float
    index: int


def path_tracking(path: Path, closest: int, x: float, y: float, yaw: float) -> PathTracking:
    """Nav2's tracking errors of the robot at ``(x, y, yaw)`` (m, rad) against ``path``.

    Of the segments before and after pose ``closest`` (the pose nearest to the robot), the one
    nearer to the robot is used; a one-pose path counts as a segment along that pose's yaw.
    """
    count = len(path)
    if count == 0:
        return PathTracking(0.0, 0.0, 0)
    closest = min(max(closest, 0), count - 1)
    first = max(closest - 1, 0)
    rows = path.poses[first : closest + 2].tolist()  # the poses around closest, as floats
    best: tuple[float, float, int, float, float] | None = None
    for start in range(first, min(closest, count - 2) + 1):
        (ax, ay, _), (bx, by, _) = rows[start - first], rows[start - first + 1]
        dx, dy = bx - ax, by - ay
        length = math.hypot(dx, dy)
        if length < 1e-9:
            continue
        along = min(max(((x - ax) * dx + (y - ay) * dy) / length, 0.0), length)
        gap = math.hypot(x - (ax + dx * along / length), y - (ay + dy * along / length))
        if best is None or gap < best[0]:
            cross = (dx * (y - ay) - dy * (x - ax)) / length
            best = (gap, cross, start, dx, dy)
    if best is None:
        ax, ay, heading = rows[closest - first]
        cross = math.cos(heading) * (y - ay) - math.sin(heading) * (x - ax)
        return PathTracking(cross, wrap_angle(heading - yaw), closest)
    _, cross, start, dx, dy = best
    return PathTracking(cross, wrap_angle(math.atan2(dy, dx) - yaw), start)
