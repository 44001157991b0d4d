"""Finding a dock in a lidar scan: the charger's outline fitted to the scan's points.

The detector knows the dock model (:data:`~baobab.sim.docks.DOCK_PARTS`: a back plate and two
side walls, open towards the robot) and where the dock is expected (the database's pose). It
takes the scan's returns near there and looks for the pose of the model that best explains
them, in two stages:

1. a coarse search over poses within :attr:`DetectorParams.search_radius` and
   :attr:`~DetectorParams.search_angle` of the expected one, scoring each by how many points
   lie within :attr:`~DetectorParams.inlier_distance` of the model's outline;
2. a robust least-squares fit (``scipy.optimize.least_squares``, soft-L1 loss) of the
   point-to-outline distances from the best candidate, on the points near it.

A fit counts as a detection when at least :attr:`~DetectorParams.min_inliers` points lie on
the outline, their RMS distance is at most :attr:`~DetectorParams.max_rms` and the pose is
within the search window: the *stated tolerance* is that window, 0.30 m and 0.35 rad by
default. Later scans refine the last detection with the fit alone. Ground truth is never read.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from baobab.sim.docks import visible_faces
from baobab.sim.lidar import LaserScan
from baobab.sim.world import Pose2D

_FACES = np.array(visible_faces())
"""The faces of the model a lidar in front of the dock can see: segments ``(K, 2, 2)`` (m,
dock frame)."""
MODEL_REACH = float(np.max(np.linalg.norm(_FACES, axis=-1)))
"""Distance (m) from the dock pose to the model's farthest point."""


@dataclass(frozen=True)
class DetectorParams:
    """How the dock is looked for and when a fit counts (module docstring)."""

    search_radius: float = 0.30
    """How far (m) the dock may stand from where it is expected."""
    search_angle: float = 0.35
    """How far (rad) its heading may differ."""
    inlier_distance: float = 0.03
    """A point this close (m) to the outline lies on it."""
    min_inliers: int = 8
    """Fewest points on the outline for a detection."""
    max_rms: float = 0.015
    """Largest RMS distance (m) of those points from the outline."""
    coarse_step: tuple[float, float] = (0.05, 0.1)
    """Grid of the coarse search: m and rad."""
    candidates: int = 3
    """How many of the coarse search's best poses are fitted."""


def scan_points(scan: LaserScan) -> np.ndarray:
    """The scan's returns as map-frame points, shape ``(N, 2)`` (m)."""
    valid = np.isfinite(scan.ranges)
    ranges = scan.ranges[valid]
    angles = scan.angles[valid] + scan.sensor_pose.yaw
    return np.column_stack(
        (scan.sensor_pose.x + ranges * np.cos(angles), scan.sensor_pose.y + ranges * np.sin(angles))
    )


def outline_distances(points: np.ndarray, x: float, y: float, yaw: float) -> np.ndarray:
    """Distance (m) from each point ``(N, 2)`` to the visible faces of a dock at ``(x, y, yaw)``."""
    return _distances(points, np.array([[x, y, yaw]]))[0]


def _distances(points: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """Distance (m) from each point ``(N, 2)`` to the faces of a dock at each pose row
    ``(P, 3)`` (x, y, yaw): shape ``(P, N)``."""
    cos, sin = np.cos(poses[:, 2])[:, None], np.sin(poses[:, 2])[:, None]
    dx = points[None, :, 0] - poses[:, 0:1]
    dy = points[None, :, 1] - poses[:, 1:2]
    local = np.stack((cos * dx + sin * dy, -sin * dx + cos * dy), axis=-1)[:, :, None, :]
    start, along = _FACES[:, 0], _FACES[:, 1] - _FACES[:, 0]
    t = np.clip(((local - start) * along).sum(-1) / (along * along).sum(-1), 0.0, 1.0)
    nearest = start + t[..., None] * along
    return np.asarray(np.linalg.norm(local - nearest, axis=-1).min(axis=-1))


class DockDetector:
    """Detects one dock expected at ``expected`` (map frame) in the scans it is given."""

    def __init__(self, expected: Pose2D, params: DetectorParams | None = None) -> None:
        self.expected = expected
        self.params = params or DetectorParams()
        self.last: Pose2D | None = None
        """The latest detection, or None before the first."""

    def detect(self, scan: LaserScan) -> Pose2D | None:
        """The dock's pose in ``scan``, or None when it is not found within the tolerance."""
        p = self.params
        points = scan_points(scan)
        near = points[
            np.hypot(points[:, 0] - self.expected.x, points[:, 1] - self.expected.y)
            < MODEL_REACH + p.search_radius
        ]
        if len(near) < p.min_inliers:
            return None
        starts = [self.last] if self.last is not None else self._coarse(near)
        fits = [fit for fit in (self._refine(near, start) for start in starts) if fit is not None]
        if not fits:
            return None
        pose = max(fits, key=lambda fit: fit[1])[0]
        self.last = pose
        return pose

    def _coarse(self, points: np.ndarray) -> list[Pose2D]:
        p, e = self.params, self.expected
        step_xy, step_yaw = p.coarse_step
        offsets = np.arange(-p.search_radius, p.search_radius + 1e-9, step_xy)
        turns = np.arange(-p.search_angle, p.search_angle + 1e-9, step_yaw)
        gx, gy, gyaw = np.meshgrid(offsets, offsets, turns, indexing="ij")
        inside = np.hypot(gx, gy) <= p.search_radius + 1e-9
        poses = np.column_stack((e.x + gx[inside], e.y + gy[inside], e.yaw + gyaw[inside]))
        scores = np.concatenate(
            [
                (_distances(points, poses[i : i + 256]) < step_xy).sum(axis=1)
                for i in range(0, len(poses), 256)
            ]
        )
        order = np.argsort(-scores, kind="stable")[: p.candidates]
        return [
            Pose2D(x=float(poses[i, 0]), y=float(poses[i, 1]), yaw=float(poses[i, 2]))
            for i in order
            if scores[i] >= p.min_inliers
        ]

    def _refine(self, points: np.ndarray, start: Pose2D) -> tuple[Pose2D, tuple[int, float]] | None:
        """The fit from ``start`` and its quality (inliers, -RMS), or None if it fails."""
        from scipy.optimize import least_squares  # ~0.2 s to import: only when docking

        p = self.params
        x, y, yaw = start.x, start.y, start.yaw
        for gate in (2 * p.inlier_distance, p.inlier_distance):
            used = points[outline_distances(points, x, y, yaw) < gate]
            if len(used) < p.min_inliers:
                return None
            fit = least_squares(
                lambda v, used=used: outline_distances(used, v[0], v[1], v[2]),
                np.array([x, y, yaw]),
                loss="soft_l1",
                f_scale=p.inlier_distance / 2,
                x_scale=np.array([0.05, 0.05, 0.1]),
            )
            x, y, yaw = (float(value) for value in fit.x)
        residuals = outline_distances(points, x, y, yaw)
        on_outline = residuals[residuals < p.inlier_distance]
        rms = math.sqrt(float(np.mean(on_outline**2))) if len(on_outline) else math.inf
        e = self.expected
        if (
            len(on_outline) < p.min_inliers
            or rms > p.max_rms
            or math.hypot(x - e.x, y - e.y) > p.search_radius + 1e-9
            or abs(math.remainder(yaw - e.yaw, math.tau)) > p.search_angle + 1e-9
        ):
            return None
        pose = Pose2D(x=x, y=y, yaw=math.remainder(yaw, math.tau))
        return pose, (len(on_outline), -rms)
