"""A TurtleBot3 Burger in a simulation in one call (:func:`build_turtlebot3_sim`)."""

from __future__ import annotations

from baobab.robots.diff_drive.robot import MobileRobot, build_mobile_sim, start_mobile_robot
from baobab.robots.turtlebot3.facts import BURGER
from baobab.robots.turtlebot3.model import DEFAULT_PREFIX, turtlebot3_spec
from baobab.sim.simulation import Simulation
from baobab.sim.world import Pose2D, World


def start_turtlebot3(
    sim: Simulation, *, prefix: str = DEFAULT_PREFIX, lidar_noise_std: float = 0.0
) -> MobileRobot:
    """Start the base controller (100 Hz) and the LDS-01 (5 Hz) of a Burger compiled into
    ``sim`` with ``prefix``; ``lidar_noise_std`` is the range noise (m)."""
    return start_mobile_robot(sim, BURGER, prefix=prefix, lidar_noise_std=lidar_noise_std)


def build_turtlebot3_sim(
    world: World | str,
    start: Pose2D | None = None,
    *,
    seed: int = 0,
    lidar_noise_std: float = 0.0,
    prefix: str = DEFAULT_PREFIX,
) -> tuple[Simulation, MobileRobot]:
    """Build ``world`` with a Burger at ``start`` (default: the world's spawn), compile it and
    start the robot (:func:`~baobab.robots.diff_drive.robot.build_mobile_sim`).

    Raises:
        WorldError: if ``world`` names a world that cannot be loaded.
    """
    return build_mobile_sim(
        world,
        BURGER,
        start,
        body=turtlebot3_spec,
        prefix=prefix,
        seed=seed,
        lidar_noise_std=lidar_noise_std,
    )
