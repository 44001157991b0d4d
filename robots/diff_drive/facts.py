"""The facts of a differential-drive robot: one record that its model, its base controller,
its lidar, its navigation defaults and the mission checks all read.

Every figure is SI (m, kg, s, rad, N m) in ``base_link``: on the floor under the midpoint of
the wheel axle (ROS's ``base_footprint``), x forward, y left, z up. A bundled robot states the
source of each figure in the facts module of its folder; a user's robot
gives the same facts in a YAML file (:mod:`baobab.robots.robot_file`). Importing this module
loads no numpy and no MuJoCo: ``baobab validate`` reads facts before any physics.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from baobab.robots.footprint import Footprint


@dataclass(frozen=True)
class Body:
    """The chassis' collision envelope: an upright box or cylinder.

    Attributes:
        shape: ``box`` or ``cylinder``.
        length: box extent along x (m); unused for a cylinder.
        width: box extent along y (m); unused for a cylinder.
        radius: cylinder radius (m); unused for a box.
        height: extent along z (m).
        center_x: x of its centre in ``base_link`` (m).
        bottom: height of its underside above the floor (m): the ground clearance.
    """

    shape: Literal["box", "cylinder"]
    height: float
    bottom: float
    center_x: float = 0.0
    length: float = 0.0
    width: float = 0.0
    radius: float = 0.0

    @property
    def top(self) -> float:
        """Height of its top above the floor (m)."""
        return self.bottom + self.height

    @property
    def half_extents(self) -> tuple[float, float]:
        """Half its extent along x and along y (m)."""
        if self.shape == "cylinder":
            return self.radius, self.radius
        return self.length / 2, self.width / 2


@dataclass(frozen=True)
class Caster:
    """A frictionless ball caster touching the floor at ``(x, y)`` in ``base_link`` (m)."""

    x: float
    y: float = 0.0
    radius: float = 0.008


@dataclass(frozen=True)
class LidarFacts:
    """A planar 360-degree lidar.

    Attributes:
        model: its name, for messages (``LDS-01``).
        x: its scan origin in ``base_link`` (m).
        y: m.
        z: height of the scan plane above the floor (m).
        range_min: the nearest it measures (m); closer returns read ``inf``.
        range_max: the farthest it measures (m).
        rate: scans per second (Hz).
        beams: samples per turn.
        radius: radius of its housing (m), drawn and colliding.
    """

    model: str
    x: float
    z: float
    range_min: float
    range_max: float
    rate: float
    beams: int
    y: float = 0.0
    radius: float = 0.035


@dataclass(frozen=True)
class DiffDriveFacts:
    """Everything baobab needs to know about a differential-drive robot with a 2D lidar.

    Attributes:
        model_name: the MuJoCo model's name.
        footprint: its outline on the floor as Nav2 configures it (radius or polygon).
        body: the chassis' collision envelope.
        wheel_radius: m.
        wheel_separation: distance between the wheel contact points (m).
        wheel_width: tyre width (m).
        wheel_mass: one wheel with its tyre (kg).
        chassis_mass: everything but the wheels (kg).
        casters: the ball casters that carry the rest.
        max_linear_speed: forward speed limit (m/s).
        max_angular_speed: yaw-rate limit (rad/s).
        max_linear_accel: linear acceleration limit (m/s^2).
        max_angular_accel: angular acceleration limit (rad/s^2).
        encoder_ticks_per_rev: wheel encoder resolution (ticks per wheel turn).
        wheel_gain: the wheel velocity servo's gain (N m per rad/s).
        wheel_max_torque: the wheel motor's torque limit (N m), its stall torque.
        lidar: the lidar on top.
        mass_center_x: x (m) of the chassis' centre of mass; None: the body's centre.
        base_link_height: ``base_link`` above ``base_footprint`` (m), as the robot's URDF
            places it (baobab's ``base_link`` is on the floor; ROS topics use the URDF's).
        imu: ``imu_link`` in the URDF's ``base_link`` (m).
        sources: where the figures come from, for ``baobab list`` and readers.
    """

    model_name: str
    footprint: Footprint
    body: Body
    wheel_radius: float
    wheel_separation: float
    wheel_width: float
    wheel_mass: float
    chassis_mass: float
    max_linear_speed: float
    max_angular_speed: float
    max_linear_accel: float
    max_angular_accel: float
    lidar: LidarFacts
    casters: tuple[Caster, ...] = ()
    encoder_ticks_per_rev: float = 4096
    wheel_gain: float = 0.2
    wheel_max_torque: float = 1.4
    mass_center_x: float | None = None
    base_link_height: float = 0.0
    imu: tuple[float, float, float] = (0.0, 0.0, 0.0)
    sources: tuple[str, ...] = field(default=(), compare=False)

    @property
    def max_wheel_speed(self) -> float:
        """Wheel rim speed limit (m/s): enough for either the speed or the yaw-rate limit."""
        return max(self.max_linear_speed, self.max_angular_speed * self.wheel_separation / 2)

    @property
    def total_mass(self) -> float:
        """Mass of the whole robot (kg)."""
        return self.chassis_mass + 2 * self.wheel_mass

    @property
    def footprint_radius(self) -> float:
        """Radius (m) of the circle around ``base_link`` that holds the footprint."""
        return self.footprint.circumscribed_radius

    @property
    def height(self) -> float:
        """Height (m) of the robot's top: its body or its lidar housing, whichever is higher."""
        return max(self.body.top, self.lidar.z + LIDAR_HALF_HEIGHT)


LIDAR_HALF_HEIGHT = 0.02
"""Half the height (m) of a lidar's turret around its scan plane, as the models draw it."""
