"""``sensor_msgs.msg``: laser scans, joint states and IMU readings."""

from __future__ import annotations

from array import array

import numpy as np

from baobab.nav.msgs import Header, Quaternion, Vector3
from baobab.nav.rosmsg import Message

__all__ = ["Imu", "JointState", "LaserScan"]


class LaserScan(Message):
    """``sensor_msgs/LaserScan``: ranges (m) at angles (rad, counter-clockwise, 0 ahead)."""

    _type_name = "sensor_msgs/msg/LaserScan"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "angle_min": "float",
        "angle_max": "float",
        "angle_increment": "float",
        "time_increment": "float",
        "scan_time": "float",
        "range_min": "float",
        "range_max": "float",
        "ranges": "sequence<float>",
        "intensities": "sequence<float>",
    }
    header: Header
    angle_min: float
    angle_max: float
    angle_increment: float
    time_increment: float
    scan_time: float
    range_min: float
    range_max: float
    ranges: array[float]
    intensities: array[float]


class JointState(Message):
    """``sensor_msgs/JointState``: per joint name, position (rad or m), velocity and effort."""

    _type_name = "sensor_msgs/msg/JointState"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "name": "sequence<string>",
        "position": "sequence<double>",
        "velocity": "sequence<double>",
        "effort": "sequence<double>",
    }
    header: Header
    name: list[str]
    position: array[float]
    velocity: array[float]
    effort: array[float]


class Imu(Message):
    """``sensor_msgs/Imu``: orientation, angular velocity (rad/s), linear acceleration (m/s^2).

    A covariance whose first element is -1 means "no estimate" of that quantity.
    """

    _type_name = "sensor_msgs/msg/Imu"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "orientation": "geometry_msgs/Quaternion",
        "orientation_covariance": "double[9]",
        "angular_velocity": "geometry_msgs/Vector3",
        "angular_velocity_covariance": "double[9]",
        "linear_acceleration": "geometry_msgs/Vector3",
        "linear_acceleration_covariance": "double[9]",
    }
    header: Header
    orientation: Quaternion
    orientation_covariance: np.ndarray
    angular_velocity: Vector3
    angular_velocity_covariance: np.ndarray
    linear_acceleration: Vector3
    linear_acceleration_covariance: np.ndarray
