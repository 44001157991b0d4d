"""A mobile robot's whole navigation stack: the navigation server, the collision monitor between
it and the base when there is one, and the servers of the world's route graph and datum."""

from __future__ import annotations

from typing import TYPE_CHECKING

from baobab.nav.server import NavigationServer
from baobab.nav.world_servers import WorldServers, attach_world_servers

if TYPE_CHECKING:
    from baobab.nav.collision_monitor import CollisionMonitor
    from baobab.nav.interfaces import MobileBase, ScanSource
    from baobab.nav.navigation_params import NavigationParams
    from baobab.sim.simulation import Simulation
    from baobab.sim.world import World


def build_navigation_stack(
    sim: Simulation,
    base: MobileBase,
    lidar: ScanSource | None,
    world: World,
    params: NavigationParams,
    monitor: CollisionMonitor | None = None,
) -> tuple[NavigationServer, WorldServers]:
    """The navigation server of the robot ``base`` drives, commanding it through ``monitor``
    (whose ``collision_monitor/toggle`` it then serves), and the world's route and GPS
    servers plugged into it."""
    drive = base if monitor is None else monitor.base
    server = NavigationServer(sim, drive, world, lidar=lidar, params=params)
    if monitor is not None:
        monitor.serve(server.services)
    return server, attach_world_servers(server, world)
