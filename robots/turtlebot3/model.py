"""The TurtleBot3 Burger as an MjSpec: its figures, its body, and attaching it to a world.

The body is built in Python with MjSpec so its dimensions come from one table of facts
(:data:`BURGER`) that the base controller and the lidar read too. The robot's frame
``base_link`` sits on the floor under the midpoint of the wheel axle (ROS's
``base_footprint``), x forward, y left, z up. The chassis hangs on a free joint; the two wheels
are hinges driven by velocity actuators; a frictionless ball caster at the back carries the
rest. Every robot geom is in ``ROBOT_GROUP`` so that the lidar and the clearance checks can
tell it from the world. Geoms that only decorate (plates, standoffs, motors, hubs) do not
collide.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco

from baobab.sim.builder import MAP_WALL_MATERIAL, MOVABLE_GROUP, ROBOT_GROUP, STATIC_GROUP
from baobab.sim.world import FLOOR_NAME, Pose2D

DEFAULT_PREFIX = "tb3/"
OBSTACLE_GROUPS = (STATIC_GROUP, MOVABLE_GROUP)
"""Geom groups of the world's obstacles: a contact with one of them is a collision."""
_CONTACT_FOUND = 1
"""A contact sensor's ``data="found"`` bit: the number of matching contacts."""


@dataclass(frozen=True)
class BurgerFacts:
    """Figures of the TurtleBot3 Burger (ROBOTIS e-manual, Nav2's TB3 parameters); SI units."""

    wheel_radius: float = 0.033
    """Wheel radius (m)."""
    wheel_separation: float = 0.160
    """Distance between the wheel contact points (m)."""
    wheel_width: float = 0.018
    """Tyre width (m)."""
    max_linear_speed: float = 0.22
    """Forward speed limit (m/s)."""
    max_angular_speed: float = 2.84
    """Yaw-rate limit (rad/s)."""
    max_linear_accel: float = 2.5
    """Linear acceleration limit (m/s^2), Nav2 velocity smoother for the TB3."""
    max_angular_accel: float = 3.2
    """Angular acceleration limit (rad/s^2), Nav2 velocity smoother for the TB3."""
    footprint_radius: float = 0.105
    """Radius of the circle around ``base_link`` that holds the robot (m), Nav2's value."""
    encoder_ticks_per_rev: int = 4096
    """Resolution of the Dynamixel XL430 wheel encoders (ticks per wheel turn)."""
    chassis_mass: float = 0.934
    """Everything but the wheels (kg): plates, motors, battery, boards, LDS-01, caster."""
    wheel_mass: float = 0.033
    """One wheel with its tyre (kg); the whole robot weighs 1.0 kg."""
    lidar_height: float = 0.182
    """LDS-01 scan plane above the floor (m)."""
    lidar_offset_x: float = -0.032
    """LDS-01 position behind the wheel axle (m)."""
    lidar_range_min: float = 0.12
    """LDS-01 minimum range (m)."""
    lidar_range_max: float = 3.5
    """LDS-01 maximum range (m)."""
    lidar_rate: float = 5.0
    """LDS-01 scan rate (Hz)."""
    lidar_beams: int = 360
    """LDS-01 samples per turn."""

    @property
    def max_wheel_speed(self) -> float:
        """Wheel rim speed limit (m/s): enough for either the speed or the yaw-rate limit."""
        return max(self.max_linear_speed, self.max_angular_speed * self.wheel_separation / 2)

    @property
    def total_mass(self) -> float:
        """Mass of the whole robot (kg)."""
        return self.chassis_mass + 2 * self.wheel_mass


BURGER = BurgerFacts()

_DARK = [0.16, 0.17, 0.19, 1.0]
_PLATE = [0.22, 0.23, 0.25, 1.0]
_TYRE = [0.08, 0.08, 0.09, 1.0]
_HUB = [0.78, 0.79, 0.80, 1.0]
_LIDAR = [0.10, 0.10, 0.11, 1.0]
_LIDAR_TURRET = [0.30, 0.55, 0.85, 1.0]
_BOARD = [0.12, 0.45, 0.30, 1.0]
_INVISIBLE = [0.0, 0.0, 0.0, 0.0]

_CHASSIS_CENTER_X = -0.025
_CHASSIS_HALF = 0.060
_CASTER_RADIUS = 0.008
_CASTER_X = -0.081


@dataclass(frozen=True)
class TurtleBot3Names:
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
        """The LDS-01 scan origin (ROS's ``base_scan``)."""
        return f"{self.prefix}base_scan"

    @property
    def footprint_geom(self) -> str:
        """The non-colliding footprint cylinder used for clearance queries."""
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


def _wxyz_about_z(yaw: float) -> list[float]:
    """MuJoCo's w, x, y, z quaternion of a rotation by ``yaw`` (rad) about z."""
    return [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]


# A cylinder's axis is its local z; the wheels need it along y: rotate -90 deg about x.
_Z_TO_Y = [math.cos(-math.pi / 4), math.sin(-math.pi / 4), 0.0, 0.0]


def turtlebot3_spec(facts: BurgerFacts = BURGER) -> mujoco.MjSpec:
    """A stand-alone MjSpec holding one Burger whose ``base_link`` is at the world origin.

    Attach it to a world with :func:`attach_turtlebot3`; names carry no prefix here.
    """
    spec = mujoco.MjSpec()
    spec.modelname = "turtlebot3_burger"
    chassis = spec.worldbody.add_body(name="base_link")
    chassis.add_freejoint(name="root")
    _add_chassis(chassis, facts)
    for side, sign in (("left", 1.0), ("right", -1.0)):
        _add_wheel(spec, chassis, facts, side, sign)
    return spec


def _add_chassis(chassis: mujoco.MjsBody, facts: BurgerFacts) -> None:
    chassis.explicitinertial = True
    chassis.mass = facts.chassis_mass
    chassis.ipos = [_CHASSIS_CENTER_X, 0.0, 0.075]
    width, height = 2 * _CHASSIS_HALF, 0.15
    ixx = facts.chassis_mass / 12 * (width**2 + height**2)
    chassis.inertia = [ixx, ixx, facts.chassis_mass / 12 * 2 * width**2]
    # The collision envelope of the plate stack, and what the eye sees of it.
    _geom(
        chassis,
        name="chassis",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[_CHASSIS_HALF, _CHASSIS_HALF, 0.069],
        pos=[_CHASSIS_CENTER_X, 0.0, 0.089],
        rgba=_INVISIBLE,
    )
    _add_plate_stack(chassis)
    _geom(
        chassis,
        name="caster",
        type=mujoco.mjtGeom.mjGEOM_SPHERE,
        size=[_CASTER_RADIUS, 0.0, 0.0],
        pos=[_CASTER_X, 0.0, _CASTER_RADIUS],
        condim=1,
        friction=[0.0, 0.0, 0.0],
        priority=1,
        rgba=_HUB,
    )
    _add_lidar(chassis, facts)
    _visual(
        chassis,
        name="footprint",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[facts.footprint_radius, 0.095, 0.0],
        pos=[0.0, 0.0, 0.105],
        rgba=_INVISIBLE,
    )


def _geom(body: mujoco.MjsBody, **kwargs: object) -> mujoco.MjsGeom:
    """A geom of the robot (``ROBOT_GROUP``)."""
    return body.add_geom(group=ROBOT_GROUP, **kwargs)


def _visual(body: mujoco.MjsBody, **kwargs: object) -> mujoco.MjsGeom:
    """A geom of the robot that only decorates: it collides with nothing."""
    return _geom(body, contype=0, conaffinity=0, **kwargs)


def _add_plate_stack(chassis: mujoco.MjsBody) -> None:
    """What the eye sees of the chassis: plates, standoffs, motors, battery and board."""
    for level, z in enumerate((0.020, 0.068, 0.112, 0.152)):
        _visual(
            chassis,
            name=f"plate_{level}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[_CHASSIS_HALF, _CHASSIS_HALF, 0.0015],
            pos=[_CHASSIS_CENTER_X, 0.0, z],
            rgba=_PLATE,
        )
    for index, (dx, dy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
        _visual(
            chassis,
            name=f"standoff_{index}",
            type=mujoco.mjtGeom.mjGEOM_CYLINDER,
            size=[0.003, 0.066, 0.0],
            pos=[_CHASSIS_CENTER_X + dx * 0.052, dy * 0.052, 0.086],
            rgba=_HUB,
        )
    for side, sign in (("left", 1.0), ("right", -1.0)):
        _visual(
            chassis,
            name=f"motor_{side}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[0.023, 0.017, 0.014],
            pos=[0.0, sign * 0.050, 0.036],
            rgba=_DARK,
        )
    _visual(
        chassis,
        name="battery",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[0.044, 0.017, 0.011],
        pos=[_CHASSIS_CENTER_X - 0.010, 0.0, 0.034],
        rgba=[0.85, 0.72, 0.20, 1.0],
    )
    _visual(
        chassis,
        name="board",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[0.050, 0.050, 0.004],
        pos=[_CHASSIS_CENTER_X, 0.0, 0.118],
        rgba=_BOARD,
    )


def _add_lidar(chassis: mujoco.MjsBody, facts: BurgerFacts) -> None:
    """The LDS-01 on top: its base and turret, and the ``base_scan`` site it scans from."""
    lidar_x = facts.lidar_offset_x
    _geom(
        chassis,
        name="lds_base",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[0.035, 0.010, 0.0],
        pos=[lidar_x, 0.0, 0.166],
        rgba=_LIDAR,
    )
    _geom(
        chassis,
        name="lds_turret",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[0.030, 0.010, 0.0],
        pos=[lidar_x, 0.0, facts.lidar_height],
        rgba=_LIDAR_TURRET,
    )
    chassis.add_site(
        name="base_scan",
        pos=[lidar_x, 0.0, facts.lidar_height],
        size=[0.01, 0.0, 0.0],
        group=ROBOT_GROUP,
        rgba=[1.0, 0.2, 0.2, 1.0],
    )


def _add_wheel(
    spec: mujoco.MjSpec, chassis: mujoco.MjsBody, facts: BurgerFacts, side: str, sign: float
) -> None:
    radius, half_width = facts.wheel_radius, facts.wheel_width / 2
    wheel = chassis.add_body(
        name=f"wheel_{side}",
        pos=[0.0, sign * facts.wheel_separation / 2, radius],
    )
    wheel.explicitinertial = True
    wheel.mass = facts.wheel_mass
    wheel.ipos = [0.0, 0.0, 0.0]
    axial = facts.wheel_mass * radius**2 / 2
    radial = facts.wheel_mass * (3 * radius**2 + (2 * half_width) ** 2) / 12
    wheel.inertia = [radial, axial, radial]
    wheel.add_joint(
        name=f"wheel_{side}_joint",
        type=mujoco.mjtJoint.mjJNT_HINGE,
        axis=[0.0, 1.0, 0.0],
        # Rotor inertia seen through the gearbox (kg m^2). It also sets the wheel servo's time
        # constant, armature / kv = 2.5 ms: a servo much stiffer than the 5 ms physics step
        # (1e-4 gave 0.5 ms) makes the chassis lead, then rock against, ramping wheels.
        armature=5e-4,
        damping=1e-4,
    )
    # The tyre touches the floor through a flat ellipsoid: one contact point in the middle of
    # the tread, as a rounded tyre has, so turning in place does not scrub across the width.
    wheel.add_geom(
        name=f"wheel_{side}",
        type=mujoco.mjtGeom.mjGEOM_ELLIPSOID,
        size=[radius, half_width, radius],
        friction=[1.0, 0.005, 0.0001],
        condim=3,
        solref=[0.01, 1.0],  # the stiffest MuJoCo allows at the 5 ms step
        priority=1,
        group=ROBOT_GROUP,
        rgba=_INVISIBLE,
    )
    wheel.add_geom(
        name=f"wheel_{side}_tyre",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[radius, half_width, 0.0],
        quat=_Z_TO_Y,
        contype=0,
        conaffinity=0,
        group=ROBOT_GROUP,
        rgba=_TYRE,
    )
    for index, angle in enumerate((0.0, math.pi / 2)):
        wheel.add_geom(
            name=f"wheel_{side}_spoke_{index}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[0.026, half_width + 0.0005, 0.004],
            quat=[math.cos(angle / 2), 0.0, math.sin(angle / 2), 0.0],
            contype=0,
            conaffinity=0,
            group=ROBOT_GROUP,
            rgba=_HUB,
        )
    actuator = spec.add_actuator(
        name=f"wheel_{side}_velocity",
        target=f"wheel_{side}_joint",
        trntype=mujoco.mjtTrn.mjTRN_JOINT,
    )
    actuator.set_to_velocity(kv=0.2)
    actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
    actuator.forcerange = [-1.4, 1.4]  # Dynamixel XL430-W250 stall torque at 11.1 V (N m)


def attach_turtlebot3(
    spec: mujoco.MjSpec,
    pose: Pose2D,
    *,
    prefix: str = DEFAULT_PREFIX,
    facts: BurgerFacts = BURGER,
) -> TurtleBot3Names:
    """Attach a Burger to the world ``spec`` with ``base_link`` at ``pose`` (map frame).

    Every name of the robot is prefixed with ``prefix``; the returned object spells them.
    """
    frame = spec.worldbody.add_frame(pos=[pose.x, pose.y, 0.0], quat=_wxyz_about_z(pose.yaw))
    robot = turtlebot3_spec(facts)
    obstacles = [geom for geom in spec.geoms if geom.group in OBSTACLE_GROUPS]
    named = [geom.name for geom in obstacles if geom.material != MAP_WALL_MATERIAL]
    has_map = len(named) < len(obstacles)
    frame.attach_body(robot.body("base_link"), prefix, "")
    names = TurtleBot3Names(prefix)
    targets = [(mujoco.mjtObj.mjOBJ_GEOM, name, names.touch_sensor(name)) for name in named]
    if has_map:
        # A map has thousands of boxes, and MuJoCo matches every contact sensor against every
        # contact at each step: two sensors count them all instead (map_contact_sensors).
        floor_sensor, world_sensor = names.map_contact_sensors
        targets.append((mujoco.mjtObj.mjOBJ_GEOM, FLOOR_NAME, floor_sensor))
        targets.append((mujoco.mjtObj.mjOBJ_BODY, "world", world_sensor))
    for kind, target, sensor in targets:
        spec.add_sensor(
            name=sensor,
            type=mujoco.mjtSensor.mjSENS_CONTACT,
            objtype=kind,
            objname=target,
            reftype=mujoco.mjtObj.mjOBJ_XBODY,
            refname=names.body,
            intprm=[_CONTACT_FOUND, 0, 1],
        )
    from baobab.sim.native_control import USERDATA_SLOTS  # numba: only when building a robot

    spec.nuserdata = USERDATA_SLOTS
    return names
