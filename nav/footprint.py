"""Collision checks for a circular footprint and projection of a unicycle's motion ahead.

For a circular robot whose radius is the inflation layer's inscribed radius, the robot is in
collision exactly when the cost under its centre is ``INSCRIBED_INFLATED_OBSTACLE`` or more.
Cells off the costmap or unknown count as free unless ``unknown_is_collision`` (Nav2's
controllers do the same when the costmap tracks unknown space). The controller uses these
checks for its collision-ahead test; the recoveries (Spin, BackUp, DriveOnHeading) project
their commands ahead with them. Assisted teleop checks a padded footprint disc against the
lethal cells exactly (:func:`lethal_distances`), so its stopping margin does not depend
on how the grid meets the wall.
"""

from __future__ import annotations

import math

import numpy as np

from baobab.nav.costmap import (
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
    Costmap2D,
)
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


def lethal_distances(
    costmap: Costmap2D, xs: np.ndarray, ys: np.ndarray, reach: float
) -> np.ndarray:
    """Distance (m) from each point ``(xs, ys)`` (m) to the nearest lethal cell's square.

    Exact geometry on the grid: the distance to the nearest point of each lethal cell, not to
    its centre, so a robot centre whose distance is at least its radius keeps that radius to
    whatever the lethal cells cover (the static layer marks every cell an obstacle overlaps),
    however the grid is aligned. Lethal cells farther than ``reach`` (m) are not looked at:
    their points read ``inf``, as do points with none. Cells off the grid are free. Returns a
    float array shaped like ``xs``; 0 for a point inside a lethal cell.
    """
    px = np.asarray(xs, dtype=float).reshape(-1)
    py = np.asarray(ys, dtype=float).reshape(-1)
    result = np.full(px.shape, np.inf)
    if px.size:
        res = costmap.resolution
        ix0 = max(math.floor((px.min() - reach - costmap.origin_x) / res), 0)
        iy0 = max(math.floor((py.min() - reach - costmap.origin_y) / res), 0)
        ix1 = min(math.floor((px.max() + reach - costmap.origin_x) / res) + 1, costmap.size_x)
        iy1 = min(math.floor((py.max() + reach - costmap.origin_y) / res) + 1, costmap.size_y)
        lethal = np.zeros((0, 0), dtype=bool)
        if ix0 < ix1 and iy0 < iy1:
            lethal = costmap.data[iy0:iy1, ix0:ix1] == LETHAL_OBSTACLE
        rows, cols = np.nonzero(lethal)
        if rows.size:
            centres_x, centres_y = costmap.map_to_world_array(cols + ix0, rows + iy0)
            half = res / 2
            gap_x = np.maximum(np.abs(centres_x[None, :] - px[:, None]) - half, 0.0)
            gap_y = np.maximum(np.abs(centres_y[None, :] - py[:, None]) - half, 0.0)
            nearest = np.sqrt((gap_x**2 + gap_y**2).min(axis=1))
            result = np.where(nearest <= reach, nearest, np.inf)
    return result.reshape(np.shape(xs))
