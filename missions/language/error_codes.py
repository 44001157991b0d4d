"""The error codes a run can end with, by name: what ``expect: error_code`` may name.

A failed run reports the code of the task that failed (Nav2's codes for navigation, the base
controllers' 8xx, the arm's) or one of the run's own 99xx codes (:class:`MissionErrorCode`).
"""

from __future__ import annotations

import enum

from baobab.behaviours.ports import ARM, BASE_CONTROLLERS, NAVIGATION
from baobab.robots.catalog import RobotInfo, load_attribute


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


def error_codes(robot: RobotInfo) -> dict[str, frozenset[int]]:
    """Every code a run of ``robot`` can end with: name -> numbers.

    A name can stand for several numbers (Nav2's ``TIMEOUT`` is 108 for the controller, 207
    for the planner...); ``expect: error_code`` compares names with names, numbers with numbers.
    An arm's own codes are those its registry entry names (``error_codes``).
    """
    from baobab.nav import errors as nav_errors
    from baobab.robots.diff_drive.controller_errors import BaseControllerError

    given = set(robot.capabilities)
    enums: list[type[enum.IntEnum]] = [MissionErrorCode]
    if NAVIGATION in given:
        enums += [
            value
            for value in vars(nav_errors).values()
            if isinstance(value, type)
            and issubclass(value, enum.IntEnum)
            and value is not enum.IntEnum
        ]
    if BASE_CONTROLLERS in given:
        enums.append(BaseControllerError)
    if ARM in given and robot.error_codes:
        enums.append(load_attribute(robot.error_codes))
    codes: dict[str, set[int]] = {}
    for codes_enum in enums:
        for member in codes_enum:
            codes.setdefault(member.name, set()).add(int(member))
    return {name: frozenset(numbers) for name, numbers in codes.items()}
