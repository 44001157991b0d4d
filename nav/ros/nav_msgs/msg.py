"""``nav_msgs.msg``: odometry, paths, goal lists and occupancy grids."""

from __future__ import annotations

from baobab.nav.msgs import (
    Goals,
    Header,
    MapMetaData,
    OccupancyGrid,
    Path,
    PoseWithCovariance,
)
from baobab.nav.ros.geometry_msgs.msg import TwistWithCovariance
from baobab.nav.rosmsg import Message

__all__ = ["Goals", "MapMetaData", "OccupancyGrid", "Odometry", "Path"]


class Odometry(Message):
    """``nav_msgs/Odometry``: the pose in ``header.frame_id``, the twist in ``child_frame_id``."""

    _type_name = "nav_msgs/msg/Odometry"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "child_frame_id": "string",
        "pose": "geometry_msgs/PoseWithCovariance",
        "twist": "geometry_msgs/TwistWithCovariance",
    }
    header: Header
    child_frame_id: str
    pose: PoseWithCovariance
    twist: TwistWithCovariance
