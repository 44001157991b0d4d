"""The ``follow_gps_waypoints`` leaf: Nav2's FollowGPSWaypoints over the world's datum.

Each waypoint is a WGS84 ``latitude`` and ``longitude`` (deg) with a heading ``yaw`` (rad) or
``yaw_deg``, which Nav2 copies unchanged into the map frame. The navigation server converts
the waypoints through the local tangent plane at the world's ``datum`` and navigates to each
in turn (:mod:`baobab.nav.gps_waypoints`). While the mission loads, every waypoint is
converted the same way and must land on the floor, clear of obstacles by the robot's
footprint; a world without a datum is refused.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Annotated

from pydantic import ConfigDict, Field, ValidationInfo, model_validator

from baobab.behaviours.ports import NAVIGATION
from baobab.behaviours.poses import MissionScope, Pose
from baobab.behaviours.registry import BehaviourType, BuildRequest, NodeKind, NodeParams
from baobab.sim.datum import Latitude, Longitude
from baobab.sim.yaml_models import YamlModel
from baobab.sim.yaml_source import FieldValueError

if TYPE_CHECKING:  # imported by the factory, when a tree is built (validation needs none)
    import py_trees

    from baobab.sim.geodesy import GeoWaypoint

Finite = Annotated[float, Field(allow_inf_nan=False)]


class GpsWaypoint(YamlModel):
    """A geographic waypoint: WGS84 ``latitude``, ``longitude`` (deg), map heading."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    latitude: Latitude = Field(description="deg, north positive")
    longitude: Longitude = Field(description="deg, east positive")
    altitude: Finite | None = Field(
        default=None, description="m above the WGS84 ellipsoid; default: the datum's"
    )
    yaw: Finite | None = Field(default=None, description="heading in the map frame (rad)")
    yaw_deg: Finite | None = Field(default=None, description="heading (deg), instead of yaw")

    @model_validator(mode="after")
    def _one_heading(self) -> GpsWaypoint:
        if self.yaw is not None and self.yaw_deg is not None:
            raise FieldValueError(("yaw_deg",), "give either yaw (rad) or yaw_deg (deg), not both")
        return self

    @property
    def heading(self) -> float:
        """The heading (rad)."""
        return math.radians(self.yaw_deg) if self.yaw_deg is not None else (self.yaw or 0.0)

    def geo(self) -> GeoWaypoint:
        """The navigation stack's waypoint."""
        from baobab.sim.geodesy import GeoWaypoint

        altitude = math.nan if self.altitude is None else self.altitude
        return GeoWaypoint(self.latitude, self.longitude, self.heading, altitude)


class FollowGpsWaypointsParams(NodeParams):
    """Navigate to each GPS waypoint in turn (FollowGPSWaypoints)."""

    waypoints: list[GpsWaypoint] = Field(
        min_length=1, description="{latitude, longitude, yaw | yaw_deg}, in order"
    )

    @model_validator(mode="after")
    def _on_the_floor(self, info: ValidationInfo) -> FollowGpsWaypointsParams:
        scope = MissionScope.of(info)
        world = scope.world
        if world is None:
            return self
        if world.datum is None:
            raise FieldValueError(
                ("waypoints",),
                f"world '{world.name}' has no datum; GPS waypoints need one (datum: {{latitude, "
                "longitude, heading}} in the world file)",
            )
        from baobab.sim.geodesy import MapDatum  # pymap3d: only for missions with GPS

        plane = MapDatum(world.datum)
        for index, waypoint in enumerate(self.waypoints):
            geo = waypoint.geo()
            x, y = plane.to_map(geo.latitude, geo.longitude, geo.altitude)
            problem = scope.free_space_problem(Pose.from_planar(x, y, geo.yaw))
            if problem is not None:
                raise FieldValueError(
                    ("waypoints", index),
                    f"GPS waypoint ({waypoint.latitude}, {waypoint.longitude}) lands at map "
                    f"({x:.2f}, {y:.2f}): {problem}",
                )
        return self

    def summary(self) -> str:
        """``4 GPS waypoints``."""
        count = len(self.waypoints)
        return f"{count} GPS waypoint{'s' if count != 1 else ''}"


def _follow_gps_waypoints(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    waypoints = [
        waypoint.geo() for waypoint in request.params_as(FollowGpsWaypointsParams).waypoints
    ]
    return request.goal_task(lambda caps: caps.navigation_port().follow_gps_waypoints(waypoints))


NODE_TYPES = (
    BehaviourType(
        "follow_gps_waypoints",
        NodeKind.ACTION,
        FollowGpsWaypointsParams,
        "navigate to geographic waypoints in turn, through the world's datum",
        _follow_gps_waypoints,
        capability=NAVIGATION,
        shorthand="waypoints",
    ),
)
"""The GPS waypoint node types."""
