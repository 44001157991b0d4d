"""The TurtleBot 4's figures, each with its source; SI units, ``base_link`` on the floor.

Sources:

- [tb4] TurtleBot 4 user manual, ``overview/features.md``: 342 x 339 x 351 mm, 3945 g,
  wheels 72 mm across, 4.5 mm ground clearance, 9 kg payload.
- [c3] Create 3 docs (``docs/hw/mechanical.md``, ``docs/api/safety.md``, ``odometry.md``):
  0.306 m/s top speed with ``safety_override`` none (the default; 0.46 m/s with ``full``),
  1.90 rad/s, ``wheel_accel_limit`` 900 mm/s^2, 508.8 encoder ticks per wheel turn.
- [c3sim] ``create3_sim``: ``control.yaml`` (``wheel_separation`` 0.233 m, ``wheel_radius``
  0.03575 m; the accelerations 0.9 m/s^2 and 7.725 rad/s^2) and ``create3.urdf.xacro``
  (body cylinder r 0.164 m, h 0.06 m, its underside 0.0192 m up; front caster at
  x = 0.125 m; centre of mass 2.28 cm ahead of the axle in the Ignition model; wheels 0.2 kg,
  15 mm wide).
- [tb4urdf] ``turtlebot4_description/urdf/standard/turtlebot4.urdf.xacro``: the RPLIDAR at
  x = -0.04 m, 0.0942 + 0.098715 m above ``base_link``.
- [a1] Slamtec RPLIDAR A1M8 datasheet: 0.15-12 m, 5.5 Hz typical scan rate (1-10 Hz), 1
  degree at 5.5 Hz (360 samples a turn).
- [nav] ``turtlebot4_navigation/config/nav2.yaml``: ``robot_radius`` 0.175 m.

The wheel servo's torque limit is not published; 1.0 N m is an estimate, several times what
the 0.9 m/s^2 limit needs with the 9 kg payload (12.9 kg x 0.9 m/s^2 x 0.036 m / 2 wheels).
"""

from __future__ import annotations

from baobab.robots.diff_drive.facts import Body, Caster, DiffDriveFacts, LidarFacts
from baobab.robots.footprint import Footprint

RPLIDAR_A1 = LidarFacts(
    model="RPLIDAR A1M8",
    x=-0.04,  # [tb4urdf]
    z=0.1929,  # [tb4urdf] 0.0942 + 0.098715
    range_min=0.15,  # [a1]
    range_max=12.0,  # [a1]
    rate=5.5,  # [a1] typical
    beams=360,  # [a1] 1 degree at 5.5 Hz
)
"""The RPLIDAR A1M8 as the TurtleBot 4 carries it."""

TURTLEBOT4 = DiffDriveFacts(
    model_name="turtlebot4",
    footprint=Footprint.circle(0.175),  # [nav]
    # [tb4] 342 mm across; [c3sim] the cylinder's height and underside.
    body=Body(shape="cylinder", radius=0.171, height=0.060, bottom=0.0192),
    wheel_radius=0.03575,  # [c3sim] ([tb4] 72 mm across)
    wheel_separation=0.233,  # [c3sim]
    wheel_width=0.015,  # [c3sim]
    wheel_mass=0.2,  # [c3sim]
    chassis_mass=3.545,  # [tb4] 3945 g less the wheels
    casters=(Caster(x=0.125, radius=0.012),),  # [c3sim] front caster
    mass_center_x=0.0228,  # [c3sim] Ignition model
    max_linear_speed=0.306,  # [c3] safety_override none
    max_angular_speed=1.90,  # [c3]
    max_linear_accel=0.9,  # [c3] wheel_accel_limit
    max_angular_accel=7.725,  # [c3sim] 0.9 / (0.233 / 2)
    encoder_ticks_per_rev=508.8,  # [c3]
    wheel_gain=0.2,
    wheel_max_torque=1.0,  # estimate (module docstring)
    lidar=RPLIDAR_A1,
    imu=(0.050613, 0.043673, 0.0844),  # [c3sim] 0.0202 + 0.0642 above base_link
    sources=("TurtleBot 4 user manual", "Create 3 docs", "create3_sim", "Slamtec A1M8"),
)
"""The TurtleBot 4 (standard): Create 3 base, RPLIDAR A1M8."""
