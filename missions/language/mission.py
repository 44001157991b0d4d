"""A validated mission: what the loader (:mod:`baobab.missions.language.loader`) returns and a
run, a test or an export reads."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from baobab.missions.language.models import Noise

if TYPE_CHECKING:
    from baobab.behaviours.poses import Pose
    from baobab.missions.language.models import Event, Expect, SubtreeSpec
    from baobab.missions.language.tree_parser import Node, NodeShape
    from baobab.nav.collision_monitor_params import CollisionMonitorParams
    from baobab.nav.nav2_params_file import Nav2ParamsFile
    from baobab.robots.catalog import RobotInfo
    from baobab.sim.world import Pose2D, World
    from baobab.sim.yaml_source import LocatedDocument


@dataclass(frozen=True)
class Mission:
    """A validated mission, ready to compile and run.

    Attributes:
        path: the mission file.
        name: the ``mission:`` value.
        description: free text.
        robot: the robot's registry entry (or its robot file's).
        supported_robots: the bundled robots the mission fits (``robots:``); None: any that
            has the capabilities its tree needs.
        world: the 2D world of a mobile robot; None for a fixed robot.
        world_name: the bundled world or scene name, or the world file's resolved path.
        start: the start pose of a mobile robot (the world's default spawn if not given).
        seed: the seed of the run's random generator.
        params: the value of every mission parameter after ``--set``.
        locations: every named pose (world spawns and locations, then the mission's).
        tree: the validated tree, subtrees expanded.
        subtrees: the subtree declarations as written.
        subtree_shapes: each subtree body's structure, parameters un-substituted (for export).
        events: timed events, sorted by time (stable).
        timeout: the run's limit (s of sim time).
        expect: the expectations, if any.
        document: the located YAML document (for messages about nodes).
        noise: the run's sensor noise (off unless the file asks for it).
        nav2_params: the Nav2 parameter file that configures the navigation stack
            (``nav2_params:`` or ``--nav2-params``), read and checked; None without one.
        nav2_substitute: run the stated substitutes of plugins baobab does not have.
        nav2_warning: the one warning about the file's parameters baobab does not use.
        collision_monitor: the robot's collision monitor (the robot's, the world's and the
            mission's ``collision_monitor:`` blocks merged), or None without one.
    """

    path: Path
    name: str
    description: str
    robot: RobotInfo
    supported_robots: tuple[str, ...] | None
    world: World | None
    world_name: str
    start: Pose2D | None
    seed: int
    params: dict[str, Any]
    locations: dict[str, Pose]
    tree: Node
    subtrees: dict[str, SubtreeSpec]
    subtree_shapes: dict[str, NodeShape]
    events: tuple[Event, ...]
    timeout: float
    expect: Expect | None
    document: LocatedDocument
    noise: Noise = field(default_factory=Noise)
    nav2_params: Nav2ParamsFile | None = None
    nav2_substitute: bool = False
    nav2_warning: str | None = None
    collision_monitor: CollisionMonitorParams | None = None
