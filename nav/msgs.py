"""ROS 2 message types for the Nav2-style facade, with ROS's field names and defaults.

Messages are mutable and built field by field as in rclpy
(``goal.pose.position.x = 1.0``); constructors take keyword arguments only, and a misspelt
field raises ``AttributeError`` (slots), as generated ROS messages do, and a value of the wrong
type raises ``AssertionError`` as theirs do (``point.x = 1`` needs ``1.0``;
:mod:`baobab.nav.rosmsg`). A fresh
:class:`Quaternion` is the identity (``w = 1.0``); a fresh :class:`Header` has a zero stamp and
an empty ``frame_id``. Quaternions are ``x, y, z, w``.

``Time`` and ``Duration`` here are rclpy's rich classes (``rclpy.time.Time``,
``rclpy.duration.Duration``); the ``builtin_interfaces`` messages that header stamps and
feedback fields hold are :class:`TimeMsg` and :class:`DurationMsg` (see
:mod:`baobab.nav.rostime`).

The helpers at the end convert between :class:`PoseStamped` and the simulator's
:class:`~baobab.sim.world.Pose2D`.
"""

from __future__ import annotations

import math
from array import array

import numpy as np
from scipy.spatial.transform import Rotation

from baobab.nav.rosmsg import Message
from baobab.nav.rostime import ClockType, Duration, DurationMsg, Time, TimeMsg
from baobab.sim.errors import BaobabError
from baobab.sim.world import Pose2D

__all__ = [
    "ClockType",
    "Costmap",
    "CostmapMetaData",
    "Duration",
    "DurationMsg",
    "Goals",
    "Header",
    "MapMetaData",
    "MessageValueError",
    "OccupancyGrid",
    "Path",
    "Point",
    "Pose",
    "PoseStamped",
    "PoseWithCovariance",
    "PoseWithCovarianceStamped",
    "Quaternion",
    "Time",
    "TimeMsg",
    "Twist",
    "TwistStamped",
    "Vector3",
    "from_pose2d",
    "pose_stamped",
    "quaternion_from_yaw",
    "stamped_poses",
    "to_pose2d",
    "yaw_from_quaternion",
    "yaws_from_quaternions",
]


class MessageValueError(BaobabError, ValueError):
    """A message holds a value with no meaning, such as a zero or non-finite quaternion."""


# --- std_msgs -------------------------------------------------------------------------------


class Header(Message):
    """``std_msgs/Header``: when (``stamp``) and in which frame (``frame_id``) data holds."""

    _type_name = "std_msgs/msg/Header"
    _fields_and_field_types = {"stamp": "builtin_interfaces/Time", "frame_id": "string"}
    stamp: TimeMsg
    frame_id: str


# --- geometry_msgs --------------------------------------------------------------------------


class Point(Message):
    """``geometry_msgs/Point`` (m)."""

    _type_name = "geometry_msgs/msg/Point"
    _fields_and_field_types = {"x": "double", "y": "double", "z": "double"}
    x: float
    y: float
    z: float


class Vector3(Message):
    """``geometry_msgs/Vector3`` (units of the field that holds it)."""

    _type_name = "geometry_msgs/msg/Vector3"
    _fields_and_field_types = {"x": "double", "y": "double", "z": "double"}
    x: float
    y: float
    z: float


class Quaternion(Message):
    """``geometry_msgs/Quaternion``, ``x, y, z, w``; the default is the identity."""

    _type_name = "geometry_msgs/msg/Quaternion"
    _fields_and_field_types = {"x": "double", "y": "double", "z": "double", "w": "double"}
    _defaults = {"w": 1.0}
    x: float
    y: float
    z: float
    w: float


class Pose(Message):
    """``geometry_msgs/Pose``: a position (m) and an orientation."""

    _type_name = "geometry_msgs/msg/Pose"
    _fields_and_field_types = {
        "position": "geometry_msgs/Point",
        "orientation": "geometry_msgs/Quaternion",
    }
    position: Point
    orientation: Quaternion


class PoseStamped(Message):
    """``geometry_msgs/PoseStamped``: a pose in ``header.frame_id`` at ``header.stamp``."""

    _type_name = "geometry_msgs/msg/PoseStamped"
    _fields_and_field_types = {"header": "std_msgs/Header", "pose": "geometry_msgs/Pose"}
    header: Header
    pose: Pose


class PoseWithCovariance(Message):
    """``geometry_msgs/PoseWithCovariance``: a pose and its row-major 6x6 covariance."""

    _type_name = "geometry_msgs/msg/PoseWithCovariance"
    _fields_and_field_types = {"pose": "geometry_msgs/Pose", "covariance": "double[36]"}
    pose: Pose
    covariance: np.ndarray


class PoseWithCovarianceStamped(Message):
    """``geometry_msgs/PoseWithCovarianceStamped`` (what Nav2's ``initialpose`` carries)."""

    _type_name = "geometry_msgs/msg/PoseWithCovarianceStamped"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "pose": "geometry_msgs/PoseWithCovariance",
    }
    header: Header
    pose: PoseWithCovariance


class Twist(Message):
    """``geometry_msgs/Twist``: linear (m/s) and angular (rad/s) velocity."""

    _type_name = "geometry_msgs/msg/Twist"
    _fields_and_field_types = {
        "linear": "geometry_msgs/Vector3",
        "angular": "geometry_msgs/Vector3",
    }
    linear: Vector3
    angular: Vector3


class TwistStamped(Message):
    """``geometry_msgs/TwistStamped``."""

    _type_name = "geometry_msgs/msg/TwistStamped"
    _fields_and_field_types = {"header": "std_msgs/Header", "twist": "geometry_msgs/Twist"}
    header: Header
    twist: Twist


# --- nav_msgs -------------------------------------------------------------------------------


class Path(Message):
    """``nav_msgs/Path``: poses a robot should follow, in order."""

    _type_name = "nav_msgs/msg/Path"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "poses": "sequence<geometry_msgs/PoseStamped>",
    }
    header: Header
    poses: list[PoseStamped]


class Goals(Message):
    """``nav_msgs/Goals``: the goal list Rolling's ``goThroughPoses`` takes."""

    _type_name = "nav_msgs/msg/Goals"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "goals": "sequence<geometry_msgs/PoseStamped>",
    }
    header: Header
    goals: list[PoseStamped]


class MapMetaData(Message):
    """``nav_msgs/MapMetaData``: grid size (cells), cell size (m) and the pose of cell (0, 0)."""

    _type_name = "nav_msgs/msg/MapMetaData"
    _fields_and_field_types = {
        "map_load_time": "builtin_interfaces/Time",
        "resolution": "float",
        "width": "uint32",
        "height": "uint32",
        "origin": "geometry_msgs/Pose",
    }
    map_load_time: TimeMsg
    resolution: float
    width: int
    height: int
    origin: Pose


class OccupancyGrid(Message):
    """``nav_msgs/OccupancyGrid``: row-major int8 occupancy, 0..100 or -1 for unknown.

    ``data[i + width * j]`` is cell column ``i``, row ``j``; ``numpy.frombuffer(grid.data,
    dtype=numpy.int8)`` views it without a copy.
    """

    _type_name = "nav_msgs/msg/OccupancyGrid"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "info": "nav_msgs/MapMetaData",
        "data": "sequence<int8>",
    }
    header: Header
    info: MapMetaData
    data: array[int]


# --- nav2_msgs ------------------------------------------------------------------------------


class CostmapMetaData(Message):
    """``nav2_msgs/CostmapMetaData``: grid size (cells), cell size (m), origin, layer name."""

    _type_name = "nav2_msgs/msg/CostmapMetaData"
    _fields_and_field_types = {
        "map_load_time": "builtin_interfaces/Time",
        "update_time": "builtin_interfaces/Time",
        "layer": "string",
        "resolution": "float",
        "size_x": "uint32",
        "size_y": "uint32",
        "origin": "geometry_msgs/Pose",
    }
    map_load_time: TimeMsg
    update_time: TimeMsg
    layer: str
    resolution: float
    size_x: int
    size_y: int
    origin: Pose


class Costmap(Message):
    """``nav2_msgs/Costmap``: row-major uint8 costs.

    0 is free, 253 inscribed, 254 lethal, 255 unknown; ``data[i + size_x * j]`` is cell
    column ``i``, row ``j``.
    """

    _type_name = "nav2_msgs/msg/Costmap"
    _fields_and_field_types = {
        "header": "std_msgs/Header",
        "metadata": "nav2_msgs/CostmapMetaData",
        "data": "sequence<uint8>",
    }
    header: Header
    metadata: CostmapMetaData
    data: array[int]


# --- conversions ----------------------------------------------------------------------------


def quaternion_from_yaw(yaw: float) -> Quaternion:
    """The quaternion of a rotation by ``yaw`` (rad) about +z: ``z = sin(yaw/2), w = cos(yaw/2)``
    (what scipy's ``Rotation.from_euler("z", yaw)`` gives, without its per-call cost)."""
    half = 0.5 * float(yaw)
    return Quaternion.unchecked(x=0.0, y=0.0, z=math.sin(half), w=math.cos(half))


def yaw_from_quaternion(q: Quaternion) -> float:
    """The heading (rad, in ``[-pi, pi]``) of ``q`` after normalising it.

    The heading is the first angle of the z-y'-x'' (yaw-pitch-roll) decomposition, as
    ``tf2::getYaw`` computes it; ``q`` and ``-q`` give the same heading.

    Raises:
        MessageValueError: ``q`` has a non-finite component or zero norm.
    """
    components = (q.x, q.y, q.z, q.w)
    if not all(math.isfinite(c) for c in components):
        raise MessageValueError(f"quaternion {components} has a non-finite component")
    if math.hypot(*components) < 1e-9:
        raise MessageValueError(f"quaternion {components} has zero norm; it is no rotation")
    return float(Rotation.from_quat(components).as_euler("ZYX")[0])


def _stamp_msg(stamp: TimeMsg | Time | None) -> TimeMsg:
    if stamp is None:
        return TimeMsg()
    if isinstance(stamp, Time):
        return stamp.to_msg()
    return TimeMsg(sec=stamp.sec, nanosec=stamp.nanosec)


def pose_stamped(
    x: float,
    y: float,
    yaw: float = 0.0,
    frame_id: str = "map",
    stamp: TimeMsg | Time | None = None,
) -> PoseStamped:
    """A planar :class:`PoseStamped` at ``(x, y)`` (m) facing ``yaw`` (rad).

    ``stamp`` may be a message or an rclpy-style :class:`Time`; ``None`` is the zero stamp.
    """
    position = Point.unchecked(x=float(x), y=float(y), z=0.0)
    return PoseStamped.unchecked(
        header=Header(stamp=_stamp_msg(stamp), frame_id=frame_id),
        pose=Pose.unchecked(position=position, orientation=quaternion_from_yaw(yaw)),
    )


def stamped_poses(
    poses: np.ndarray, frame_id: str = "map", stamp: TimeMsg | Time | None = None
) -> list[PoseStamped]:
    """The :class:`PoseStamped` of each ``(x, y, yaw)`` row of ``poses`` (m, m, rad), all
    stamped ``stamp``: :func:`pose_stamped` over an array, the quaternions computed at once.

    Raises:
        MessageValueError: a non-finite value.
    """
    rows = np.asarray(poses, dtype=float).reshape(-1, 3)
    if not np.isfinite(rows).all():
        raise MessageValueError("poses must be finite")
    half = 0.5 * rows[:, 2]
    columns = np.column_stack([rows[:, :2], np.sin(half), np.cos(half)])
    stamp_msg = _stamp_msg(stamp)
    sec, nanosec = stamp_msg.sec, stamp_msg.nanosec
    return [
        PoseStamped.unchecked(
            header=Header.unchecked(
                stamp=TimeMsg.unchecked(sec=sec, nanosec=nanosec), frame_id=frame_id
            ),
            pose=Pose.unchecked(
                position=Point.unchecked(x=x, y=y, z=0.0),
                orientation=Quaternion.unchecked(x=0.0, y=0.0, z=z, w=w),
            ),
        )
        for x, y, z, w in columns.tolist()
    ]


def yaws_from_quaternions(quaternions: np.ndarray) -> np.ndarray:
    """:func:`yaw_from_quaternion` of each ``(x, y, z, w)`` row of ``quaternions`` (rad).

    Raises:
        MessageValueError: a row with a non-finite component or zero norm (the first is named).
    """
    rows = np.asarray(quaternions, dtype=float).reshape(-1, 4)
    bad = ~np.isfinite(rows).all(axis=1) | (np.linalg.norm(rows, axis=1) < 1e-9)
    if bad.any():
        x, y, z, w = rows[int(np.argmax(bad))].tolist()
        yaw_from_quaternion(Quaternion(x=x, y=y, z=z, w=w))  # raises, saying what is wrong
    if len(rows) == 0:
        return np.zeros(0)
    return np.asarray(Rotation.from_quat(rows).as_euler("ZYX")[:, 0], dtype=float)


def to_pose2d(pose: Pose | PoseStamped) -> Pose2D:
    """The planar pose (x, y in m, yaw in rad) of a :class:`Pose` or :class:`PoseStamped`.

    ``z`` is dropped and the quaternion is normalised; the frame is not checked (callers that
    care compare ``header.frame_id`` themselves).

    Raises:
        MessageValueError: a non-finite coordinate, or a zero or non-finite quaternion.
    """
    plain = pose.pose if isinstance(pose, PoseStamped) else pose
    x, y = plain.position.x, plain.position.y
    if not (math.isfinite(x) and math.isfinite(y)):
        raise MessageValueError(f"position ({x}, {y}) is not finite")
    return Pose2D(x=x, y=y, yaw=yaw_from_quaternion(plain.orientation))


def from_pose2d(
    pose: Pose2D, frame_id: str = "map", stamp: TimeMsg | Time | None = None
) -> PoseStamped:
    """The :class:`PoseStamped` of a simulator :class:`~baobab.sim.world.Pose2D`."""
    return pose_stamped(pose.x, pose.y, pose.yaw, frame_id=frame_id, stamp=stamp)
