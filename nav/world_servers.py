"""The action servers a world brings: routes on its route graph, GPS waypoints at its datum.

:func:`attach_world_servers` plugs them into a navigation server's ``action_servers`` (the
mission runner and ``BasicNavigator`` call it on the server they build, the mission runner
with the mission's own route graph where it has one). A world without a ``route_graph`` or a
``datum`` gets neither, and the navigator's ``getRoute`` / ``followGpsWaypoints`` fail cleanly
as before.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from baobab.nav.gps_waypoints import GpsWaypointFollower
from baobab.nav.route_drive import register_route_driving
from baobab.nav.route_server import RouteServer
from baobab.sim.route_graph_file import RouteGraph
from baobab.sim.world import World

if TYPE_CHECKING:
    from baobab.nav.server import NavigationServer


@dataclass(frozen=True)
class WorldServers:
    """The servers :func:`attach_world_servers` plugged in (None: nothing to serve)."""

    routes: RouteServer | None = None
    gps: GpsWaypointFollower | None = None


def attach_world_servers(
    navigation: NavigationServer, world: World, *, route_graph: RouteGraph | None = None
) -> WorldServers:
    """Register the route server (``route_graph``, else the world's) and the GPS waypoint
    follower (the world's datum) where there is something for them to serve."""
    graph = route_graph if route_graph is not None else world.routes
    routes = gps = None
    if graph is not None:
        routes = RouteServer(navigation, graph)
        routes.register()
        register_route_driving(routes)
    if world.datum is not None:
        gps = GpsWaypointFollower(navigation, world.datum)
        gps.register()
    return WorldServers(routes, gps)
