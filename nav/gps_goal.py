"""A FollowGPSWaypoints goal as plain values: what a mission leaf sends to the GPS waypoint
follower through the navigation server, without building ROS messages."""

from __future__ import annotations

from dataclasses import dataclass, field

from baobab.sim.geodesy import GeoWaypoint


@dataclass(frozen=True)
class GpsGoal:
    """A FollowGPSWaypoints goal without ROS messages (the navigation server's
    ``follow_gps_waypoints``): the waypoints, ``number_of_loops`` and ``goal_index``."""

    waypoints: list[GeoWaypoint] = field(default_factory=list)
    number_of_loops: int = 0
    goal_index: int = 0
