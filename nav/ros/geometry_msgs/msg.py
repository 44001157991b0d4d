"""``geometry_msgs.msg``: points, vectors, quaternions, poses, transforms, twists, wrenches."""

from __future__ import annotations

import numpy as np

from baobab.nav.msgs import (
    Header,
    Point,
    Pose,
    PoseStamped,
    PoseWithCovariance,
    PoseWithCovarianceStamped,
    Quaternion,
    Twist,
    TwistStamped,
    Vector3,
)
from baobab.nav.rosmsg import Message

__all__ = [
    "Accel",
    "AccelStamped",
    "Point",
    "Point32",
    "PointStamped",
    "Polygon",
    "Pose",
    "Pose2D",
    "PoseArray",
    "PoseStamped",
    "PoseWithCovariance",
    "PoseWithCovarianceStamped",
    "Quaternion",
    "QuaternionStamped",
    "Transform",
    "TransformStamped",
    "Twist",
    "TwistStamped",
    "TwistWithCovariance",
    "TwistWithCovarianceStamped",
    "Vector3",
    "Vector3Stamped",
    "Wrench",
    "WrenchStamped",
]


class Point32(Message):
    """``geometry_msgs/Point32`` (m, single precision)."""

    _type_name = "geometry_msgs/msg/Point32"
    _fields_and_field_types = {"x": "float", "y": "float", "z": "float"}
    x: float
    y: float
    z: float


class Pose2D(Message):
    """``geometry_msgs/Pose2D``: x, y (m) and theta (rad)."""

    _type_name = "geometry_msgs/msg/Pose2D"
    _fields_and_field_types = {"x": "double", "y": "double", "theta": "double"}
    x: float
    y: float
    theta: float


class PointStamped(Message):
    """``geometry_msgs/PointStamped``."""

    _type_name = "geometry_msgs/msg/PointStamped"
    _fields_and_field_types = {"header": "std_msgs/Header", "point": "geometry_msgs/Point"}
    header: Header
    point: Point


class Vector3Stamped(Message):
    """``geometry_msgs/Vector3Stamped``."""

    _type_name = "geometry_msgs/msg/Vector3Stamped"
    _fields_and_field_types = {"header": "std_msgs/Header", "vector": "geometry_msgs/Vector3"}
    header: Header
    vector: Vector3


class QuaternionStamped(Message):
    """``geometry_msgs/QuaternionStamped``."""

    _type_name = "geometry_msgs/msg/QuaternionStamped"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "quaternion": "geometry_msgs/Quaternion",
    }
    header: Header
    quaternion: Quaternion


class Polygon(Message):
    """``geometry_msgs/Polygon``."""

    _type_name = "geometry_msgs/msg/Polygon"
    _fields_and_field_types = {"points": "sequence<geometry_msgs/Point32>"}
    points: list[Point32]


class PoseArray(Message):
    """``geometry_msgs/PoseArray``."""

    _type_name = "geometry_msgs/msg/PoseArray"
    _fields_and_field_types = {"header": "std_msgs/Header", "poses": "sequence<geometry_msgs/Pose>"}
    header: Header
    poses: list[Pose]


class Transform(Message):
    """``geometry_msgs/Transform``: a translation (m) and a rotation."""

    _type_name = "geometry_msgs/msg/Transform"
    _fields_and_field_types = {
        "translation": "geometry_msgs/Vector3",
        "rotation": "geometry_msgs/Quaternion",
    }
    translation: Vector3
    rotation: Quaternion


class TransformStamped(Message):
    """``geometry_msgs/TransformStamped``: ``child_frame_id`` in ``header.frame_id``."""

    _type_name = "geometry_msgs/msg/TransformStamped"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "child_frame_id": "string",
        "transform": "geometry_msgs/Transform",
    }
    header: Header
    child_frame_id: str
    transform: Transform


class TwistWithCovariance(Message):
    """``geometry_msgs/TwistWithCovariance``: a twist and its row-major 6x6 covariance."""

    _type_name = "geometry_msgs/msg/TwistWithCovariance"
    _fields_and_field_types = {"twist": "geometry_msgs/Twist", "covariance": "double[36]"}
    twist: Twist
    covariance: np.ndarray


class TwistWithCovarianceStamped(Message):
    """``geometry_msgs/TwistWithCovarianceStamped``."""

    _type_name = "geometry_msgs/msg/TwistWithCovarianceStamped"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "twist": "geometry_msgs/TwistWithCovariance",
    }
    header: Header
    twist: TwistWithCovariance


class Accel(Message):
    """``geometry_msgs/Accel``: linear (m/s^2) and angular (rad/s^2) acceleration."""

    _type_name = "geometry_msgs/msg/Accel"
    _fields_and_field_types = {
        "linear": "geometry_msgs/Vector3",
        "angular": "geometry_msgs/Vector3",
    }
    linear: Vector3
    angular: Vector3


class AccelStamped(Message):
    """``geometry_msgs/AccelStamped``."""

    _type_name = "geometry_msgs/msg/AccelStamped"
    _fields_and_field_types = {"header": "std_msgs/Header", "accel": "geometry_msgs/Accel"}
    header: Header
    accel: Accel


class Wrench(Message):
    """``geometry_msgs/Wrench``: force (N) and torque (N m)."""

    _type_name = "geometry_msgs/msg/Wrench"
    _fields_and_field_types = {"force": "geometry_msgs/Vector3", "torque": "geometry_msgs/Vector3"}
    force: Vector3
    torque: Vector3


class WrenchStamped(Message):
    """``geometry_msgs/WrenchStamped``."""

    _type_name = "geometry_msgs/msg/WrenchStamped"
    _fields_and_field_types = {"header": "std_msgs/Header", "wrench": "geometry_msgs/Wrench"}
    header: Header
    wrench: Wrench
