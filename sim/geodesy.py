"""Geographic poses to the map frame, through a local tangent plane at the world's datum.

What robot_localization's ``navsat_transform`` answers on ``fromLL`` / ``toLL`` with a fixed
datum and ``use_local_cartesian``: a WGS84 latitude, longitude and altitude become East, North,
Up coordinates in the plane tangent to the ellipsoid at the datum (geodetic -> ECEF ->
ENU, exact, no map projection), and the map frame is that plane turned by the datum's heading
(the ENU yaw of the map's x axis). The conversions are pymap3d's (``geodetic2enu``,
``enu2geodetic``): pure Python, kept, tested against published geodetic and ECEF pairs.
pyproj would do the same through PROJ's ``topocentric`` pipeline at the price of a compiled
library and its data files; a plane tangent at one point needs neither.

An unknown altitude (NaN, as ``geographic_msgs/GeoPoint`` allows) is taken as the datum's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from baobab.sim.datum import Datum
from baobab.sim.errors import BaobabError

WGS84 = "wgs84"
"""The ellipsoid of GPS fixes (and of robot_localization)."""


class GeodesyError(BaobabError, ValueError):
    """A geographic point that cannot be converted (out of range or not a number)."""


@dataclass(frozen=True)
class GeoWaypoint:
    """A geographic waypoint: ``latitude``, ``longitude`` (deg, WGS84), ``yaw`` (rad, the
    heading a ``GeoPose`` orientation carries), ``altitude`` (m above the ellipsoid, NaN:
    the datum's)."""

    latitude: float
    longitude: float
    yaw: float = 0.0
    altitude: float = math.nan


def check_geodetic(latitude: float, longitude: float) -> None:
    """Refuse a latitude outside -90..90 or a longitude outside -180..180 (deg).

    Raises:
        GeodesyError: naming the value and its range.
    """
    if not (math.isfinite(latitude) and -90.0 <= latitude <= 90.0):
        raise GeodesyError(f"latitude {latitude} is outside -90..90 degrees")
    if not (math.isfinite(longitude) and -180.0 <= longitude <= 180.0):
        raise GeodesyError(f"longitude {longitude} is outside -180..180 degrees")


def geodetic_to_enu(
    latitude: float,
    longitude: float,
    altitude: float,
    origin: tuple[float, float, float],
    ellipsoid: str = WGS84,
) -> tuple[float, float, float]:
    """East, North, Up (m) of a point (deg, deg, m) from ``origin`` (lat, lon deg; alt m).

    Raises:
        GeodesyError: a coordinate out of range.
    """
    import pymap3d  # ~0.2 s to import: only when a conversion is asked for

    check_geodetic(latitude, longitude)
    shape = pymap3d.Ellipsoid.from_name(ellipsoid)
    east, north, up = pymap3d.geodetic2enu(
        latitude, longitude, altitude, *origin, ell=shape, deg=True
    )
    return float(east), float(north), float(up)


@dataclass(frozen=True)
class MapDatum:
    """The map frame of a world placed on the Earth by its datum."""

    datum: Datum

    @property
    def origin(self) -> tuple[float, float, float]:
        """The datum's latitude, longitude (deg) and altitude (m)."""
        return (self.datum.latitude, self.datum.longitude, self.datum.altitude)

    def to_map(
        self, latitude: float, longitude: float, altitude: float = math.nan
    ) -> tuple[float, float]:
        """Map x, y (m) of a WGS84 point (deg; altitude m above the ellipsoid, NaN unknown).

        Raises:
            GeodesyError: a coordinate out of range or not finite.
        """
        height = self.datum.altitude if math.isnan(altitude) else altitude
        if not math.isfinite(height):
            raise GeodesyError(f"altitude {altitude} is not a finite number")
        east, north, _ = geodetic_to_enu(latitude, longitude, height, self.origin)
        heading = self.datum.heading
        cos, sin = math.cos(heading), math.sin(heading)
        return cos * east + sin * north, -sin * east + cos * north

    def to_geodetic(self, x: float, y: float) -> tuple[float, float, float]:
        """Latitude, longitude (deg) and altitude (m) of map point (x, y) (m) on the plane."""
        import pymap3d

        heading = self.datum.heading
        cos, sin = math.cos(heading), math.sin(heading)
        east, north = cos * x - sin * y, sin * x + cos * y
        shape = pymap3d.Ellipsoid.from_name(WGS84)
        latitude, longitude, altitude = pymap3d.enu2geodetic(
            east, north, 0.0, *self.origin, ell=shape, deg=True
        )
        return float(latitude), float(longitude), float(altitude)
