"""The world's moving objects as the navigation stack hears of them: topics and TF frames.

Each moving object (:mod:`baobab.sim.moving_objects`) publishes its pose twice, as a person
tracker and a motion-capture system would:

- on its pose topic (``/<name>/pose`` unless the world names another), at every lidar scan in
  which the robot can see it: the beams towards it return at its near side, within
  :data:`SEEN_TOLERANCE`, up to the lidar's range. An object behind a wall, or farther than
  the lidar reaches, publishes nothing on its topic: a follower by topic loses it;
- as its TF frame (its name unless given), always.

Poses are the object's body in the simulation (where its script put it), in the map frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from baobab.nav.interfaces import ScanSource
from baobab.sim.lidar import LaserScan
from baobab.sim.moving_object_motion import moving_object_pose
from baobab.sim.moving_objects import MovingObject, absolute_topic
from baobab.sim.simulation import Simulation
from baobab.sim.world import Pose2D

SEEN_TOLERANCE = 0.15
"""How much (m) a beam towards an object may differ from the distance to its near side."""


@dataclass(frozen=True)
class Detection:
    """A pose heard on a topic: its stamp (s of sim time) and the pose (map frame)."""

    stamp: float
    pose: Pose2D


class ObjectPoses:
    """The pose topics and TF frames of ``objects`` in ``sim``, seen by ``lidar``.

    Args:
        sim: the simulation whose mocap bodies the objects are.
        objects: the world's moving objects.
        lidar: the robot's scanner; None: no topic ever carries a pose.
    """

    def __init__(
        self, sim: Simulation, objects: list[MovingObject], lidar: ScanSource | None
    ) -> None:
        self._sim = sim
        self._objects = list(objects)
        self._latest: dict[str, Detection] = {}
        self._lidar = lidar
        if lidar is not None and self._objects:
            lidar.subscribe(self._on_scan)

    @property
    def topics(self) -> list[str]:
        """The pose topics of the objects."""
        return [item.pose_topic for item in self._objects]

    @property
    def frames(self) -> list[str]:
        """The TF frames of the objects."""
        return [item.tf_frame for item in self._objects]

    def latest(self, topic: str) -> Detection | None:
        """The last pose published on ``topic``, or None if none ever was."""
        return self._latest.get(absolute_topic(topic))

    def frame(self, frame: str) -> Pose2D | None:
        """The pose of TF frame ``frame`` now, or None when no object has that frame."""
        for item in self._objects:
            if item.tf_frame == frame:
                return moving_object_pose(self._sim, item.name)
        return None

    def close(self) -> None:
        """Stop listening to the lidar."""
        if self._lidar is not None and self._objects:
            self._lidar.unsubscribe(self._on_scan)

    def _on_scan(self, scan: LaserScan) -> None:
        for item in self._objects:
            pose = moving_object_pose(self._sim, item.name)
            if sees(scan, pose.x, pose.y, item.radius):
                self._latest[item.pose_topic] = Detection(scan.stamp, pose)


def sees(scan: LaserScan, x: float, y: float, radius: float) -> bool:
    """True when the beams of ``scan`` towards a cylinder of ``radius`` (m) at ``(x, y)``
    return at its near side (nothing in between, within range)."""
    sensor = scan.sensor_pose
    distance = math.hypot(x - sensor.x, y - sensor.y)
    near_side = distance - radius
    if near_side <= scan.range_min or near_side >= scan.range_max:
        return False
    bearing = math.atan2(y - sensor.y, x - sensor.x) - sensor.yaw
    half_width = math.asin(min(radius / distance, 1.0)) * 0.5
    count = len(scan.ranges)
    first = math.floor((bearing - half_width - scan.angle_min) / scan.angle_increment)
    last = math.ceil((bearing + half_width - scan.angle_min) / scan.angle_increment)
    beams = np.arange(first, last + 1) % count
    ranges = scan.ranges[beams]
    hits = np.isfinite(ranges) & (np.abs(ranges - near_side) < SEEN_TOLERANCE + radius / 2)
    return bool(hits.any())


__all__ = ["SEEN_TOLERANCE", "Detection", "ObjectPoses", "sees"]
