"""The forward-progress rule: its parameters and its measure of forward speed.

While a navigation goal runs, whenever the robot is not moving forward and more than
:data:`DEFAULT_PERIOD` has passed since the last clearing, clear all costmaps (the rule of the
Nav2 Simple Commander tutorial's ``nav_to_pose.py``, which baobab's missions grew from).

Kept apart from the decorator in :mod:`baobab.behaviours.progress` (which needs py_trees) so
that validating a mission can read the defaults without importing py_trees.
"""

from __future__ import annotations

import math

from baobab.sim.world import Pose2D

DEFAULT_PERIOD = 0.5
"""Least sim time (s) between two clearings (the tutorial's ``COSTMAP_CLEARING_PERIOD``)."""
DEFAULT_MIN_SPEED = 0.01
"""Forward speed (m/s) above which the robot counts as moving forward; above zero so that
contact jitter of a stopped robot does not count."""


def forward_speed(previous: Pose2D, current: Pose2D, dt: float) -> float:
    """Speed (m/s) along ``previous``'s heading from ``previous`` to ``current`` in ``dt`` s."""
    dx, dy = current.x - previous.x, current.y - previous.y
    return (dx * math.cos(previous.yaw) + dy * math.sin(previous.yaw)) / dt
