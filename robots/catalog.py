"""The robot registry: every robot a mission may name, with its facts and what it provides.

A robot is one :class:`~baobab.robots.robot_info.RobotInfo` (:mod:`baobab.robots.robot_info`:
its name, capabilities, facts, how its model is built, the defaults its facts decide). Each
robot's folder ``robots/<name>/`` gives its entries in ``entry.py`` (``ENTRIES``), and the
registry gathers the folders that have one: adding a bundled robot is one folder. Consumers ask
this registry; only it and the robots' own folders name a robot. A user's robot file
(:mod:`baobab.robots.robot_file`) gives a ``RobotInfo`` of the same kind.

Importing this module loads no numpy and no MuJoCo: ``baobab validate`` reads it.
"""

from __future__ import annotations

import importlib
from importlib import resources

from baobab.robots.robot_info import (
    ARM,
    BASE,
    BASE_CONTROLLERS,
    COLLISION_MONITOR,
    DIFF_DRIVE_KERNEL,
    GRIPPER,
    LIDAR,
    MOBILE_CAPABILITIES,
    NAVIGATION,
    ROS_NODES,
    TELEOP,
    RobotInfo,
    load_attribute,
)

__all__ = [
    "ALIASES",
    "ARM",
    "BASE",
    "BASE_CONTROLLERS",
    "COLLISION_MONITOR",
    "DEFAULT_MOBILE_ROBOT",
    "DIFF_DRIVE_KERNEL",
    "ENTRY_MODULE",
    "GRIPPER",
    "LIDAR",
    "MOBILE_CAPABILITIES",
    "MOBILE_ROBOTS",
    "NAVIGATION",
    "ROBOTS",
    "ROBOT_FOLDERS",
    "ROBOT_NAMES",
    "ROS_NODES",
    "TELEOP",
    "RobotInfo",
    "default_mobile_robot",
    "load_attribute",
    "robot_named",
]

ENTRY_MODULE = "entry"
"""The module of a robot's folder that lists its registry entries (``ENTRIES``)."""

ROBOT_FOLDERS: tuple[str, ...] = tuple(
    sorted(
        folder.name
        for folder in resources.files(__package__ or "baobab.robots").iterdir()
        if folder.joinpath(f"{ENTRY_MODULE}.py").is_file()
    )
)
"""The folders of ``robots/`` that hold a robot (by name)."""


def _entries() -> list[RobotInfo]:
    """Every folder's entries: the mobile robots first, then the fixed ones, each in folder
    order (a folder's own order within it)."""
    entries: list[RobotInfo] = []
    for folder in ROBOT_FOLDERS:
        module = importlib.import_module(f"baobab.robots.{folder}.{ENTRY_MODULE}")
        entries.extend(module.ENTRIES)
    return sorted(entries, key=lambda robot: not robot.mobile)


DEFAULT_MOBILE_ROBOT = "turtlebot3"
"""The robot whose defaults a navigation stack built without a robot uses."""

ROBOTS: dict[str, RobotInfo] = {robot.name: robot for robot in _entries()}
"""Every bundled robot by name."""

ALIASES: dict[str, str] = {
    alias: robot.name for robot in ROBOTS.values() for alias in robot.aliases
}
"""Other names of bundled robots -> their names."""

ROBOT_NAMES: tuple[str, ...] = (*ROBOTS, *ALIASES)
"""Every name a mission's ``robot:`` may give."""

MOBILE_ROBOTS: tuple[str, ...] = tuple(name for name, robot in ROBOTS.items() if robot.mobile)
"""The bundled mobile robots, by name."""


def robot_named(name: str) -> RobotInfo | None:
    """The bundled robot called ``name`` (or one of its aliases), or None."""
    return ROBOTS.get(ALIASES.get(name, name))


def default_mobile_robot() -> RobotInfo:
    """The robot :data:`DEFAULT_MOBILE_ROBOT` names."""
    return ROBOTS[DEFAULT_MOBILE_ROBOT]
