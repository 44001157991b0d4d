"""A TurtleBot3 Burger running in a simulation: world + robot in one call, and its handle."""

from __future__ import annotations

from dataclasses import dataclass

from baobab.robots.diff_drive.base import DiffDriveBase
from baobab.robots.turtlebot3.model import (
    BURGER,
    DEFAULT_PREFIX,
    BurgerFacts,
    TurtleBot3Names,
    attach_turtlebot3,
)
from baobab.sim.builder import world_spec
from baobab.sim.lidar import Lidar
from baobab.sim.simulation import Simulation
from baobab.sim.world import Pose2D, World, load_world


@dataclass
class TurtleBot3:
    """A Burger living in a :class:`Simulation`: its base and its lidar, both already running."""

    sim: Simulation
    base: DiffDriveBase
    lidar: Lidar
    names: TurtleBot3Names


def start_turtlebot3(
    sim: Simulation,
    *,
    prefix: str = DEFAULT_PREFIX,
    facts: BurgerFacts = BURGER,
    lidar_noise_std: float = 0.0,
) -> TurtleBot3:
    """Start the base controller (100 Hz) and the LDS-01 (5 Hz) of a Burger compiled into ``sim``.

    Args:
        sim: a simulation whose model holds a Burger attached with ``prefix``.
        prefix: name prefix of the robot's MuJoCo elements.
        facts: the robot's figures.
        lidar_noise_std: standard deviation of the Gaussian range noise (m).
    """
    names = TurtleBot3Names(prefix)
    base = DiffDriveBase(sim, prefix=prefix, facts=facts)
    lidar = Lidar(
        sim,
        names.lidar_site,
        rate=facts.lidar_rate,
        beams=facts.lidar_beams,
        range_min=facts.lidar_range_min,
        range_max=facts.lidar_range_max,
        noise_std=lidar_noise_std,
        frame_id=f"{prefix}base_scan",
    )
    return TurtleBot3(sim=sim, base=base, lidar=lidar, names=names)


def build_turtlebot3_sim(
    world: World | str,
    start: Pose2D | None = None,
    *,
    seed: int = 0,
    lidar_noise_std: float = 0.0,
    prefix: str = DEFAULT_PREFIX,
) -> tuple[Simulation, TurtleBot3]:
    """Build ``world`` with a Burger at ``start``, compile it and start the robot.

    Args:
        world: the world, or the name of a bundled world, or a path to a world file.
        start: the robot's pose in the map frame; defaults to the world's default spawn.
        seed: seed of the simulation's random generator (lidar noise).
        lidar_noise_std: standard deviation of the Gaussian range noise (m).
        prefix: name prefix of the robot's MuJoCo elements.

    Returns:
        The simulation and the robot handle with its base controller and lidar registered.

    Raises:
        WorldError: if ``world`` names a world that cannot be loaded.
    """
    if not isinstance(world, World):
        world = load_world(world)
    pose = world.spawn if start is None else start
    spec = world_spec(world)
    attach_turtlebot3(spec, pose, prefix=prefix)
    sim = Simulation(spec.compile(), seed=seed)
    return sim, start_turtlebot3(sim, prefix=prefix, lidar_noise_std=lidar_noise_std)
