"""World description -> MjSpec: floor, static obstacles, movable obstacle slots, lights.

Geom groups are a contract with the sensors and the contact checks:

- ``FLOOR_GROUP`` (0): the floor plane.
- ``STATIC_GROUP`` (1): walls, boxes and cylinders of the world file, and the boxes a map's
  solid cells merge into (``map_0``, ``map_1``, ...; :mod:`baobab.sim.map_geometry`), which
  wear the material :data:`MAP_WALL_MATERIAL`. All are geoms of the world body: MuJoCo's
  broad phase pays for every geom of any other body at every step.
- ``MOVABLE_GROUP`` (2): obstacle slots that events spawn or move at run time (mocap bodies).
- ``ROBOT_GROUP`` (3): every geom of a robot; sensors on a robot exclude this group.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from baobab.sim.map_geometry import solid_rectangles
from baobab.sim.world import (
    FLOOR_NAME,
    MAP_GEOM_PREFIX,
    MOVABLE_SLOT_COUNT,
    MOVABLE_SLOT_PREFIX,
    World,
)

FLOOR_GROUP = 0
STATIC_GROUP = 1
MOVABLE_GROUP = 2
ROBOT_GROUP = 3

PHYSICS_TIMESTEP = 0.005
"""Default physics step (s): 200 Hz, two steps per 100 Hz base-controller tick."""

MOVABLE_PARK_DISTANCE = 1000.0
"""Where unused movable slots wait (m along x): far outside every world and every sensor."""


def movable_slot_name(index: int) -> str:
    """Body (and geom) name of the movable obstacle slot ``index``."""
    return f"{MOVABLE_SLOT_PREFIX}{index}"


def world_spec(
    world: World,
    *,
    timestep: float = PHYSICS_TIMESTEP,
    movable_slots: int = MOVABLE_SLOT_COUNT,
) -> mujoco.MjSpec:
    """Build an MjSpec holding ``world``; attach robots to it, then ``compile()``.

    Args:
        world: the validated world description.
        timestep: physics step in seconds.
        movable_slots: how many mocap box bodies to reserve for run-time obstacles.
    """
    spec = mujoco.MjSpec()
    spec.modelname = world.name
    spec.option.timestep = timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    spec.visual.global_.offwidth = 1280
    spec.visual.global_.offheight = 960
    spec.visual.headlight.ambient = [0.35, 0.35, 0.35]
    spec.visual.headlight.diffuse = [0.5, 0.5, 0.5]
    spec.stat.center = [world.floor.center[0], world.floor.center[1], 0.0]
    spec.stat.extent = max(world.floor.size) / 2
    _add_floor(spec, world)
    _add_obstacles(spec.worldbody, world)
    _add_map_walls(spec, world)
    _add_movable_slots(spec.worldbody, movable_slots)
    return spec


def _add_floor(spec: mujoco.MjSpec, world: World) -> None:
    """The checkered floor plane (``FLOOR_GROUP``) and the sun above its centre."""
    body = spec.worldbody
    (sx, sy), (cx, cy) = world.floor.size, world.floor.center
    texture = spec.add_texture(
        name="floor_checker",
        type=mujoco.mjtTexture.mjTEXTURE_2D,
        builtin=mujoco.mjtBuiltin.mjBUILTIN_CHECKER,
        rgb1=list(world.floor.colour[:3]),
        rgb2=[c * 0.9 for c in world.floor.colour[:3]],
        width=256,
        height=256,
    )
    material = spec.add_material(name="floor_material", texrepeat=[sx, sy], texuniform=False)
    material.textures[mujoco.mjtTextureRole.mjTEXROLE_RGB] = texture.name
    body.add_geom(
        name=FLOOR_NAME,
        type=mujoco.mjtGeom.mjGEOM_PLANE,
        size=[sx / 2, sy / 2, 0.05],
        pos=[cx, cy, 0.0],
        material="floor_material",
        group=FLOOR_GROUP,
    )
    body.add_light(
        name="sun",
        pos=[cx, cy, 10.0],
        dir=[0.2, 0.3, -1.0],
        diffuse=[0.6, 0.6, 0.6],
        castshadow=False,
    )


def _add_obstacles(body: mujoco.MjsBody, world: World) -> None:
    """The world file's boxes and cylinders, standing on the floor (``STATIC_GROUP``)."""
    for box in world.boxes:
        body.add_geom(
            name=box.name,
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[box.size[0] / 2, box.size[1] / 2, box.height / 2],
            pos=[box.center[0], box.center[1], box.height / 2],
            quat=_yaw_quaternion_wxyz(box.yaw),
            rgba=list(box.colour),
            group=STATIC_GROUP,
        )
    for cylinder in world.cylinders:
        body.add_geom(
            name=cylinder.name,
            type=mujoco.mjtGeom.mjGEOM_CYLINDER,
            size=[cylinder.radius, cylinder.height / 2, 0.0],
            pos=[cylinder.center[0], cylinder.center[1], cylinder.height / 2],
            rgba=list(cylinder.colour),
            group=STATIC_GROUP,
        )


MAP_WALL_COLOUR = (0.35, 0.36, 0.40, 1.0)
"""Colour of the boxes a map's solid cells become."""
MAP_WALL_MATERIAL = f"{MAP_GEOM_PREFIX}walls"
"""The material of every box of a map's walls, which tells them from the world file's own
obstacles (the name is reserved by the ``map_`` prefix on a world with a map)."""


def _add_map_walls(spec: mujoco.MjSpec, world: World) -> None:
    """The map's solid cells as boxes ``world.map.wall_height`` tall (``STATIC_GROUP``)."""
    grid, solid = world.grid, world.map_solid()
    if grid is None or solid is None or world.map is None:
        return
    body = spec.worldbody
    spec.add_material(name=MAP_WALL_MATERIAL, rgba=list(MAP_WALL_COLOUR))
    height = world.map.wall_height
    res = grid.resolution
    x0, y0 = grid.origin
    rectangles = solid_rectangles(solid)
    half = np.empty((len(rectangles), 3))
    half[:, 0] = (rectangles[:, 2] - rectangles[:, 0]) * res / 2
    half[:, 1] = (rectangles[:, 3] - rectangles[:, 1]) * res / 2
    half[:, 2] = height / 2
    centre = np.empty((len(rectangles), 3))
    centre[:, 0] = x0 + (rectangles[:, 0] + rectangles[:, 2]) * res / 2
    centre[:, 1] = y0 + (rectangles[:, 1] + rectangles[:, 3]) * res / 2
    centre[:, 2] = height / 2
    colour = list(MAP_WALL_COLOUR)
    for index in range(len(rectangles)):
        body.add_geom(
            name=f"{MAP_GEOM_PREFIX}{index}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=half[index].tolist(),
            pos=centre[index].tolist(),
            rgba=colour,
            material=MAP_WALL_MATERIAL,
            group=STATIC_GROUP,
        )


def _add_movable_slots(body: mujoco.MjsBody, count: int) -> None:
    """``count`` mocap boxes (``MOVABLE_GROUP``) parked far away until an event places one."""
    for index in range(count):
        slot = body.add_body(
            name=movable_slot_name(index),
            mocap=True,
            pos=[MOVABLE_PARK_DISTANCE + 10.0 * index, MOVABLE_PARK_DISTANCE, 0.25],
        )
        slot.add_geom(
            name=movable_slot_name(index),
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[0.15, 0.15, 0.25],
            rgba=[0.85, 0.35, 0.2, 1.0],
            group=MOVABLE_GROUP,
        )


def _yaw_quaternion_wxyz(yaw: float) -> list[float]:
    """MuJoCo's w, x, y, z quaternion for a rotation of ``yaw`` (rad) about z."""
    return [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]


def geom_ids_in_group(model: mujoco.MjModel, group: int) -> np.ndarray:
    """Ids of every geom of ``model`` in geom group ``group``."""
    return np.flatnonzero(model.geom_group == group)
