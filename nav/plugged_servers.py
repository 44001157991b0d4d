"""Nav2's newer servers plugged into the navigation server: docking and following.

:func:`plug_in` builds them for one navigation server and registers their actions in its
``action_servers`` (``dock_robot``, ``undock_robot``, ``follow_object``) and the docking
server's ``docking_server/reload_database`` in its ``services``, where ``BasicNavigator``
finds them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol

from baobab.nav.docking import DockingParams
from baobab.nav.docking_server import RELOAD_DATABASE, DockingHost, DockingServer
from baobab.nav.following import FOLLOW_ACTION, FollowingParams, FollowingServer
from baobab.nav.interfaces import ActionServer, ScanSource
from baobab.nav.object_poses import ObjectPoses
from baobab.sim.simulation import Simulation
from baobab.sim.tasks import TaskHandle
from baobab.sim.world import Pose2D, World


class PluginHost(DockingHost, Protocol):
    """What the plugged-in servers use of the navigation server."""

    action_servers: dict[str, ActionServer]
    services: dict[str, Any]


@dataclass(frozen=True)
class PluggedParams:
    """The plugged-in servers' settings (Nav2's defaults)."""

    docking: DockingParams = field(default_factory=DockingParams)
    following: FollowingParams = field(default_factory=FollowingParams)


class PluggedServerTasks:
    """The navigation server's part that holds the plugged-in servers: their registries and
    the tasks they run (its NavigationPort)."""

    action_servers: dict[str, ActionServer]
    """Servers of the Nav2 actions the navigation server does not run itself, by action name:
    docking and following."""
    services: dict[str, Callable[..., Any]]
    """Nav2 services beyond the costmap ones, by name: ``docking_server/reload_database``,
    ``collision_monitor/toggle`` (``enable`` -> ``(success, message)``) when a collision
    monitor is plugged in."""
    docking: DockingServer
    following: FollowingServer

    def _plug_in(
        self,
        host: PluginHost,
        sim: Simulation,
        lidar: ScanSource | None,
        world: World,
        params: PluggedParams,
    ) -> None:
        """Make the registries and plug the servers of ``host`` (this object) in."""
        self.action_servers = {}
        self.services = {}
        self.docking, self.following = plug_in(host, sim, lidar, world, params)

    def _unplug(self) -> None:
        """Stop the plugged-in servers' subscriptions."""
        self.docking.close()
        self.following.poses.close()

    def dock_robot(self, dock_id: str, dock_pose: Pose2D | None, staging: bool) -> TaskHandle:
        """Dock at the database's ``dock_id``, or at ``dock_pose`` (Nav2's DockRobot)."""
        return self.docking.dock_robot(dock_id, dock_pose, navigate_to_staging_pose=staging)

    def undock_robot(self) -> TaskHandle:
        """Back out of the dock to its staging pose (Nav2's UndockRobot)."""
        return self.docking.undock_robot()

    def follow_object(self, topic: str, frame: str, max_duration: float) -> TaskHandle:
        """Keep the desired distance from a moving object (Nav2's FollowObject)."""
        return self.following.follow_object(topic, frame, max_duration)


def plug_in(
    host: PluginHost,
    sim: Simulation,
    lidar: ScanSource | None,
    world: World,
    params: PluggedParams,
) -> tuple[DockingServer, FollowingServer]:
    """The docking and following servers of ``host``, registered there (module docstring)."""
    docking_server = DockingServer(host, lidar, world.docks, params.docking)
    poses = ObjectPoses(sim, world.moving_objects, lidar)
    period = 1.0 / host.params.controller.controller_frequency
    following = params.following
    following_server = FollowingServer(host.base, host.tasks, poses, following, period=period)
    host.action_servers.update(docking_server.action_servers())
    host.action_servers[FOLLOW_ACTION] = following_server
    host.services[RELOAD_DATABASE] = docking_server.reload_database
    return docking_server, following_server


__all__ = ["PluggedParams", "PluggedServerTasks", "PluginHost", "plug_in"]
