"""Navigator feedback: distance remaining, smoothed speed, time remaining, tracking errors.

Nav2's BT navigators fill NavigateToPose / NavigateThroughPoses feedback on every loop
(reference/nav2.md §2.2): ``distance_remaining`` is the length of the current global path from
the pose closest to the robot (searched within a window ahead of the last closest pose), and
``estimated_time_remaining`` is that distance over the odometry speed averaged over
``filter_duration``, or 0 when the robot barely moves or is almost there. The controller's
``TrackingFeedback`` (:func:`path_tracking`) says how far the robot is off its path; the
controller's compiled cycle computes it (:mod:`baobab.nav.tracking_kernel`, tested against this)
and hands its fields on as a :class:`ControllerTracking`, put together when read.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from baobab.nav.path import Path, wrap_angle
from baobab.sim.world import Pose2D


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


class TrackingErrors(Protocol):
    """Where a controller cycle found the robot against its path (the compiled cycle's
    :class:`~baobab.nav.rpp_kernel.PursuitStep` has these fields)."""

    @property
    def position_error(self) -> float:
        """Signed distance (m) off the path, as :attr:`PathTracking.position_error`."""
        ...

    @property
    def heading_error(self) -> float:
        """rad, as :attr:`PathTracking.heading_error`."""
        ...

    @property
    def tracking_index(self) -> int:
        """The segment, as :attr:`PathTracking.index`."""
        ...


class ControllerTracking(Mapping[str, Any]):
    """Nav2's ``TrackingFeedback`` fields of one controller cycle (m, rad, m/s), read only.

    Built every cycle from what the cycle found, but the fields (a dict) are put together
    only when first read: the controller runs at 20 Hz, its feedback is read far less often.
    The inputs are immutable, so the fields are the ones the cycle would have written.

    Args:
        errors: the cycle's tracking errors.
        pose: the robot's pose the cycle used.
        goal: the path's last pose.
        speed: the robot's forward speed (m/s) the cycle used.
        remaining: path length (m) left from the pose closest to the robot.
    """

    __slots__ = ("_errors", "_fields", "_goal", "_pose", "_remaining", "_speed")

    def __init__(
        self, errors: TrackingErrors, pose: Pose2D, goal: Pose2D, speed: float, remaining: float
    ) -> None:
        self._errors, self._pose, self._goal = errors, pose, goal
        self._speed, self._remaining = speed, remaining
        self._fields: dict[str, Any] | None = None

    def _values(self) -> dict[str, Any]:
        fields = self._fields
        if fields is None:
            errors, pose, goal = self._errors, self._pose, self._goal
            fields = self._fields = {
                "position_tracking_error": errors.position_error,
                "heading_tracking_error": errors.heading_error,
                "current_path_index": errors.tracking_index,
                "robot_pose": pose,
                "distance_to_goal": math.hypot(goal.x - pose.x, goal.y - pose.y),
                "speed": self._speed,
                "remaining_path_length": self._remaining,
            }
        return fields

    def __getitem__(self, key: str) -> Any:
        return self._values()[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values())

    def __len__(self) -> int:
        return len(self._values())

    def __repr__(self) -> str:
        return f"ControllerTracking({self._values()!r})"


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
