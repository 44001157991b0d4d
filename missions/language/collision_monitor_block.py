"""A mission's collision monitor: its world's block, its Nav2 parameter file's
``collision_monitor`` node and its own ``collision_monitor:`` block.

The three hold Nav2's parameters (:mod:`baobab.nav.collision_monitor_params`) and merge in
that order, parameter by parameter, so a mission can switch off one zone of its world's
monitor (``PolygonSlow: {enabled: false}``) or change one figure. A mistake is located in the
file that holds it (the mission, the parameter file or the world). A tree that toggles the
monitor needs one.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from baobab.missions.language.errors import located
from baobab.missions.language.tree_parser import Node
from baobab.robots.catalog import COLLISION_MONITOR, RobotInfo
from baobab.sim.errors import WorldError
from baobab.sim.world import World, bundled_world_path
from baobab.sim.yaml_source import KeyPath, LocatedDocument, load_located_yaml

if TYPE_CHECKING:
    from baobab.nav.collision_monitor_params import CollisionMonitorParams
    from baobab.nav.nav2_params_file import Nav2ParamsFile

BLOCK = "collision_monitor"
"""The key of the block in mission and world files."""


def mission_collision_monitor(
    document: LocatedDocument,
    written: Mapping[str, Any] | None,
    robot: RobotInfo,
    world: tuple[World | None, str],
    nav2_file: Nav2ParamsFile | None,
    origins: Mapping[KeyPath, str],
) -> CollisionMonitorParams | None:
    """The monitor the mission runs with, or None when no block configures one.

    Args:
        world: the mission's world and its name (as the mission gives it).
        nav2_file: the mission's Nav2 parameter file, or None.

    Raises:
        MissionError: a mistake in the mission's block, or a robot that cannot carry a
            monitor (located in the mission).
        WorldError: a mistake in the world's block (located in the world file).
        Nav2ParamsError: a mistake in the parameter file's node (located in that file).
    """
    world_block = None if world[0] is None else world[0].collision_monitor
    if nav2_file is None or "collision_monitor" not in nav2_file.nodes:
        file_block = None
    else:
        from baobab.nav.nav2_collision_monitor import file_monitor_block

        file_block = file_monitor_block(nav2_file)
    if world_block is None and file_block is None and written is None:
        return None
    if not (robot.mobile and robot.has_lidar):
        message = f"a collision monitor needs a mobile robot with a lidar; {robot.name} is not one"
        raise located(document, (BLOCK,) if written is not None else ("robot",), message)
    # the monitor's parameters load only for a mission that has one (validate stays light)
    from baobab.nav.collision_monitor_config import layered_collision_monitor, robot_footprint
    from baobab.nav.collision_monitor_params import CollisionMonitorConfigError

    try:
        layers = [world_block, file_block, written]
        return layered_collision_monitor(layers, robot_footprint(robot))
    except CollisionMonitorConfigError as exc:
        message = exc.describe(BLOCK)
        if exc.layer == 2:
            raise located(document, (BLOCK, *exc.key_path), message, origins) from None
        if exc.layer == 1 and nav2_file is not None:
            from baobab.nav.nav2_collision_monitor import file_monitor_error

            raise file_monitor_error(nav2_file, exc) from None
        raise _world_error(world[1], (BLOCK, *exc.key_path), message) from None


def check_toggles(document: LocatedDocument, tree: Node, configured: bool) -> None:
    """Refuse a node that toggles a collision monitor the mission does not have.

    Raises:
        MissionError: at the first such node.
    """
    if configured:
        return
    for node in tree.walk():
        if node.behaviour.capability == COLLISION_MONITOR:
            raise located(
                document,
                node.type_path,
                f"{node.type} needs a collision monitor: give the mission (or its world) a "
                f"{BLOCK}: block",
            )


def _world_error(world_name: str, key_path: KeyPath, message: str) -> WorldError:
    """``message`` located at ``key_path`` in the world file ``world_name`` names."""
    path = Path(world_name) if "/" in world_name else bundled_world_path(world_name)
    document = load_located_yaml(path, WorldError)
    line, column = document.locate(key_path)
    return WorldError(document.path, line, column, message)
