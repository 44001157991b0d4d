"""Scene content as plain primitives shaped like Foxglove's: MuJoCo geoms, named locations.

A :class:`GeomScene` turns the geoms of a compiled model into cubes, spheres and cylinders at
their current world poses, grouped into one :class:`Entity` per body, ready for
:meth:`baobab.sim.recording.Recorder.log_scene`. MuJoCo shapes map as follows:

- box -> cube (MuJoCo sizes are half extents, Foxglove's full extents);
- sphere and ellipsoid -> sphere (an ellipsoid is a sphere with unequal extents);
- cylinder -> cylinder (axis along local z in both);
- capsule -> a cylinder and one sphere at each end;
- plane -> a thin cube of the plane's finite size (only when ``include_planes``);
- mesh, height field and SDF geoms are skipped.

This module knows nothing of Foxglove itself: the recorder converts these dataclasses.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Literal

import mujoco
import numpy as np
from scipy.spatial.transform import Rotation

from baobab.sim.builder import MOVABLE_GROUP, MOVABLE_PARK_DISTANCE, ROBOT_GROUP, STATIC_GROUP
from baobab.sim.world import Pose2D

Vector3 = tuple[float, float, float]
Quaternion = tuple[float, float, float, float]
"""x, y, z, w."""
Rgba = tuple[float, float, float, float]
"""Red, green, blue, alpha in [0, 1]."""

Shape = Literal["cube", "sphere", "cylinder"]

IDENTITY: Quaternion = (0.0, 0.0, 0.0, 1.0)
PLANE_THICKNESS = 0.002
"""Thickness (m) of the cube drawn for a plane; its top face lies in the plane."""

LOCATION_COLOUR: Rgba = (0.20, 0.45, 0.85, 0.9)


@dataclass(frozen=True)
class Primitive:
    """A cube, sphere or cylinder (axis along local z) in its entity's frame.

    Attributes:
        shape: "cube", "sphere" or "cylinder".
        position: centre (m).
        orientation: quaternion x, y, z, w.
        size: full extents along local x, y, z (m): a cylinder of radius r and length l has
            size (2r, 2r, l).
        colour: RGBA in [0, 1].
    """

    shape: Shape
    position: Vector3
    orientation: Quaternion
    size: Vector3
    colour: Rgba


@dataclass(frozen=True)
class Arrow:
    """An arrow from ``position`` along the local +x axis of ``orientation``, ``length`` m long."""

    position: Vector3
    orientation: Quaternion
    length: float
    colour: Rgba


@dataclass(frozen=True)
class Label:
    """Text at ``position`` (m), ``font_size`` m tall, always facing the viewer."""

    text: str
    position: Vector3
    font_size: float = 0.12
    colour: Rgba = (0.1, 0.1, 0.1, 1.0)


@dataclass(frozen=True)
class Outline:
    """A closed line through ``points`` (m, in its entity's frame), ``thickness`` m wide."""

    points: tuple[Vector3, ...]
    colour: Rgba
    thickness: float = 0.01


@dataclass(frozen=True)
class Entity:
    """One scene entity: an id (replaced by later entities with the same id) and its parts."""

    id: str
    frame_id: str
    primitives: tuple[Primitive, ...] = ()
    arrows: tuple[Arrow, ...] = ()
    labels: tuple[Label, ...] = ()
    metadata: Mapping[str, str] = field(default_factory=dict)
    outlines: tuple[Outline, ...] = ()


@dataclass(frozen=True)
class _GeomInfo:
    geom_id: int
    shape: int
    size: np.ndarray
    colour: Rgba


class GeomScene:
    """The geoms of a model as primitives, one entity per body, at the poses of some data.

    Sizes and colours are read from the model once; :meth:`entities` reads only the poses.
    Geoms farther than ``hide_beyond`` from the origin along x or y are left out: that is
    where the builder parks unused movable-obstacle slots.

    Args:
        model: the compiled model.
        groups: geom groups to include (default: static obstacles, movable obstacles, robots).
        frame_id: frame of the entities; the world frame of the sim (``map`` for mobile
            robots, which localise perfectly, ``world`` for an arm's scene).
        include_planes: draw finite planes as thin cubes.
        hide_beyond: distance (m) along x or y past which a geom is not drawn.
        id_prefix: prepended to every entity id (body names), to keep topics apart.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        *,
        groups: Iterable[int] = (STATIC_GROUP, MOVABLE_GROUP, ROBOT_GROUP),
        frame_id: str = "map",
        include_planes: bool = False,
        hide_beyond: float = MOVABLE_PARK_DISTANCE / 2,
        id_prefix: str = "",
    ) -> None:
        wanted = set(groups)
        drawable = {
            mujoco.mjtGeom.mjGEOM_BOX,
            mujoco.mjtGeom.mjGEOM_SPHERE,
            mujoco.mjtGeom.mjGEOM_ELLIPSOID,
            mujoco.mjtGeom.mjGEOM_CYLINDER,
            mujoco.mjtGeom.mjGEOM_CAPSULE,
        }
        if include_planes:
            drawable.add(mujoco.mjtGeom.mjGEOM_PLANE)
        self.frame_id = frame_id
        self.hide_beyond = hide_beyond
        self._by_body: dict[str, list[_GeomInfo]] = {}
        for geom_id in range(model.ngeom):
            shape = int(model.geom_type[geom_id])
            if int(model.geom_group[geom_id]) not in wanted or shape not in drawable:
                continue
            if shape == mujoco.mjtGeom.mjGEOM_PLANE and not all(model.geom_size[geom_id][:2] > 0):
                continue  # an infinite plane has no extent to draw
            body_id = int(model.geom_bodyid[geom_id])
            body_name = model.body(body_id).name or f"body_{body_id}"
            info = _GeomInfo(
                geom_id, shape, model.geom_size[geom_id].copy(), _geom_colour(model, geom_id)
            )
            self._by_body.setdefault(id_prefix + body_name, []).append(info)

    @property
    def entity_ids(self) -> list[str]:
        """Ids of the entities :meth:`entities` may return, one per body with drawn geoms."""
        return list(self._by_body)

    def entities(self, data: mujoco.MjData) -> list[Entity]:
        """One entity per body, its geoms at their current world poses (from ``data``).

        ``data`` must have been through ``mj_forward`` or ``mj_step`` (geom poses are read
        from ``geom_xpos`` / ``geom_xquat``).
        """
        entities = []
        for entity_id, infos in self._by_body.items():
            primitives: list[Primitive] = []
            for info in infos:
                position = data.geom_xpos[info.geom_id]
                if max(abs(position[0]), abs(position[1])) > self.hide_beyond:
                    continue
                w, x, y, z = (float(v) for v in data.geom_xquat[info.geom_id])
                axis_z = data.geom_xmat[info.geom_id].reshape(3, 3)[:, 2]
                primitives.extend(_primitives(info, position, (x, y, z, w), axis_z))
            if primitives:
                entities.append(Entity(entity_id, self.frame_id, tuple(primitives)))
        return entities


def _geom_colour(model: mujoco.MjModel, geom_id: int) -> Rgba:
    """The geom's rgba, or its material's when the geom keeps MuJoCo's default grey."""
    rgba = model.geom_rgba[geom_id]
    material = int(model.geom_matid[geom_id])
    if material >= 0 and np.allclose(rgba, (0.5, 0.5, 0.5, 1.0)):
        rgba = model.mat_rgba[material]
    r, g, b, a = (float(v) for v in rgba)
    return (r, g, b, a)


def _primitives(
    info: _GeomInfo, position: np.ndarray, quaternion: Quaternion, axis_z: np.ndarray
) -> list[Primitive]:
    """Primitives of one geom at ``position`` / ``quaternion``; ``axis_z``: its local z in world."""
    size, colour = info.size, info.colour
    centre: Vector3 = (float(position[0]), float(position[1]), float(position[2]))
    if info.shape == mujoco.mjtGeom.mjGEOM_BOX:
        return [Primitive("cube", centre, quaternion, _vec(2 * size), colour)]
    if info.shape == mujoco.mjtGeom.mjGEOM_SPHERE:
        d = 2 * float(size[0])
        return [Primitive("sphere", centre, quaternion, (d, d, d), colour)]
    if info.shape == mujoco.mjtGeom.mjGEOM_ELLIPSOID:
        return [Primitive("sphere", centre, quaternion, _vec(2 * size), colour)]
    if info.shape == mujoco.mjtGeom.mjGEOM_PLANE:
        # The plane's normal is its local z: move the thin cube down so its top is the plane.
        below = _vec(position - axis_z * PLANE_THICKNESS / 2)
        extents = (2 * float(size[0]), 2 * float(size[1]), PLANE_THICKNESS)
        return [Primitive("cube", below, quaternion, extents, colour)]
    radius, half_length = float(size[0]), float(size[1])
    d = 2 * radius
    cylinder = Primitive("cylinder", centre, quaternion, (d, d, 2 * half_length), colour)
    if info.shape == mujoco.mjtGeom.mjGEOM_CYLINDER:
        return [cylinder]
    axis = axis_z * half_length
    caps = [
        Primitive("sphere", _vec(position + sign * axis), quaternion, (d, d, d), colour)
        for sign in (1.0, -1.0)
    ]
    return [cylinder, *caps]


def _vec(values: np.ndarray) -> Vector3:
    return (float(values[0]), float(values[1]), float(values[2]))


def yaw_quaternion(yaw: float) -> Quaternion:
    """The quaternion (x, y, z, w) of a rotation by ``yaw`` (rad) about z."""
    x, y, z, w = (float(v) for v in Rotation.from_euler("z", yaw).as_quat())
    return (x, y, z, w)


def location_entities(
    locations: Mapping[str, Pose2D],
    *,
    frame_id: str = "map",
    colour: Rgba = LOCATION_COLOUR,
    radius: float = 0.08,
    id_prefix: str = "location/",
) -> list[Entity]:
    """Named poses as markers: a flat disc, an arrow along the yaw and the name above.

    Args:
        locations: name -> planar pose (m, rad) in ``frame_id``.
        frame_id: frame of the poses.
        colour: disc and arrow colour.
        radius: disc radius (m); the arrow is three radii long.
        id_prefix: prepended to each location name to form the entity id.
    """
    entities = []
    for name, pose in locations.items():
        orientation = yaw_quaternion(pose.yaw)
        disc = Primitive(
            "cylinder", (pose.x, pose.y, 0.005), IDENTITY, (2 * radius, 2 * radius, 0.01), colour
        )
        arrow = Arrow((pose.x, pose.y, 0.02), orientation, 3 * radius, colour)
        label = Label(name, (pose.x, pose.y, 0.25))
        entities.append(
            Entity(id_prefix + name, frame_id, (disc,), (arrow,), (label,), {"kind": "location"})
        )
    return entities
