"""The MuJoCo names of a differential-drive robot's parts, and which geoms are obstacles.

Every robot model (:mod:`baobab.robots.diff_drive.model`, or a robot's own body in its
folder) names its parts the same way, under the robot's prefix, so that the base controller,
the lidar, the probes and the faults find them by name whatever the robot.
"""

from __future__ import annotations

from dataclasses import dataclass

from baobab.sim.builder import MOVABLE_GROUP, STATIC_GROUP
from baobab.sim.world import FLOOR_NAME

OBSTACLE_GROUPS = (STATIC_GROUP, MOVABLE_GROUP)
"""Geom groups of the world's obstacles: a contact with one of them is a collision."""


@dataclass(frozen=True)
class DiffDriveNames:
    """MuJoCo names of the robot's parts for a given prefix."""

    prefix: str

    @property
    def body(self) -> str:
        """The chassis body, whose frame is ``base_link``."""
        return f"{self.prefix}base_link"

    @property
    def root_joint(self) -> str:
        """The chassis free joint."""
        return f"{self.prefix}root"

    @property
    def wheel_joints(self) -> tuple[str, str]:
        """Left and right wheel hinges."""
        return (f"{self.prefix}wheel_left_joint", f"{self.prefix}wheel_right_joint")

    @property
    def wheel_actuators(self) -> tuple[str, str]:
        """Left and right wheel velocity actuators."""
        return (f"{self.prefix}wheel_left_velocity", f"{self.prefix}wheel_right_velocity")

    @property
    def lidar_site(self) -> str:
        """The lidar's scan origin (ROS's ``base_scan``)."""
        return f"{self.prefix}base_scan"

    @property
    def footprint_geom(self) -> str:
        """The non-colliding footprint geom used for clearance queries."""
        return f"{self.prefix}footprint"

    def touch_sensor(self, obstacle: str) -> str:
        """The contact sensor that counts the robot's contacts with the geom ``obstacle``."""
        return f"{self.prefix}touch/{obstacle}"

    @property
    def map_contact_sensors(self) -> tuple[str, str]:
        """On a world with a map, the sensors that count the robot's contacts with the floor
        and with any geom of the world body, in that order: the world body's count less the
        floor's and the world file's obstacles' (each has its own sensor) is the robot's
        contacts with the map's walls."""
        return (f"{self.prefix}touch_map/{FLOOR_NAME}", f"{self.prefix}touch_map/world")
