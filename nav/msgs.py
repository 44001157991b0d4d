"""ROS 2 message types for the Nav2-style facade, with ROS's field names and defaults.

Messages are mutable and built field by field as in rclpy
(``goal.pose.position.x = 1.0``); constructors take keyword arguments only, and a misspelt
field raises ``AttributeError`` (slots), as generated ROS messages do. A fresh
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
from dataclasses import dataclass, field

from scipy.spatial.transform import Rotation

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
    "to_pose2d",
    "yaw_from_quaternion",
]


class MessageValueError(BaobabError, ValueError):
    """A message holds a value with no meaning, such as a zero or non-finite quaternion."""


# --- std_msgs -------------------------------------------------------------------------------


@dataclass(slots=True, kw_only=True)
class Header:
    """``std_msgs/Header``: when (``stamp``) and in which frame (``frame_id``) data holds."""

    stamp: TimeMsg = field(default_factory=TimeMsg)
    frame_id: str = ""


# --- geometry_msgs --------------------------------------------------------------------------


@dataclass(slots=True, kw_only=True)
class Point:
    """``geometry_msgs/Point`` (m)."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0


@dataclass(slots=True, kw_only=True)
class Vector3:
    """``geometry_msgs/Vector3`` (units of the field that holds it)."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0


@dataclass(slots=True, kw_only=True)
class Quaternion:
    """``geometry_msgs/Quaternion``, ``x, y, z, w``; the default is the identity."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    w: float = 1.0


@dataclass(slots=True, kw_only=True)
class Pose:
    """``geometry_msgs/Pose``: a position (m) and an orientation."""

    position: Point = field(default_factory=Point)
    orientation: Quaternion = field(default_factory=Quaternion)


@dataclass(slots=True, kw_only=True)
class PoseStamped:
    """``geometry_msgs/PoseStamped``: a pose in ``header.frame_id`` at ``header.stamp``."""

    header: Header = field(default_factory=Header)
    pose: Pose = field(default_factory=Pose)


@dataclass(slots=True, kw_only=True)
class PoseWithCovariance:
    """``geometry_msgs/PoseWithCovariance``: a pose and its row-major 6x6 covariance."""

    pose: Pose = field(default_factory=Pose)
    covariance: list[float] = field(default_factory=lambda: [0.0] * 36)


@dataclass(slots=True, kw_only=True)
class PoseWithCovarianceStamped:
    """``geometry_msgs/PoseWithCovarianceStamped`` (what Nav2's ``initialpose`` carries)."""

    header: Header = field(default_factory=Header)
    pose: PoseWithCovariance = field(default_factory=PoseWithCovariance)


@dataclass(slots=True, kw_only=True)
class Twist:
    """``geometry_msgs/Twist``: linear (m/s) and angular (rad/s) velocity."""

    linear: Vector3 = field(default_factory=Vector3)
    angular: Vector3 = field(default_factory=Vector3)


@dataclass(slots=True, kw_only=True)
class TwistStamped:
    """``geometry_msgs/TwistStamped``."""

    header: Header = field(default_factory=Header)
    twist: Twist = field(default_factory=Twist)


# --- nav_msgs -------------------------------------------------------------------------------


@dataclass(slots=True, kw_only=True)
class Path:
    """``nav_msgs/Path``: poses a robot should follow, in order."""

    header: Header = field(default_factory=Header)
    poses: list[PoseStamped] = field(default_factory=list)


@dataclass(slots=True, kw_only=True)
class Goals:
    """``nav_msgs/Goals``: the goal list Rolling's ``goThroughPoses`` takes."""

    header: Header = field(default_factory=Header)
    goals: list[PoseStamped] = field(default_factory=list)


@dataclass(slots=True, kw_only=True)
class MapMetaData:
    """``nav_msgs/MapMetaData``: grid size (cells), cell size (m) and the pose of cell (0, 0)."""

    map_load_time: TimeMsg = field(default_factory=TimeMsg)
    resolution: float = 0.0
    width: int = 0
    height: int = 0
    origin: Pose = field(default_factory=Pose)


@dataclass(slots=True, kw_only=True)
class OccupancyGrid:
    """``nav_msgs/OccupancyGrid``: row-major int8 occupancy, 0..100 or -1 for unknown.

    ``data[i + width * j]`` is cell column ``i``, row ``j``; ``numpy.frombuffer(grid.data,
    dtype=numpy.int8)`` views it without a copy.
    """

    header: Header = field(default_factory=Header)
    info: MapMetaData = field(default_factory=MapMetaData)
    data: array[int] = field(default_factory=lambda: array("b"))


# --- nav2_msgs ------------------------------------------------------------------------------


@dataclass(slots=True, kw_only=True)
class CostmapMetaData:
    """``nav2_msgs/CostmapMetaData``: grid size (cells), cell size (m), origin, layer name."""

    map_load_time: TimeMsg = field(default_factory=TimeMsg)
    update_time: TimeMsg = field(default_factory=TimeMsg)
    layer: str = ""
    resolution: float = 0.0
    size_x: int = 0
    size_y: int = 0
    origin: Pose = field(default_factory=Pose)


@dataclass(slots=True, kw_only=True)
class Costmap:
    """``nav2_msgs/Costmap``: row-major uint8 costs.

    0 is free, 253 inscribed, 254 lethal, 255 unknown; ``data[i + size_x * j]`` is cell
    column ``i``, row ``j``.
    """

    header: Header = field(default_factory=Header)
    metadata: CostmapMetaData = field(default_factory=CostmapMetaData)
    data: array[int] = field(default_factory=lambda: array("B"))


# --- conversions ----------------------------------------------------------------------------


def quaternion_from_yaw(yaw: float) -> Quaternion:
    """The quaternion of a rotation by ``yaw`` (rad) about +z."""
    x, y, z, w = Rotation.from_euler("z", yaw).as_quat()
    return Quaternion(x=float(x), y=float(y), z=float(z), w=float(w))


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
    return PoseStamped(
        header=Header(stamp=_stamp_msg(stamp), frame_id=frame_id),
        pose=Pose(position=Point(x=float(x), y=float(y)), orientation=quaternion_from_yaw(yaw)),
    )


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
