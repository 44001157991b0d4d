"""The TurtleBot3 Burger's and Waffle's figures, each with its source; SI units, ``base_link``.

Sources (ROBOTIS):

- [spec] e-manual, TurtleBot3 specifications (``docs/en/platform/turtlebot3/features/
  specifications.md``): size, weight, speed limits, actuators.
- [node] ``turtlebot3_bringup/param/{burger,waffle}.yaml``: ``wheels.separation`` and
  ``wheels.radius`` of ``turtlebot3_node``.
- [urdf] ``turtlebot3_description/urdf/turtlebot3_{burger,waffle}.urdf``: the base collision
  box, wheel and caster joints, ``base_scan``, link masses; ``base_link`` sits 0.010 m above
  ``base_footprint`` (the floor).
- [nav2] ``turtlebot3_navigation2/param/*.yaml``: the velocity smoother's acceleration limits
  (2.5 m/s^2, 3.2 rad/s^2) and the Burger's ``robot_radius``.
- [lds] e-manual, LDS-01 appendix: 120-3500 mm, 300 rpm (5 Hz), 1 degree (360 samples).
- [dxl] ROBOTIS Dynamixel e-manual: XL430-W250 stall torque 1.4 N m at 11.1 V, XM430-W210
  3.0 N m at 12 V; 4096 ticks per turn.

The Burger's body is its own MjSpec (:mod:`.model`, the plates and standoffs of the real one);
the Waffle's is the generic differential-drive body (:mod:`baobab.robots.diff_drive.model`).
"""

from __future__ import annotations

from baobab.robots.diff_drive.facts import Body, Caster, DiffDriveFacts, LidarFacts
from baobab.robots.footprint import Footprint

LDS_01 = LidarFacts(
    model="LDS-01",
    x=-0.032,  # [urdf] base_scan x of the Burger
    z=0.182,  # the Burger's scan plane above the floor ([urdf] 0.172 + 0.010)
    range_min=0.12,  # [lds]
    range_max=3.5,  # [lds]
    rate=5.0,  # [lds] 300 rpm
    beams=360,  # [lds] 1 degree
)
"""The LDS-01 as the Burger carries it."""

BURGER = DiffDriveFacts(
    model_name="turtlebot3_burger",
    # The circle around base_link that holds the plate stack's rear corners (hypot(0.085,
    # 0.060) = 0.104 m); [nav2] ROBOTIS configures 0.1 m.
    footprint=Footprint.circle(0.105),
    # The collision envelope of the plate stack (the [urdf] box is 0.140 x 0.140 x 0.143).
    body=Body(shape="box", length=0.120, width=0.120, height=0.138, bottom=0.020, center_x=-0.025),
    wheel_radius=0.033,  # [node]
    wheel_separation=0.160,  # [node]
    wheel_width=0.018,  # [urdf]
    wheel_mass=0.033,  # one wheel with its tyre; the whole robot weighs 1.0 kg [spec]
    chassis_mass=0.934,  # plates, motors, battery, boards, LDS-01, caster
    casters=(Caster(x=-0.081, radius=0.008),),  # [urdf] caster x
    max_linear_speed=0.22,  # [spec]
    max_angular_speed=2.84,  # [spec]
    max_linear_accel=2.5,  # [nav2]
    max_angular_accel=3.2,  # [nav2]
    encoder_ticks_per_rev=4096,  # [dxl] XL430-W250
    wheel_gain=0.2,
    wheel_max_torque=1.4,  # [dxl] XL430-W250 stall torque at 11.1 V
    lidar=LDS_01,
    base_link_height=0.010,  # [urdf]
    imu=(-0.032, 0.0, 0.068),  # [urdf] imu_joint
    sources=("ROBOTIS e-manual", "turtlebot3_description URDF", "turtlebot3_navigation2"),
)
"""The TurtleBot3 Burger."""

WAFFLE = DiffDriveFacts(
    model_name="turtlebot3_waffle",
    # [spec] 281 x 306 mm, centred where the [urdf] base box is (x = -0.064): the wheels'
    # outer faces are the sides (0.144 + 0.009 = 0.153).
    footprint=Footprint.rectangle(-0.2045, 0.0765, -0.153, 0.153),
    body=Body(shape="box", length=0.266, width=0.266, height=0.094, bottom=0.010, center_x=-0.064),
    wheel_radius=0.033,  # [node]
    wheel_separation=0.287,  # [node] ([urdf] wheels at y = +-0.144)
    wheel_width=0.018,  # [urdf]
    wheel_mass=0.0285,  # [urdf]
    chassis_mass=1.743,  # the robot's 1.8 kg [spec] less the wheels
    casters=(Caster(x=-0.177, y=0.064), Caster(x=-0.177, y=-0.064)),  # [urdf]
    max_linear_speed=0.26,  # [spec]
    max_angular_speed=1.82,  # [spec]
    max_linear_accel=2.5,  # [nav2]
    max_angular_accel=3.2,  # [nav2]
    encoder_ticks_per_rev=4096,  # [dxl] XM430-W210
    wheel_gain=0.2,
    wheel_max_torque=3.0,  # [dxl] XM430-W210 stall torque at 12 V
    # [urdf] base_scan (-0.064, 0, 0.122) above base_link; the same LDS as the Burger.
    lidar=LidarFacts(
        model="LDS-01",
        x=-0.064,
        z=0.132,
        range_min=LDS_01.range_min,
        range_max=LDS_01.range_max,
        rate=LDS_01.rate,
        beams=LDS_01.beams,
    ),
    base_link_height=0.010,  # [urdf]
    imu=(0.0, 0.0, 0.068),  # [urdf] imu_joint
    sources=("ROBOTIS e-manual", "turtlebot3_description URDF", "turtlebot3_navigation2"),
)
"""The TurtleBot3 Waffle (the Waffle Pi shares its base)."""
