"""Collision checks of the robot's footprint, and projection of a unicycle's motion ahead.

For a circular robot whose radius is the inflation layer's inscribed radius, the robot is in
collision exactly when the cost under its centre is ``INSCRIBED_INFLATED_OBSTACLE`` or more.
A robot with a polygon footprint (the costmap's :attr:`~baobab.nav.costmap.Costmap2D.outline`)
collides, as Nav2's ``FootprintCollisionChecker`` has it, when its outline at the pose crosses
a ``LETHAL_OBSTACLE`` cell (:mod:`baobab.nav.footprint_kernel`): the pose's yaw matters.
Cells off the costmap or unknown count as free unless ``unknown_is_collision`` (Nav2's
controllers do the same when the costmap tracks unknown space). The controller uses these
checks for its collision-ahead test; the recoveries (Spin, BackUp, DriveOnHeading) project
their commands ahead with them. Assisted teleop checks the padded footprint against the
lethal cells exactly (:func:`lethal_distances`, :func:`outline_lethal_distances`), so its
stopping margin does not depend on how the grid meets the wall.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from baobab.nav.costmap import (
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
    Costmap2D,
)
from baobab.nav.footprint_kernel import footprint_collisions
from baobab.sim.world import Pose2D


def collision_mask(
    costmap: Costmap2D,
    xs: np.ndarray,
    ys: np.ndarray,
    unknown_is_collision: bool = False,
    yaws: np.ndarray | None = None,
) -> np.ndarray:
    """Which robot poses ``(xs, ys, yaws)`` (m, rad) are in collision (``bool`` array).

    A circular robot needs no ``yaws``; a polygon footprint without them is checked at yaw 0.
    """
    if costmap.has_polygon:
        x = np.asarray(xs, dtype=float).reshape(-1)
        poses = np.column_stack(
            (
                x,
                np.asarray(ys, dtype=float).reshape(-1),
                np.zeros_like(x) if yaws is None else np.asarray(yaws, dtype=float).reshape(-1),
            )
        )
        hits = footprint_collisions(
            costmap.data, costmap.pack(), costmap.outline, poses, unknown_is_collision
        )
        return hits.reshape(np.shape(xs))
    costs = costmap.costs(np.asarray(xs), np.asarray(ys), outside=NO_INFORMATION)
    unknown = costs == NO_INFORMATION
    return np.where(unknown, unknown_is_collision, costs >= INSCRIBED_INFLATED_OBSTACLE)


def in_collision(
    costmap: Costmap2D, x: float, y: float, unknown_is_collision: bool = False, yaw: float = 0.0
) -> bool:
    """True when the robot at ``(x, y, yaw)`` (m, rad) collides (a circle ignores ``yaw``)."""
    if costmap.has_polygon:
        poses = np.array([[x, y, yaw]])
        return bool(
            collision_mask(costmap, poses[:, 0], poses[:, 1], unknown_is_collision, poses[:, 2])[0]
        )
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
    if in_collision(costmap, pose.x, pose.y, unknown_is_collision, pose.yaw):
        return 0.0
    poses = project_motion(pose, linear, angular, duration, dt)
    if len(poses) == 0:
        return None
    hits = collision_mask(costmap, poses[:, 0], poses[:, 1], unknown_is_collision, poses[:, 2])
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


OUTLINE_SPACING = 0.01
"""m between the points of a polygon's outline :func:`outline_lethal_distances` measures."""


def outline_lethal_distances(
    costmap: Costmap2D, outline: np.ndarray, poses: np.ndarray, reach: float
) -> np.ndarray:
    """Distance (m) from the polygon ``outline`` (``base_link``, m) at each pose ``(x, y,
    yaw)`` to the nearest lethal cell's square; 0 when a lethal cell's centre lies inside it.

    The outline is measured at points :data:`OUTLINE_SPACING` apart (within half that of the
    exact distance); lethal cells farther than ``reach`` (m) read ``inf``, as in
    :func:`lethal_distances`.
    """
    closed = np.vstack((outline, outline[:1]))
    points = []
    for start, end in itertools.pairwise(closed):
        steps = max(math.ceil(math.dist(start, end) / OUTLINE_SPACING), 1)
        t = np.arange(steps) / steps
        points.append(start + t[:, None] * (end - start))
    local = np.vstack(points)
    result = np.empty(len(poses))
    for k, (x, y, yaw) in enumerate(np.asarray(poses, dtype=float)):
        cos, sin = math.cos(yaw), math.sin(yaw)
        px = x + cos * local[:, 0] - sin * local[:, 1]
        py = y + sin * local[:, 0] + cos * local[:, 1]
        nearest = float(lethal_distances(costmap, px, py, reach).min())
        if nearest > 0.0 and _lethal_centre_inside(costmap, px, py):
            nearest = 0.0
        result[k] = nearest
    return result


def _lethal_centre_inside(costmap: Costmap2D, px: np.ndarray, py: np.ndarray) -> bool:
    """True when a lethal cell's centre lies inside the polygon through ``(px, py)``."""
    x0 = max(math.floor((px.min() - costmap.origin_x) / costmap.resolution), 0)
    y0 = max(math.floor((py.min() - costmap.origin_y) / costmap.resolution), 0)
    x1 = min(math.floor((px.max() - costmap.origin_x) / costmap.resolution) + 1, costmap.size_x)
    y1 = min(math.floor((py.max() - costmap.origin_y) / costmap.resolution) + 1, costmap.size_y)
    if x0 >= x1 or y0 >= y1:
        return False
    rows, cols = np.nonzero(costmap.data[y0:y1, x0:x1] == LETHAL_OBSTACLE)
    if rows.size == 0:
        return False
    cx, cy = costmap.map_to_world_array(cols + x0, rows + y0)
    inside = np.zeros(cx.shape, dtype=bool)
    for i in range(len(px)):
        j = (i + 1) % len(px)
        crosses = (py[i] > cy) != (py[j] > cy)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_at = px[i] + (cy - py[i]) * (px[j] - px[i]) / (py[j] - py[i])
        inside ^= crosses & (cx < x_at)
    return bool(inside.any())
