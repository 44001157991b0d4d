"""``geographic_msgs.msg``: points and poses on the WGS84 ellipsoid (what GPS waypoints are)."""

from __future__ import annotations

from baobab.nav.msgs import Header, Quaternion
from baobab.nav.rosmsg import Message

__all__ = ["GeoPoint", "GeoPose", "GeoPoseStamped"]


class GeoPoint(Message):
    """``geographic_msgs/GeoPoint``: latitude and longitude (deg), altitude (m, NaN unknown)."""

    _type_name = "geographic_msgs/msg/GeoPoint"
    _fields_and_field_types = {"latitude": "double", "longitude": "double", "altitude": "double"}
    latitude: float
    longitude: float
    altitude: float


class GeoPose(Message):
    """``geographic_msgs/GeoPose``: a position and an ENU orientation (yaw 0 faces east)."""

    _type_name = "geographic_msgs/msg/GeoPose"
    _fields_and_field_types = {
        "position": "geographic_msgs/GeoPoint",
        "orientation": "geometry_msgs/Quaternion",
    }
    position: GeoPoint
    orientation: Quaternion


class GeoPoseStamped(Message):
    """``geographic_msgs/GeoPoseStamped``."""

    _type_name = "geographic_msgs/msg/GeoPoseStamped"
    _fields_and_field_types = {"header": "std_msgs/Header", "pose": "geographic_msgs/GeoPose"}
    header: Header
    pose: GeoPose
