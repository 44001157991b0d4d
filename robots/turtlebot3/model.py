"""The TurtleBot3 Burger's own body as an MjSpec, and attaching it to a world.

The body is built in Python with MjSpec so its dimensions come from one table of facts
(:data:`~baobab.robots.turtlebot3.facts.BURGER`) that the base controller and the lidar read
too. The robot's frame ``base_link`` sits on the floor under the midpoint of the wheel axle
(ROS's ``base_footprint``), x forward, y left, z up. The chassis hangs on a free joint; the two
wheels are the differential-drive ones (:func:`~baobab.robots.diff_drive.model.add_wheel`); a
frictionless ball caster at the back carries the rest. Every robot geom is in ``ROBOT_GROUP``
so that the lidar and the clearance checks can tell it from the world. Geoms that only
decorate (plates, standoffs, motors, hubs) do not collide.
"""

from __future__ import annotations

import mujoco

from baobab.robots.diff_drive.facts import DiffDriveFacts
from baobab.robots.diff_drive.model import (
    HUB_COLOUR,
    INVISIBLE,
    add_caster,
    add_wheel,
    attach_robot,
    robot_geom,
    visual_geom,
)
from baobab.robots.diff_drive.names import DiffDriveNames
from baobab.robots.turtlebot3.facts import BURGER
from baobab.sim.builder import ROBOT_GROUP
from baobab.sim.world import Pose2D

DEFAULT_PREFIX = "tb3/"

_DARK = [0.16, 0.17, 0.19, 1.0]
_PLATE = [0.22, 0.23, 0.25, 1.0]
_LIDAR = [0.10, 0.10, 0.11, 1.0]
_LIDAR_TURRET = [0.30, 0.55, 0.85, 1.0]
_BOARD = [0.12, 0.45, 0.30, 1.0]

_CHASSIS_CENTER_X = -0.025
_CHASSIS_HALF = 0.060


def turtlebot3_spec(facts: DiffDriveFacts = BURGER) -> mujoco.MjSpec:
    """A stand-alone MjSpec holding one Burger whose ``base_link`` is at the world origin.

    Attach it to a world with :func:`attach_turtlebot3`; names carry no prefix here.
    """
    spec = mujoco.MjSpec()
    spec.modelname = facts.model_name
    chassis = spec.worldbody.add_body(name="base_link")
    chassis.add_freejoint(name="root")
    _add_chassis(chassis, facts)
    for side, sign in (("left", 1.0), ("right", -1.0)):
        add_wheel(spec, chassis, facts, side, sign)
    return spec


def _add_chassis(chassis: mujoco.MjsBody, facts: DiffDriveFacts) -> None:
    chassis.explicitinertial = True
    chassis.mass = facts.chassis_mass
    chassis.ipos = [_CHASSIS_CENTER_X, 0.0, 0.075]
    width, height = 2 * _CHASSIS_HALF, 0.15
    ixx = facts.chassis_mass / 12 * (width**2 + height**2)
    chassis.inertia = [ixx, ixx, facts.chassis_mass / 12 * 2 * width**2]
    # The collision envelope of the plate stack, and what the eye sees of it.
    robot_geom(
        chassis,
        name="chassis",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[_CHASSIS_HALF, _CHASSIS_HALF, 0.069],
        pos=[_CHASSIS_CENTER_X, 0.0, 0.089],
        rgba=INVISIBLE,
    )
    _add_plate_stack(chassis)
    add_caster(chassis, facts.casters[0], "caster")
    _add_lidar(chassis, facts)
    visual_geom(
        chassis,
        name="footprint",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[facts.footprint_radius, 0.095, 0.0],
        pos=[0.0, 0.0, 0.105],
        rgba=INVISIBLE,
    )


def _add_plate_stack(chassis: mujoco.MjsBody) -> None:
    """What the eye sees of the chassis: plates, standoffs, motors, battery and board."""
    for level, z in enumerate((0.020, 0.068, 0.112, 0.152)):
        visual_geom(
            chassis,
            name=f"plate_{level}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[_CHASSIS_HALF, _CHASSIS_HALF, 0.0015],
            pos=[_CHASSIS_CENTER_X, 0.0, z],
            rgba=_PLATE,
        )
    for index, (dx, dy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
        visual_geom(
            chassis,
            name=f"standoff_{index}",
            type=mujoco.mjtGeom.mjGEOM_CYLINDER,
            size=[0.003, 0.066, 0.0],
            pos=[_CHASSIS_CENTER_X + dx * 0.052, dy * 0.052, 0.086],
            rgba=HUB_COLOUR,
        )
    for side, sign in (("left", 1.0), ("right", -1.0)):
        visual_geom(
            chassis,
            name=f"motor_{side}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[0.023, 0.017, 0.014],
            pos=[0.0, sign * 0.050, 0.036],
            rgba=_DARK,
        )
    visual_geom(
        chassis,
        name="battery",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[0.044, 0.017, 0.011],
        pos=[_CHASSIS_CENTER_X - 0.010, 0.0, 0.034],
        rgba=[0.85, 0.72, 0.20, 1.0],
    )
    visual_geom(
        chassis,
        name="board",
        type=mujoco.mjtGeom.mjGEOM_BOX,
        size=[0.050, 0.050, 0.004],
        pos=[_CHASSIS_CENTER_X, 0.0, 0.118],
        rgba=_BOARD,
    )


def _add_lidar(chassis: mujoco.MjsBody, facts: DiffDriveFacts) -> None:
    """The LDS-01 on top: its base and turret, and the ``base_scan`` site it scans from."""
    lidar_x = facts.lidar.x
    robot_geom(
        chassis,
        name="lds_base",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[0.035, 0.010, 0.0],
        pos=[lidar_x, 0.0, 0.166],
        rgba=_LIDAR,
    )
    robot_geom(
        chassis,
        name="lds_turret",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[0.030, 0.010, 0.0],
        pos=[lidar_x, 0.0, facts.lidar.z],
        rgba=_LIDAR_TURRET,
    )
    chassis.add_site(
        name="base_scan",
        pos=[lidar_x, 0.0, facts.lidar.z],
        size=[0.01, 0.0, 0.0],
        group=ROBOT_GROUP,
        rgba=[1.0, 0.2, 0.2, 1.0],
    )


def attach_turtlebot3(
    spec: mujoco.MjSpec,
    pose: Pose2D,
    *,
    prefix: str = DEFAULT_PREFIX,
    facts: DiffDriveFacts = BURGER,
) -> DiffDriveNames:
    """Attach a Burger to the world ``spec`` with ``base_link`` at ``pose`` (map frame).

    Every name of the robot is prefixed with ``prefix``; the returned object spells them.
    """
    return attach_robot(spec, turtlebot3_spec(facts), pose, prefix=prefix)
