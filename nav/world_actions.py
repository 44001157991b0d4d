"""The navigation server's tasks served by a world's own servers: routes and GPS waypoints.

:class:`WorldActions` gives :class:`~baobab.nav.server.NavigationServer` the
``NavigationPort`` methods ``follow_route`` and ``follow_gps_waypoints``: each sends its goal
to the server :mod:`baobab.nav.world_servers` registered under the action's name, and a world
without a route graph or a datum rejects the goal (``GoalRejectedError``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from baobab.nav.errors import GoalRejectedError
from baobab.nav.gps_goal import GpsGoal
from baobab.nav.interfaces import ActionServer
from baobab.nav.route_requests import RouteRequest
from baobab.sim.geodesy import GeoWaypoint
from baobab.sim.tasks import TaskHandle
from baobab.sim.world import Pose2D


class WorldActions:
    """Route driving and GPS waypoints, sent to the servers in ``action_servers``."""

    action_servers: dict[str, ActionServer]

    def follow_route(self, start: int | Pose2D | None, goal: int | Pose2D) -> TaskHandle:
        """Drive the route graph from ``start`` to ``goal`` (:meth:`RouteRequest.between`)."""
        return self._world_action("follow_route", "route graph", RouteRequest.between(start, goal))

    def follow_gps_waypoints(self, waypoints: Sequence[GeoWaypoint]) -> TaskHandle:
        """Follow geographic waypoints in turn through the world's datum (FollowGPSWaypoints)."""
        return self._world_action("follow_gps_waypoints", "datum", GpsGoal(list(waypoints)))

    def _world_action(self, name: str, needs: str, goal: Any) -> TaskHandle:
        server = self.action_servers.get(name)
        if server is None:
            raise GoalRejectedError(f"'{name}' needs a world with a {needs}; this one has none")
        return server.send_goal(goal)
