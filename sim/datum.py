"""A world's datum: where on Earth its map frame lies, for GPS waypoints.

``datum: {latitude, longitude, heading}`` places the map origin at a WGS84 point and says which
way the map's x axis points: ``heading`` (rad, or ``heading_deg``) is an ENU yaw, 0 = east,
counter-clockwise positive (+pi/2 = north), as robot_localization's ``datum: [lat, lon,
heading]`` parameter means it. ``altitude`` is the origin's height above the WGS84 ellipsoid
(m, default 0). Values outside their ranges are located errors in the world file.
"""

from __future__ import annotations

import math
from typing import Annotated

from pydantic import ConfigDict, Field, model_validator

from baobab.sim.yaml_models import YamlModel, degrees_in_place

MIN_ALTITUDE = -11_000.0
"""Lowest datum altitude (m above the ellipsoid): below the deepest ocean trench."""
MAX_ALTITUDE = 20_000.0
"""Highest datum altitude (m): well above any mountain."""


Latitude = Annotated[float, Field(ge=-90, le=90, allow_inf_nan=False)]
"""A WGS84 latitude (deg, north positive) as YAML models check it."""
Longitude = Annotated[float, Field(ge=-180, le=180, allow_inf_nan=False)]
"""A WGS84 longitude (deg, east positive) as YAML models check it."""


class Datum(YamlModel):
    """The map origin's latitude and longitude (deg, WGS84), ENU heading and altitude."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    latitude: Latitude = Field(description="deg, north positive, -90..90")
    longitude: Longitude = Field(description="deg, east positive, -180..180")
    heading: Annotated[float, Field(ge=-math.tau, le=math.tau, allow_inf_nan=False)] = Field(
        default=0.0, description="ENU yaw of the map's x axis (rad): 0 east, pi/2 north"
    )
    altitude: Annotated[float, Field(ge=MIN_ALTITUDE, le=MAX_ALTITUDE, allow_inf_nan=False)] = (
        Field(default=0.0, description="m above the WGS84 ellipsoid")
    )

    @model_validator(mode="before")
    @classmethod
    def _degrees(cls, value: object) -> object:
        both = "give either heading (radians) or heading_deg, not both"
        return degrees_in_place(value, "heading", both, limit=360)
