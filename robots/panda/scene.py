"""The ``panda_table`` scene: the arm on a table, a 5 cm cube and a place target.

``sim/worlds/panda_table.xml`` holds the table, cube, target marker, lights, camera and the
solver options; :func:`panda_table_spec` attaches ``panda.xml`` at its ``panda_mount`` frame.
The physics step is 1 ms, so the arm's torque control runs at 1 kHz, once per physics step.
"""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import numpy as np

import baobab.sim
from baobab.robots.panda import native_loop
from baobab.robots.panda.arm_server import ArmServer, ArmServerConfig
from baobab.robots.panda.errors import PandaSceneError
from baobab.robots.panda.impedance import ImpedanceGains
from baobab.robots.panda.model import (
    ARM_JOINTS,
    BASE_BODY,
    FINGER_JOINTS,
    HOME_CONFIGURATION,
    MAX_OPENING,
    PANDA_XML,
)
from baobab.robots.panda.pose import Pose
from baobab.sim.camera import CameraPose, framing, geom_box_corners
from baobab.sim.simulation import Simulation

PANDA_TABLE_XML = Path(baobab.sim.__file__).parent / "worlds" / "panda_table.xml"

PREFIX = "panda/"
"""Name prefix of the robot's elements in the scene."""

MOUNT_FRAME = "panda_mount"
CUBE_BODY = "cube"
CUBE_JOINT = "cube_joint"
CUBE_GEOM = "cube"
PLACE_TARGET_SITE = "place_target"
TABLE_GEOM = "table"
FLOOR_GEOM = "floor"

ROBOT_CONTACT_SENSOR = "robot_environment_contact"
"""Contact sensor: how many contacts the robot has with the table or the floor (-)."""

# The contact sensor's intprm: data bits (1 = "found", the match count), reduction (0 =
# none), number of reported slots.
_CONTACT_FOUND = 1
_CONTACT_REDUCE_NONE = 0

CUBE_HALF_SIZE = 0.025
"""Half the cube's edge (m)."""

TABLE_HEIGHT = 0.5
"""Height of the table top (m)."""

VIDEO_AZIMUTH = 140.0
"""The video looks at the arm from the front left, across the table (deg)."""

VIDEO_ELEVATION = -40.0
"""The video looks down on the table top, steeply enough that the floor fills the back (deg)."""

CUBE_REGION = ((0.35, 0.60), (-0.25, 0.05))
"""Where seeded cubes appear: (x range, y range) in the world frame (m). The arm's base is at
the world origin on the table top; the place target is at y = 0.3, clear of this region."""


def panda_table_spec() -> mujoco.MjSpec:
    """The scene with the Panda attached at the mount frame (prefix ``panda/``).

    It carries one sensor, :data:`ROBOT_CONTACT_SENSOR`: the number of contacts between the
    robot and the world body's geoms (table and floor), counted by MuJoCo inside the step; and
    it reserves the userdata slots of the arm's compiled control loop
    (:data:`~baobab.robots.panda.native_loop.USERDATA_SLOTS`).
    """
    spec = mujoco.MjSpec.from_file(str(PANDA_TABLE_XML))
    robot = mujoco.MjSpec.from_file(str(PANDA_XML))
    spec.attach(robot, frame=spec.frame(MOUNT_FRAME), prefix=PREFIX)
    spec.nuserdata = native_loop.USERDATA_SLOTS
    spec.add_sensor(
        name=ROBOT_CONTACT_SENSOR,
        type=mujoco.mjtSensor.mjSENS_CONTACT,
        objtype=mujoco.mjtObj.mjOBJ_XBODY,  # the robot's whole subtree
        objname=PREFIX + BASE_BODY,
        reftype=mujoco.mjtObj.mjOBJ_BODY,
        refname="world",
        intprm=[_CONTACT_FOUND, _CONTACT_REDUCE_NONE, 1],
    )
    return spec


def sample_cube_xy(rng: np.random.Generator) -> tuple[float, float]:
    """A cube position (x, y) in m drawn uniformly from :data:`CUBE_REGION`."""
    (x_low, x_high), (y_low, y_high) = CUBE_REGION
    return float(rng.uniform(x_low, x_high)), float(rng.uniform(y_low, y_high))


def build_panda_sim(
    seed: int = 0,
    cube_xy: tuple[float, float] | None = None,
    *,
    cube_yaw: float = 0.0,
    cube_mass: float | None = None,
    gains: ImpedanceGains | None = None,
    config: ArmServerConfig | None = None,
) -> tuple[Simulation, ArmServer]:
    """Compile ``panda_table`` and start the arm server, ready for tasks.

    The arm starts at the "ready" pose with the hand open; the cube lies on the table at
    ``cube_xy`` or, if None, at a position drawn from the simulation's seeded generator.

    Args:
        seed: seed of the simulation's generator.
        cube_xy: cube position on the table (m, world frame), or None to draw one.
        cube_yaw: cube rotation about the vertical (rad).
        cube_mass: cube mass (kg); the scene's 0.1 kg if None.
        gains: impedance gains of the arm.
        config: arm task tolerances.

    Raises:
        PandaSceneError: if ``cube_xy`` is not on the table or ``cube_mass`` is not positive.
    """
    spec = panda_table_spec()
    if cube_mass is not None:
        if not cube_mass > 0.0:
            raise PandaSceneError(f"cube mass must be positive, got {cube_mass} kg")
        spec.geom(CUBE_GEOM).mass = cube_mass
    sim = Simulation(spec.compile(), seed=seed)
    model, data = sim.model, sim.data
    xy = sample_cube_xy(sim.rng) if cube_xy is None else cube_xy
    _check_on_table(model, xy)
    for name, angle in zip(ARM_JOINTS, HOME_CONFIGURATION, strict=True):
        data.joint(PREFIX + name).qpos = angle
    for name in FINGER_JOINTS:
        data.joint(PREFIX + name).qpos = MAX_OPENING / 2
    half_yaw = 0.5 * cube_yaw
    data.joint(CUBE_JOINT).qpos = [
        xy[0],
        xy[1],
        TABLE_HEIGHT + CUBE_HALF_SIZE,
        math.cos(half_yaw),  # MuJoCo's w, x, y, z
        0.0,
        0.0,
        math.sin(half_yaw),
    ]
    sim.forward()
    server = ArmServer(
        sim, prefix=PREFIX, gains=gains, config=config, contact_sensor=ROBOT_CONTACT_SENSOR
    )
    return sim, server


def place_target(sim: Simulation) -> np.ndarray:
    """World position of the place-target marker on the table top (m)."""
    return sim.data.site(PLACE_TARGET_SITE).xpos.copy()


def video_view(sim: Simulation, aspect: float) -> CameraPose:
    """The video's fixed 3/4 view: the table top and the arm as it stands now fill the frame.

    Args:
        sim: the scene in its start state (the arm then works below its start pose).
        aspect: frame width over height.
    """
    model = sim.model
    base = model.body(PREFIX + BASE_BODY).id
    arm = [g for g in range(model.ngeom) if model.body_rootid[model.geom_bodyid[g]] == base]
    table = geom_box_corners(model, sim.data, [model.geom(TABLE_GEOM).id])
    table_top = table[table[:, 2] >= table[:, 2].max() - 1e-9]
    return framing(
        np.concatenate([table_top, geom_box_corners(model, sim.data, arm)]),
        azimuth=VIDEO_AZIMUTH,
        elevation=VIDEO_ELEVATION,
        fovy=float(model.vis.global_.fovy),
        aspect=aspect,
    )


def cube_pose(sim: Simulation) -> Pose:
    """The cube's pose in the world frame, from its free joint (always current)."""
    qpos = sim.data.joint(CUBE_JOINT).qpos
    w, x, y, z = (float(v) for v in qpos[3:7])
    return Pose((float(qpos[0]), float(qpos[1]), float(qpos[2])), (x, y, z, w))


def _check_on_table(model: mujoco.MjModel, xy: tuple[float, float]) -> None:
    table = model.geom(TABLE_GEOM)
    centre, half = table.pos[:2], table.size[:2] - CUBE_HALF_SIZE
    if len(xy) != 2 or not np.all(np.abs(np.asarray(xy, dtype=float) - centre) <= half):
        raise PandaSceneError(
            f"cube position {tuple(xy)} is not on the table "
            f"(x {centre[0] - half[0]:.3f}..{centre[0] + half[0]:.3f} m, "
            f"y {centre[1] - half[1]:.3f}..{centre[1] + half[1]:.3f} m)"
        )
