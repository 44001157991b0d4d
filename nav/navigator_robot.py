"""The simulated robot a :class:`~baobab.nav.navigator.BasicNavigator` drives.

The navigation server takes any :class:`~baobab.nav.interfaces.MobileBase` and
:class:`~baobab.nav.interfaces.ScanSource`. The Nav2 facade is different, because a Nav2 script
constructs ``BasicNavigator()`` and expects a robot to be there: :func:`build_simulated_robot`
builds one from ``baobab.robots`` (the layer below ``nav``; robots never import nav).

Checking a pose (:func:`check_free`, :func:`pose_is_free`) loads no physics: ``baobab nav2``
and ``baobab teleop`` refuse a blocked start before MuJoCo and the robot's compiled loop load,
so the robot package is imported when a robot is built.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

from baobab.sim.errors import BaobabError
from baobab.sim.geometry import nearest_obstacle
from baobab.sim.world import Pose2D, World

if TYPE_CHECKING:  # checking a pose (baobab nav2, baobab teleop) loads no physics
    from baobab.nav.interfaces import MobileBase, ScanSource
    from baobab.sim.simulation import Simulation

ROBOT_MODELS = ("turtlebot3",)
"""The robot names a navigator accepts."""


class NavigatorSetupError(BaobabError, ValueError):
    """A navigator asked for something that cannot be built: an unknown robot, a blocked pose."""


@dataclass
class SimulatedRobot:
    """A robot running in its own simulation, as the navigator needs it.

    Attributes:
        sim: the simulation (world + robot), its callbacks registered.
        base: the drive, ground-truth pose in the map frame (the sim localises perfectly).
        lidar: the 2D scanner feeding the costmaps.
        footprint_radius: radius (m) of the base's circular footprint.
        teleport: puts the robot at rest at a map-frame pose (``setInitialPose``).
    """

    sim: Simulation
    base: MobileBase
    lidar: ScanSource
    footprint_radius: float
    teleport: Callable[[Pose2D], None]


def build_simulated_robot(robot: str, world: World, start: Pose2D, seed: int) -> SimulatedRobot:
    """Build ``world`` with ``robot`` at ``start`` in a new simulation seeded with ``seed``.

    Raises:
        NavigatorSetupError: ``robot`` is not one of :data:`ROBOT_MODELS`, or ``start`` is not
            free for its footprint.
    """
    if robot != "turtlebot3":
        raise NavigatorSetupError(
            f"unknown robot {robot!r}; a navigator drives one of: {', '.join(ROBOT_MODELS)}"
        )
    from baobab.robots.turtlebot3 import BURGER, build_turtlebot3_sim  # MuJoCo: only to build

    check_free(world, start, BURGER.footprint_radius, what="start pose")
    sim, turtlebot = build_turtlebot3_sim(world, start, seed=seed)
    return SimulatedRobot(
        sim=sim,
        base=turtlebot.base,
        lidar=turtlebot.lidar,
        footprint_radius=BURGER.footprint_radius,
        teleport=turtlebot.base.teleport,
    )


def footprint_radius(robot: str) -> float:
    """The footprint radius (m) of a navigator's robot (0 for a name it does not drive)."""
    from baobab.robots.catalog import ROBOTS  # facts only: no physics

    info = ROBOTS.get(robot)
    return info.footprint_radius if info is not None and robot in ROBOT_MODELS else 0.0


def default_start(world: World, radius: float) -> Pose2D:
    """Where a robot starts when nothing says: the world's default spawn, or on a map without
    one the map frame's origin (where Nav2's AMCL starts its estimate, ``initial_pose`` 0, 0, 0).

    Raises:
        NavigatorSetupError: a map without a spawn whose origin is not free.
    """
    spawn = world.spawns.get("default")
    if spawn is not None:
        return spawn
    origin = Pose2D(x=0.0, y=0.0)
    name, distance = nearest_obstacle(world, 0.0, 0.0)
    if distance < radius:
        raise NavigatorSetupError(
            f"world '{world.name}' has no spawn and the map origin (0, 0) is not free ('{name}' "
            f"is {distance:.3f} m from it); give a start pose (start=Pose2D(...), --start X,Y,YAW"
            ", a mission's start:)"
        )
    return origin


def pose_is_free(world: World, pose: Pose2D, radius: float) -> bool:
    """True when a footprint of ``radius`` (m) at ``pose`` is clear of obstacles, on the floor."""
    return nearest_obstacle(world, pose.x, pose.y)[1] >= radius


def check_free(world: World, pose: Pose2D, radius: float, *, what: str) -> None:
    """Raise unless a footprint of ``radius`` (m) at ``pose`` is free in ``world``.

    Raises:
        NavigatorSetupError: naming the obstacle (or the floor edge) in the way.
    """
    name, distance = nearest_obstacle(world, pose.x, pose.y)
    if distance < radius:
        raise NavigatorSetupError(
            f"{what} ({pose.x:.3f}, {pose.y:.3f}) is not free in world '{world.name}': "
            f"'{name}' is {distance:.3f} m from it, the robot's footprint needs {radius:.3f} m"
        )
