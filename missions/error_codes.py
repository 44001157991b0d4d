"""The error codes a run can end with, by name: what ``expect: error_code`` may name.

A failed run reports the code of the task that failed (Nav2's codes for navigation, the base
controllers' 8xx, the arm's) or one of the run's own 99xx codes (:class:`MissionErrorCode`).
"""

from __future__ import annotations

import enum


class MissionErrorCode(enum.IntEnum):
    """Why a mission failed when no task's own error code explains it (99xx)."""

    NONE = 0
    TREE_FAILED = 9900
    """The tree failed at a node that is not a task (a condition, a constant, a timeout)."""
    MISSION_TIMEOUT = 9901
    """The mission's ``timeout`` (sim time) passed while the tree was still running."""
    SIMULATION_ERROR = 9902
    """The physics diverged."""
    ROBOT_DISPLACED = 9903
    """The robot's pose jumped farther than it can drive (teleported, kidnapped)."""
    SENSOR_TIMEOUT = 9904
    """No lidar scan arrived for longer than the sensor timeout."""
    SENSOR_DEGRADED = 9905
    """The lidar's scans stayed too noisy to trust for longer than the tolerance."""
    WHEEL_FAULT = 9906
    """A wheel's measured speed stayed far from its command (motor or wheel failure)."""
