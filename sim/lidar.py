"""2D lidar: the LaserScan message shape (the sensor itself is added by the TurtleBot3 work)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from baobab.sim.world import Pose2D


@dataclass(frozen=True)
class LaserScan:
    """One planar scan, shaped like ``sensor_msgs/LaserScan``.

    Beam ``i`` points at ``angle_min + i * angle_increment`` (rad, counter-clockwise, 0 ahead)
    in the sensor frame. ``ranges`` (m) holds ``inf`` where nothing was hit within
    ``range_max``. ``sensor_pose`` is the sensor's planar pose in the map frame when the scan
    was taken (the sim localises perfectly), and ``stamp`` is the sim time (s).
    """

    stamp: float
    frame_id: str
    angle_min: float
    angle_max: float
    angle_increment: float
    range_min: float
    range_max: float
    ranges: np.ndarray
    sensor_pose: Pose2D

    @property
    def angles(self) -> np.ndarray:
        """Beam angles (rad) in the sensor frame."""
        return self.angle_min + self.angle_increment * np.arange(len(self.ranges))
