"""A planned path: map-frame poses (x, y, yaw) in metres and radians."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from baobab.sim.world import Pose2D


@dataclass(frozen=True, eq=False)
class Path:
    """A sequence of map-frame poses, shaped like ``nav_msgs/Path`` without the stamps.

    Attributes:
        poses: ``(N, 3)`` float array of ``x`` (m), ``y`` (m), ``yaw`` (rad).
        frame_id: the frame the poses are in.
    """

    poses: np.ndarray
    frame_id: str = "map"

    def __post_init__(self) -> None:
        poses = np.array(self.poses, dtype=float, copy=True).reshape(-1, 3)
        if not np.all(np.isfinite(poses)):
            raise ValueError("path poses must be finite")
        poses.setflags(write=False)
        object.__setattr__(self, "poses", poses)

    @classmethod
    def from_points(cls, points: np.ndarray, final_yaw: float, frame_id: str = "map") -> Path:
        """A path through ``(N, 2)`` points, each pose facing the next, the last one ``final_yaw``.

        This is Nav2's orientation rule for grid planners: every pose looks along the segment
        that leaves it; the last pose takes the goal's yaw.
        """
        xy = np.asarray(points, dtype=float).reshape(-1, 2)
        yaws = np.full(len(xy), float(final_yaw))
        if len(xy) > 1:
            step = np.diff(xy, axis=0)
            yaws[:-1] = np.arctan2(step[:, 1], step[:, 0])
        return cls(np.column_stack([xy, yaws]), frame_id)

    def __len__(self) -> int:
        return int(self.poses.shape[0])

    @property
    def xy(self) -> np.ndarray:
        """``(N, 2)`` positions (m)."""
        return self.poses[:, :2]

    @property
    def yaws(self) -> np.ndarray:
        """``(N,)`` headings (rad)."""
        return self.poses[:, 2]

    @cached_property
    def cumulative_lengths(self) -> np.ndarray:
        """``(N,)`` length (m) of the polyline from the first pose to each pose (read-only).

        Computed once per path: the poses cannot change.
        """
        steps = np.hypot(*np.diff(self.xy, axis=0).T) if len(self) > 1 else np.zeros(0)
        lengths = np.concatenate([[0.0], np.cumsum(steps)])
        lengths.setflags(write=False)
        return lengths

    def pose(self, index: int) -> Pose2D:
        """Pose ``index`` (negative counts from the end)."""
        x, y, yaw = self.poses[index]
        return Pose2D(x=float(x), y=float(y), yaw=float(yaw))

    @cached_property
    def goal(self) -> Pose2D:
        """The last pose (made once: the poses cannot change)."""
        return self.pose(-1)

    def length(self, start_index: int = 0) -> float:
        """Length (m) of the polyline from pose ``start_index`` to the end."""
        if len(self) - start_index < 2:
            return 0.0
        steps = np.diff(self.xy[start_index:], axis=0)
        return float(np.hypot(steps[:, 0], steps[:, 1]).sum())

    def closest_index(self, x: float, y: float, start_index: int = 0) -> int:
        """Index of the pose nearest to ``(x, y)`` among poses ``start_index`` onwards."""
        rest = self.xy[start_index:]
        return start_index + int(np.argmin(np.hypot(rest[:, 0] - x, rest[:, 1] - y)))

    def __repr__(self) -> str:
        if len(self) == 0:
            return "Path(empty)"
        (x0, y0, _), (x1, y1, _) = self.poses[0], self.poses[-1]
        return (
            f"Path({len(self)} poses, {self.length():.2f} m, "
            f"({x0:.2f}, {y0:.2f}) -> ({x1:.2f}, {y1:.2f}))"
        )


def wrap_angle(angle: float) -> float:
    """``angle`` (rad) wrapped to ``[-pi, pi)``."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


def wrap_angles(angles: np.ndarray) -> np.ndarray:
    """Vectorised :func:`wrap_angle`."""
    return np.mod(np.asarray(angles, dtype=float) + np.pi, 2 * np.pi) - np.pi
