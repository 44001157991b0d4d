"""Collision checks for a circular footprint and projection of a unicycle's motion ahead.

For a circular robot whose radius is the inflation layer's inscribed radius, the robot is in
collision exactly when the cost under its centre is ``INSCRIBED_INFLATED_OBSTACLE`` or more.
Cells off the costmap or unknown count as free unless ``unknown_is_collision`` (Nav2's
controllers do the same when the costmap tracks unknown space). The controller uses these
checks for its collision-ahead test; the recoveries (Spin, BackUp, DriveOnHeading,
AssistedTeleop) project their commands ahead with them.
"""

from __future__ import annotations

import numpy as np

from baobab.nav.costmap import INSCRIBED_INFLATED_OBSTACLE, NO_INFORMATION, Costmap2D
from baobab.sim.world import Pose2D


def collision_mask(
    costmap: Costmap2D, xs: np.ndarray, ys: np.ndarray, unknown_is_collision: bool = False
) -> np.ndarray:
    """Which robot centres ``(xs, ys)`` (m) are in collision (``bool`` array)."""
    costs = costmap.costs(np.asarray(xs), np.asarray(ys), outside=NO_INFORMATION)
    unknown = costs == NO_INFORMATION
    return np.where(unknown, unknown_is_collision, costs >= INSCRIBED_INFLATED_OBSTACLE)


def in_collision(
    costmap: Costmap2D, x: float, y: float, unknown_is_collision: bool = False
) -> bool:
    """True when a robot centred on ``(x, y)`` (m) collides."""
    cost = costmap.cost(x, y, outside=NO_INFORMATION)
    if cost == NO_INFORMATION:
        return unknown_is_collision
    return cost >= INSCRIBED_INFLATED_OBSTACLE


def project_motion(
    pose: Pose2D, linear: float, angular: float, duration: float, dt: float
) -> np.ndarray:
    """Poses after ``dt, 2 dt, ...`` up to ``duration`` (s) of constant ``(linear, angular)``.

    The unicycle is integrated exactly (arcs, not Euler steps). Returns ``(K, 3)`` rows of
    ``x`` (m), ``y`` (m), ``yaw`` (rad).
    """
    if dt <= 0:
        raise ValueError(f"dt must be positive, got {dt}")
    steps = int(np.floor(duration / dt + 1e-9))
    t = dt * np.arange(1, steps + 1)
    yaw = pose.yaw + angular * t
    if abs(angular) < 1e-9:
        x = pose.x + linear * t * np.cos(pose.yaw)
        y = pose.y + linear * t * np.sin(pose.yaw)
    else:
        radius = linear / angular
        x = pose.x + radius * (np.sin(yaw) - np.sin(pose.yaw))
        y = pose.y - radius * (np.cos(yaw) - np.cos(pose.yaw))
    return np.column_stack([x, y, yaw])


def time_to_collision(
    costmap: Costmap2D,
    pose: Pose2D,
    linear: float,
    angular: float,
    duration: float,
    dt: float = 0.1,
    unknown_is_collision: bool = False,
) -> float | None:
    """First projected time (s, a multiple of ``dt``) at which the robot collides, or None.

    The pose itself is checked too: a robot already in collision returns 0.0.
    """
    if in_collision(costmap, pose.x, pose.y, unknown_is_collision):
        return 0.0
    poses = project_motion(pose, linear, angular, duration, dt)
    if len(poses) == 0:
        return None
    hits = collision_mask(costmap, poses[:, 0], poses[:, 1], unknown_is_collision)
    if not hits.any():
        return None
    return float(dt * (int(np.argmax(hits)) + 1))
