"""A differential-drive robot as an MjSpec, built from its facts, and attaching it to a world.

:func:`diff_drive_spec` builds the generic body every robot without one of its own gets (the
bundled robots of the registry, a user's robot file): the chassis (its box or cylinder
collision envelope, with explicit inertia) on a free joint, two wheels driven by velocity
actuators (:func:`add_wheel`), frictionless ball casters, the lidar's housing and the
``base_scan`` site at its mount, and a non-colliding footprint geom (a cylinder for a radius,
a prism for a polygon) for the clearance metric. :func:`attach_robot` puts any robot's spec
into a world with one contact sensor per obstacle geom.

Every robot geom is in ``ROBOT_GROUP`` so that the lidar and the clearance checks can tell it
from the world; geoms that only decorate collide with nothing. Names follow
:class:`~baobab.robots.diff_drive.names.DiffDriveNames`.
"""

from __future__ import annotations

import math

import mujoco

from baobab.robots.diff_drive.facts import LIDAR_HALF_HEIGHT, Caster, DiffDriveFacts
from baobab.robots.diff_drive.names import OBSTACLE_GROUPS, DiffDriveNames
from baobab.sim.builder import MAP_WALL_MATERIAL, ROBOT_GROUP
from baobab.sim.world import FLOOR_NAME, Pose2D

CONTACT_FOUND = 1
"""A contact sensor's ``data="found"`` bit: the number of matching contacts."""

BODY_COLOUR = [0.20, 0.21, 0.23, 1.0]
TYRE_COLOUR = [0.08, 0.08, 0.09, 1.0]
HUB_COLOUR = [0.78, 0.79, 0.80, 1.0]
LIDAR_COLOUR = [0.10, 0.10, 0.11, 1.0]
INVISIBLE = [0.0, 0.0, 0.0, 0.0]

Z_TO_Y = [math.cos(-math.pi / 4), math.sin(-math.pi / 4), 0.0, 0.0]
"""A cylinder's axis is its local z; a wheel needs it along y: -90 degrees about x."""


def wxyz_about_z(yaw: float) -> list[float]:
    """MuJoCo's w, x, y, z quaternion of a rotation by ``yaw`` (rad) about z."""
    return [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]


def robot_geom(body: mujoco.MjsBody, **kwargs: object) -> mujoco.MjsGeom:
    """A geom of the robot (``ROBOT_GROUP``)."""
    return body.add_geom(group=ROBOT_GROUP, **kwargs)


def visual_geom(body: mujoco.MjsBody, **kwargs: object) -> mujoco.MjsGeom:
    """A geom of the robot that only decorates: it collides with nothing."""
    return robot_geom(body, contype=0, conaffinity=0, **kwargs)


def diff_drive_spec(facts: DiffDriveFacts) -> mujoco.MjSpec:
    """A stand-alone MjSpec holding the generic body of ``facts``, ``base_link`` at the origin.

    Attach it to a world with :func:`attach_robot`; names carry no prefix here.
    """
    spec = mujoco.MjSpec()
    spec.modelname = facts.model_name
    chassis = spec.worldbody.add_body(name="base_link")
    chassis.add_freejoint(name="root")
    _add_chassis(chassis, facts)
    for index, caster in enumerate(facts.casters):
        add_caster(chassis, caster, f"caster_{index}")
    _add_lidar(chassis, facts)
    add_footprint_geom(spec, chassis, facts, bottom=facts.body.bottom, top=facts.height)
    for side, sign in (("left", 1.0), ("right", -1.0)):
        add_wheel(spec, chassis, facts, side, sign)
    return spec


def add_caster(chassis: mujoco.MjsBody, caster: Caster, name: str) -> None:
    """A frictionless ball caster touching the floor under ``chassis`` (frictionless so that
    it carries weight without resisting a turn)."""
    robot_geom(
        chassis,
        name=name,
        type=mujoco.mjtGeom.mjGEOM_SPHERE,
        size=[caster.radius, 0.0, 0.0],
        pos=[caster.x, caster.y, caster.radius],
        condim=1,
        friction=[0.0, 0.0, 0.0],
        priority=1,
        rgba=HUB_COLOUR,
    )


def _add_chassis(chassis: mujoco.MjsBody, facts: DiffDriveFacts) -> None:
    body, mass = facts.body, facts.chassis_mass
    centre_z = body.bottom + body.height / 2
    chassis.explicitinertial = True
    chassis.mass = mass
    com_x = body.center_x if facts.mass_center_x is None else facts.mass_center_x
    chassis.ipos = [com_x, 0.0, centre_z]
    if body.shape == "cylinder":
        radial = mass * (3 * body.radius**2 + body.height**2) / 12
        chassis.inertia = [radial, radial, mass * body.radius**2 / 2]
        size = [body.radius, body.height / 2, 0.0]
        shape = mujoco.mjtGeom.mjGEOM_CYLINDER
    else:
        length, width, height = body.length, body.width, body.height
        chassis.inertia = [
            mass * (width**2 + height**2) / 12,
            mass * (length**2 + height**2) / 12,
            mass * (length**2 + width**2) / 12,
        ]
        size = [length / 2, width / 2, height / 2]
        shape = mujoco.mjtGeom.mjGEOM_BOX
    robot_geom(
        chassis,
        name="chassis",
        type=shape,
        size=size,
        pos=[body.center_x, 0.0, centre_z],
        rgba=BODY_COLOUR,
    )


def _add_lidar(chassis: mujoco.MjsBody, facts: DiffDriveFacts) -> None:
    """The lidar's housing around its scan plane, a standoff down to the body, and the
    ``base_scan`` site it scans from."""
    lidar = facts.lidar
    robot_geom(
        chassis,
        name="lidar",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[lidar.radius, LIDAR_HALF_HEIGHT, 0.0],
        pos=[lidar.x, lidar.y, lidar.z],
        rgba=LIDAR_COLOUR,
    )
    gap = lidar.z - LIDAR_HALF_HEIGHT - facts.body.top
    if gap > 0:
        visual_geom(
            chassis,
            name="lidar_standoff",
            type=mujoco.mjtGeom.mjGEOM_CYLINDER,
            size=[lidar.radius / 3, gap / 2, 0.0],
            pos=[lidar.x, lidar.y, facts.body.top + gap / 2],
            rgba=HUB_COLOUR,
        )
    chassis.add_site(
        name="base_scan",
        pos=[lidar.x, lidar.y, lidar.z],
        size=[0.01, 0.0, 0.0],
        group=ROBOT_GROUP,
        rgba=[1.0, 0.2, 0.2, 1.0],
    )


def add_footprint_geom(
    spec: mujoco.MjSpec,
    chassis: mujoco.MjsBody,
    facts: DiffDriveFacts,
    *,
    bottom: float,
    top: float,
) -> None:
    """The invisible, non-colliding ``footprint`` geom from ``bottom`` to ``top`` (m): an
    upright cylinder for a radius, a prism of the polygon otherwise (a mesh: MuJoCo measures
    distances to its convex hull)."""
    footprint, half = facts.footprint, (top - bottom) / 2
    if footprint.radius is not None:
        visual_geom(
            chassis,
            name="footprint",
            type=mujoco.mjtGeom.mjGEOM_CYLINDER,
            size=[footprint.radius, half, 0.0],
            pos=[0.0, 0.0, bottom + half],
            rgba=INVISIBLE,
        )
        return
    vertices = [
        coordinate for x, y in footprint.polygon for z in (bottom, top) for coordinate in (x, y, z)
    ]
    spec.add_mesh(name="footprint_prism", uservert=vertices)
    visual_geom(
        chassis,
        name="footprint",
        type=mujoco.mjtGeom.mjGEOM_MESH,
        meshname="footprint_prism",
        rgba=INVISIBLE,
    )


def add_wheel(
    spec: mujoco.MjSpec, chassis: mujoco.MjsBody, facts: DiffDriveFacts, side: str, sign: float
) -> None:
    """The ``side`` wheel (``sign`` +1 left, -1 right): hinge, tyre, hubs and its velocity
    actuator, from the facts' wheel figures, servo gain and torque limit."""
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
        rgba=INVISIBLE,
    )
    wheel.add_geom(
        name=f"wheel_{side}_tyre",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[radius, half_width, 0.0],
        quat=Z_TO_Y,
        contype=0,
        conaffinity=0,
        group=ROBOT_GROUP,
        rgba=TYRE_COLOUR,
    )
    for index, angle in enumerate((0.0, math.pi / 2)):
        wheel.add_geom(
            name=f"wheel_{side}_spoke_{index}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[radius - 0.007, half_width + 0.0005, 0.004],
            quat=[math.cos(angle / 2), 0.0, math.sin(angle / 2), 0.0],
            contype=0,
            conaffinity=0,
            group=ROBOT_GROUP,
            rgba=HUB_COLOUR,
        )
    actuator = spec.add_actuator(
        name=f"wheel_{side}_velocity",
        target=f"wheel_{side}_joint",
        trntype=mujoco.mjtTrn.mjTRN_JOINT,
    )
    actuator.set_to_velocity(kv=facts.wheel_gain)
    actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
    actuator.forcerange = [-facts.wheel_max_torque, facts.wheel_max_torque]


def attach_robot(
    spec: mujoco.MjSpec, robot: mujoco.MjSpec, pose: Pose2D, *, prefix: str
) -> DiffDriveNames:
    """Attach the stand-alone ``robot`` spec to the world ``spec`` with ``base_link`` at
    ``pose`` (map frame), every name prefixed with ``prefix``, and one contact sensor per
    obstacle geom of the world (two for all of a map's walls); the returned object spells the
    names."""
    frame = spec.worldbody.add_frame(pos=[pose.x, pose.y, 0.0], quat=wxyz_about_z(pose.yaw))
    obstacles = [geom for geom in spec.geoms if geom.group in OBSTACLE_GROUPS]
    named = [geom.name for geom in obstacles if geom.material != MAP_WALL_MATERIAL]
    has_map = len(named) < len(obstacles)
    frame.attach_body(robot.body("base_link"), prefix, "")
    names = DiffDriveNames(prefix)
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
            intprm=[CONTACT_FOUND, 0, 1],
        )
    from baobab.sim.native_control import USERDATA_SLOTS  # numba: only when building a robot

    spec.nuserdata = USERDATA_SLOTS
    return names
