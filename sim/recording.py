"""Record a run as Foxglove messages, to an MCAP file or live over Foxglove's WebSocket protocol.

A :class:`Recorder` takes plain data (sim times in seconds, positions, quaternions x, y, z, w,
:class:`~baobab.sim.lidar.LaserScan`, uint8 grids, JSON-able dicts, scene
:class:`~baobab.sim.scene_primitives.Entity`) and logs it with Foxglove's well-known protobuf
schemas (``foxglove.FrameTransforms``, ``foxglove.LaserScan``, ``foxglove.PoseInFrame``, ...)
through the official ``foxglove-sdk``. Where the messages go is the job of its sinks:
:class:`McapSink` writes a file, :class:`LiveSink` serves Foxglove on a WebSocket; a recorder
may feed both at once.

Channels are created on first use of a topic, so a file holds only the topics a run produced.
Message log times are ``time_origin_ns + round(t * 1e9)`` for sim time ``t``; they must not go
backwards on a topic (:class:`RecordingError` otherwise), which keeps every channel in time order.

Static transforms (``/tf_static``) are latched, as ROS latches them: a live viewer that
subscribes late is sent the latest ones with the next message logged.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import foxglove
import numpy as np
from foxglove import channels as fc
from foxglove import messages as fm

from baobab.sim import foxglove_messages as convert
from baobab.sim.closable import Closable
from baobab.sim.lidar import LaserScan
from baobab.sim.recording_sinks import LiveSink, McapSink, RecordingError, Sink
from baobab.sim.scene_primitives import IDENTITY, Entity, Quaternion, Vector3, yaw_quaternion
from baobab.sim.world import Pose2D

__all__ = [
    "ANY_OBJECT",
    "JsonSchema",
    "LiveSink",
    "McapSink",
    "Recorder",
    "RecordingError",
    "Sink",
    "Trail",
    "Transform",
]


@dataclass(frozen=True)
class JsonSchema:
    """A named JSON Schema for a JSON channel (lets Foxglove complete field paths)."""

    name: str
    schema: Mapping[str, Any]


ANY_OBJECT = JsonSchema("baobab.Json", {"type": "object"})
"""A JSON channel's schema when the payload's shape is not described further."""


@dataclass(frozen=True)
class Transform:
    """The pose of frame ``child`` in frame ``parent``: translation (m), rotation x, y, z, w."""

    parent: str
    child: str
    translation: Vector3
    rotation: Quaternion = IDENTITY

    @classmethod
    def planar(cls, parent: str, child: str, pose: Pose2D, z: float = 0.0) -> Transform:
        """A transform from a planar pose (m, rad) and a height ``z`` (m)."""
        return cls(parent, child, (pose.x, pose.y, z), yaw_quaternion(pose.yaw))


class Recorder(Closable):
    """Log a run's data as Foxglove messages to one or more sinks.

    Use as a context manager, or call :meth:`close` at the end (it finalises the MCAP file).

    Args:
        sinks: where the messages go.
        time_origin_ns: added to every time; 0 keeps sim time as is (a file then starts at
            the epoch), ``time.time_ns()`` at start makes a live view show the wall clock.
    """

    def __init__(self, sinks: Sequence[Sink], *, time_origin_ns: int = 0) -> None:
        self.time_origin_ns = int(time_origin_ns)
        self._context = foxglove.Context()
        self._channels: dict[str, tuple[type, Any]] = {}
        self._last_ns: dict[str, int] = {}
        self._latched: dict[str, tuple[Any, int]] = {}
        """Topic -> its latest message and log time, resent to viewers that subscribe late."""
        self._now_ns = -1
        self._sinks: list[Sink] = []
        try:
            for sink in sinks:
                sink.attach(self._context)
                self._sinks.append(sink)
        except BaseException:
            self.close()
            raise

    @property
    def topics(self) -> list[str]:
        """Topics logged so far, in order of first use."""
        return list(self._channels)

    def close(self) -> None:
        """Close every channel and sink (idempotent)."""
        for _, channel in self._channels.values():
            channel.close()
        self._channels.clear()
        for sink in self._sinks:
            sink.close()
        self._sinks.clear()

    # -- navigation ---------------------------------------------------------------------------

    def log_transforms(self, topic: str, t: float, transforms: Sequence[Transform]) -> None:
        """Log transforms stamped ``t`` (s), e.g. map -> odom -> base_link, as one message
        (ROS's topic is ``/tf``)."""
        ns = self._stamp(topic, t)
        message = _frame_transforms(transforms, convert.timestamp(ns))
        self._channel(topic, fc.FrameTransformsChannel).log(message, log_time=ns)

    def log_static_transforms(self, topic: str, t: float, transforms: Sequence[Transform]) -> None:
        """Log transforms that never change, stamped ``t`` (s), and latch them (ROS's
        ``/tf_static``).

        A live viewer that subscribes to ``topic`` later is sent this message again (same
        stamp and log time) with the next message logged on any topic. A file holds only what
        is logged: republish periodically so that a viewer that opens it at any time, or reads
        only part of it, finds the transforms.
        """
        ns = self._stamp(topic, t)
        message = _frame_transforms(transforms, convert.timestamp(ns))
        self._channel(topic, fc.FrameTransformsChannel).log(message, log_time=ns)
        self._latched[topic] = (message, ns)

    def log_pose(
        self,
        topic: str,
        t: float,
        position: Sequence[float] | np.ndarray,
        orientation: Sequence[float] | np.ndarray = IDENTITY,
        *,
        frame_id: str = "map",
    ) -> None:
        """Log a pose (position m, quaternion x, y, z, w) in ``frame_id`` as PoseInFrame."""
        ns = self._stamp(topic, t)
        message = fm.PoseInFrame(
            timestamp=convert.timestamp(ns),
            frame_id=frame_id,
            pose=convert.pose(position, orientation),
        )
        self._channel(topic, fc.PoseInFrameChannel).log(message, log_time=ns)

    def log_planar_pose(
        self, topic: str, t: float, pose: Pose2D, *, frame_id: str = "map", z: float = 0.0
    ) -> None:
        """Log a planar pose (m, rad) at height ``z`` (m) as PoseInFrame."""
        self.log_pose(topic, t, (pose.x, pose.y, z), yaw_quaternion(pose.yaw), frame_id=frame_id)

    def log_path(
        self,
        topic: str,
        t: float,
        poses: np.ndarray,
        *,
        frame_id: str = "map",
        z: float = 0.0,
    ) -> None:
        """Log a planar path, rows ``(x, y, yaw)`` (m, m, rad), as PosesInFrame."""
        poses = np.asarray(poses, dtype=float).reshape(-1, 3)
        ns = self._stamp(topic, t)
        message = fm.PosesInFrame(
            timestamp=convert.timestamp(ns),
            frame_id=frame_id,
            poses=[
                convert.pose((x, y, z), quaternion)
                for (x, y, _), quaternion in zip(
                    poses, convert.yaw_quaternions(poses[:, 2]), strict=True
                )
            ],
        )
        self._channel(topic, fc.PosesInFrameChannel).log(message, log_time=ns)

    def log_scan(
        self, topic: str, scan: LaserScan, *, frame_id: str = "map", z: float = 0.0
    ) -> None:
        """Log a scan at its own stamp, placed at its ``sensor_pose`` (map frame) and height z.

        Placing the scan by the sensor pose it was taken from (the sim localises perfectly)
        keeps it right whatever the TF stream holds. Ranges with no return stay ``inf``.
        """
        ns = self._stamp(topic, scan.stamp)
        sensor = scan.sensor_pose
        message = fm.LaserScan(
            timestamp=convert.timestamp(ns),
            frame_id=frame_id,
            pose=convert.pose((sensor.x, sensor.y, z), yaw_quaternion(sensor.yaw)),
            start_angle=scan.angle_min,
            end_angle=scan.angle_max,
            ranges=[float(r) for r in scan.ranges],
        )
        self._channel(topic, fc.LaserScanChannel).log(message, log_time=ns)

    def log_grid(
        self,
        topic: str,
        t: float,
        data: np.ndarray,
        *,
        resolution: float,
        origin: tuple[float, float],
        frame_id: str = "map",
        field: str = "cost",
        latched: bool = False,
    ) -> None:
        """Log a grid of bytes as a Grid with one field: uint8 (a costmap) or int8 (a map's
        occupancy values, -1 unknown, as ``nav_msgs/OccupancyGrid``).

        Args:
            topic: the topic.
            t: sim time (s).
            data: ``data[iy, ix]``, row ``iy`` along +y, column ``ix`` along +x.
            resolution: cell side (m).
            origin: position (m) of the outer corner of cell ``[0, 0]`` in ``frame_id``.
            frame_id: the grid's frame.
            field: the field name Foxglove colours by.
            latched: resend it to live viewers that subscribe later (a map that does not
                change; see :meth:`log_static_transforms`).
        """
        grid = np.ascontiguousarray(data)
        numeric = _GRID_TYPES.get(grid.dtype.str)
        if numeric is None or grid.ndim != 2:
            raise ValueError(
                f"a grid must be a 2D uint8 or int8 array, got {grid.dtype} {grid.shape}"
            )
        ns = self._stamp(topic, t)
        message = fm.Grid(
            timestamp=convert.timestamp(ns),
            frame_id=frame_id,
            pose=convert.pose((origin[0], origin[1], 0.0), IDENTITY),
            column_count=grid.shape[1],
            cell_size=fm.Vector2(x=resolution, y=resolution),
            row_stride=grid.shape[1],
            cell_stride=1,
            fields=[fm.PackedElementField(name=field, offset=0, type=numeric)],
            data=grid.tobytes(),
        )
        self._channel(topic, fc.GridChannel).log(message, log_time=ns)
        if latched:
            self._latched[topic] = (message, ns)

    # -- scene, arm, JSON ------------------------------------------------------------------------

    def log_scene(
        self, topic: str, t: float, entities: Sequence[Entity], *, replace_all: bool = False
    ) -> None:
        """Log scene entities as a SceneUpdate; entities replace earlier ones with the same id.

        Args:
            topic: the topic.
            t: sim time (s).
            entities: the entities to add or replace.
            replace_all: delete every entity previously sent on the topic first.
        """
        ns = self._stamp(topic, t)
        stamp = convert.timestamp(ns)
        deletions = (
            [fm.SceneEntityDeletion(timestamp=stamp, type=fm.SceneEntityDeletionType.All)]
            if replace_all
            else []
        )
        message = fm.SceneUpdate(
            deletions=deletions,
            entities=[convert.scene_entity(entity, stamp) for entity in entities],
        )
        self._channel(topic, fc.SceneUpdateChannel).log(message, log_time=ns)

    def log_joint_states(
        self,
        topic: str,
        t: float,
        names: Sequence[str],
        positions: Sequence[float] | np.ndarray,
        velocities: Sequence[float] | np.ndarray | None = None,
        efforts: Sequence[float] | np.ndarray | None = None,
    ) -> None:
        """Log joint positions (rad or m), velocities and efforts (N m or N) as JointStates."""
        count = len(names)
        for label, values in (("velocities", velocities), ("efforts", efforts), ("", positions)):
            if values is not None and len(values) != count:
                raise ValueError(f"{label or 'positions'}: {len(values)} values for {count} joints")
        ns = self._stamp(topic, t)
        joints = [
            fm.JointState(
                name=name,
                position=float(positions[i]),
                velocity=None if velocities is None else float(velocities[i]),
                effort=None if efforts is None else float(efforts[i]),
            )
            for i, name in enumerate(names)
        ]
        message = fm.JointStates(timestamp=convert.timestamp(ns), joints=joints)
        self._channel(topic, fc.JointStatesChannel).log(message, log_time=ns)

    def log_json(
        self, topic: str, t: float, payload: Mapping[str, Any], *, schema: JsonSchema = ANY_OBJECT
    ) -> None:
        """Log a JSON object (numpy values and non-finite floats are converted: NaN -> null).

        The schema is fixed by the first message on a topic.
        """
        ns = self._stamp(topic, t)
        text = json.dumps(convert.jsonable(payload), allow_nan=False, separators=(",", ":"))
        if topic not in self._channels:
            channel = foxglove.Channel(
                topic,
                schema=foxglove.Schema(
                    name=schema.name,
                    encoding="jsonschema",
                    data=json.dumps(schema.schema).encode(),
                ),
                message_encoding="json",
                context=self._context,
            )
            self._channels[topic] = (foxglove.Channel, channel)
        kind, json_channel = self._channels[topic]
        if kind is not foxglove.Channel:
            raise RecordingError(f"topic {topic} already carries {kind.__name__}, not JSON")
        json_channel.log(text.encode(), log_time=ns)

    # -- internals ------------------------------------------------------------------------------

    def _channel(self, topic: str, kind: type) -> Any:
        entry = self._channels.get(topic)
        if entry is None:
            entry = (kind, kind(topic, context=self._context))
            self._channels[topic] = entry
        elif entry[0] is not kind:
            raise RecordingError(
                f"topic {topic} already carries {entry[0].__name__}, not {kind.__name__}"
            )
        return entry[1]

    def _stamp(self, topic: str, t: float) -> int:
        """Log time (ns) of sim time ``t`` on ``topic``; broadcasts the time to live sinks."""
        if not math.isfinite(t) or t < 0:
            raise RecordingError(f"{topic}: time must be a finite, non-negative sim time, got {t}")
        ns = self.time_origin_ns + round(t * 1e9)
        last = self._last_ns.get(topic)
        if last is not None and ns < last:
            before = (last - self.time_origin_ns) / 1e9
            raise RecordingError(f"{topic}: time went backwards, {t:.9f} s after {before:.9f} s")
        self._last_ns[topic] = ns
        if ns > self._now_ns:
            self._now_ns = ns
            for sink in self._sinks:
                sink.broadcast_time(ns)
        if self._latched:
            self._resend_latched()
        return ns

    def _resend_latched(self) -> None:
        """Log the latched messages again on the topics viewers subscribed to since last time.

        Every sink gets the copy (foxglove-sdk's Python API cannot address one client): a file
        then holds the message twice, at the same log time, which keeps the topic in order.
        """
        for sink in self._sinks:
            for topic in sink.new_subscriptions():
                latched = self._latched.get(topic)
                if latched is not None:
                    message, ns = latched
                    self._channels[topic][1].log(message, log_time=ns)


_GRID_TYPES = {
    np.dtype(np.uint8).str: fm.PackedElementFieldNumericType.Uint8,
    np.dtype(np.int8).str: fm.PackedElementFieldNumericType.Int8,
}
"""The element types a logged grid may have."""


def _frame_transforms(transforms: Sequence[Transform], stamp: fm.Timestamp) -> fm.FrameTransforms:
    return fm.FrameTransforms(
        transforms=[
            fm.FrameTransform(
                timestamp=stamp,
                parent_frame_id=tf.parent,
                child_frame_id=tf.child,
                translation=convert.vector3(tf.translation),
                rotation=convert.quaternion(tf.rotation),
            )
            for tf in transforms
        ]
    )


class Trail:
    """A followed path, thinned: a pose is kept once the robot moved or turned enough.

    Args:
        min_distance: keep a pose this far (m) from the last kept one.
        min_angle: or turned this much (rad) from it.
    """

    def __init__(self, min_distance: float = 0.05, min_angle: float = 0.2) -> None:
        self.min_distance = min_distance
        self.min_angle = min_angle
        self._poses: list[tuple[float, float, float]] = []

    def add(self, pose: Pose2D) -> bool:
        """Add the pose if it is far enough from the last kept one; True if kept."""
        if self._poses:
            x, y, yaw = self._poses[-1]
            turned = abs(math.remainder(pose.yaw - yaw, math.tau))
            if math.hypot(pose.x - x, pose.y - y) < self.min_distance and turned < self.min_angle:
                return False
        self._poses.append((pose.x, pose.y, pose.yaw))
        return True

    @property
    def poses(self) -> np.ndarray:
        """Kept poses, rows ``(x, y, yaw)``."""
        return np.array(self._poses, dtype=float).reshape(-1, 3)
