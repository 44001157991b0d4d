"""Seed 000's forward-progress rule: its parameters and its measure of forward speed.

Kept apart from the decorator in :mod:`baobab.behaviours.progress` (which needs py_trees) so
that validating a mission can read the defaults without importing py_trees.
"""

from __future__ import annotations

import math

from baobab.sim.world import Pose2D

DEFAULT_PERIOD = 0.5
"""Seed 000's ``COSTMAP_CLEARING_PERIOD`` (s)."""
DEFAULT_MIN_SPEED = 0.01
"""Forward speed (m/s) above which the robot counts as moving forward; above zero so that
contact jitter of a stopped robot does not count."""


def forward_speed(previous: Pose2D, current: Pose2D, dt: float) -> float:
    """Speed (m/s) along ``previous``'s heading from ``previous`` to ``current`` in ``dt`` s."""
    dx, dy = current.x - previous.x, current.y - previous.y
    return (dx * math.cos(previous.yaw) + dy * math.sin(previous.yaw)) / dt
