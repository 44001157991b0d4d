"""A differential-drive robot running in a simulation: world + robot in one call, and its handle.

:func:`build_mobile_sim` builds a world with a robot from its facts (its own body, or the
generic one of :mod:`baobab.robots.diff_drive.model`), compiles it and starts the robot: the
base controller at 100 Hz and the lidar at its scan rate. A registry entry does it by name
(:meth:`baobab.robots.catalog.RobotInfo.build_sim`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import mujoco

from baobab.robots.diff_drive.base import DiffDriveBase
from baobab.robots.diff_drive.facts import DiffDriveFacts
from baobab.robots.diff_drive.model import attach_robot, diff_drive_spec
from baobab.robots.diff_drive.names import DiffDriveNames
from baobab.sim.builder import world_spec
from baobab.sim.errors import SimulationError
from baobab.sim.lidar import Lidar
from baobab.sim.simulation import Simulation
from baobab.sim.world import Pose2D, World, load_world

DEFAULT_PREFIX = "robot/"
"""The name prefix of a robot's MuJoCo elements when nothing else says."""

BodyBuilder = Callable[[DiffDriveFacts], mujoco.MjSpec]
"""Builds a robot's stand-alone MjSpec (``base_link`` at the origin) from its facts."""


@dataclass
class MobileRobot:
    """A differential-drive robot living in a :class:`Simulation`: its base and its lidar,
    both already running, its MuJoCo names and its facts."""

    sim: Simulation
    base: DiffDriveBase
    lidar: Lidar
    names: DiffDriveNames
    facts: DiffDriveFacts


def scan_rate(sim: Simulation, rate: float) -> float:
    """``rate`` (Hz) if its period is a whole number of physics steps, else the nearest rate
    that is (the RPLIDAR's 5.5 Hz scans every 0.18 s at the 5 ms step)."""
    try:
        sim.steps_for(1.0 / rate, what="scan period")
    except SimulationError:
        steps = max(round(1.0 / rate / sim.physics_dt), 1)
        return 1.0 / (steps * sim.physics_dt)
    return rate


def start_mobile_robot(
    sim: Simulation,
    facts: DiffDriveFacts,
    *,
    prefix: str = DEFAULT_PREFIX,
    lidar_noise_std: float = 0.0,
) -> MobileRobot:
    """Start the base controller (100 Hz) and the lidar of a robot compiled into ``sim``.

    Args:
        sim: a simulation whose model holds the robot attached with ``prefix``.
        facts: the robot's figures.
        prefix: name prefix of the robot's MuJoCo elements.
        lidar_noise_std: standard deviation of the Gaussian range noise (m).
    """
    names = DiffDriveNames(prefix)
    base = DiffDriveBase(sim, prefix=prefix, facts=facts)
    lidar = facts.lidar
    scanner = Lidar(
        sim,
        names.lidar_site,
        rate=scan_rate(sim, lidar.rate),
        beams=lidar.beams,
        range_min=lidar.range_min,
        range_max=lidar.range_max,
        noise_std=lidar_noise_std,
        frame_id=f"{prefix}base_scan",
    )
    return MobileRobot(sim=sim, base=base, lidar=scanner, names=names, facts=facts)


def build_mobile_sim(
    world: World | str,
    facts: DiffDriveFacts,
    start: Pose2D | None = None,
    *,
    body: BodyBuilder = diff_drive_spec,
    prefix: str = DEFAULT_PREFIX,
    seed: int = 0,
    lidar_noise_std: float = 0.0,
) -> tuple[Simulation, MobileRobot]:
    """Build ``world`` with the robot of ``facts`` at ``start``, compile it, start the robot.

    Args:
        world: the world, or the name of a bundled world, or a path to a world file.
        facts: the robot's figures.
        start: the robot's pose in the map frame; defaults to the world's default spawn.
        body: builds the robot's MjSpec from its facts (default: the generic body).
        prefix: name prefix of the robot's MuJoCo elements.
        seed: seed of the simulation's random generator (lidar noise).
        lidar_noise_std: standard deviation of the Gaussian range noise (m).

    Returns:
        The simulation and the robot handle with its base controller and lidar registered.

    Raises:
        WorldError: if ``world`` names a world that cannot be loaded.
    """
    if not isinstance(world, World):
        world = load_world(world)
    pose = world.spawn if start is None else start
    spec = world_spec(world)
    attach_robot(spec, body(facts), pose, prefix=prefix)
    sim = Simulation(spec.compile(), seed=seed)
    return sim, start_mobile_robot(sim, facts, prefix=prefix, lidar_noise_std=lidar_noise_std)
