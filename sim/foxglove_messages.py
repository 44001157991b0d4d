"""Plain data as Foxglove message objects: times, vectors, poses, colours, scene entities, JSON.

The conversions :class:`~baobab.sim.recording.Recorder` uses: quaternions are x, y, z, w, times
are integer nanoseconds, JSON loses numpy types and non-finite floats.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from foxglove import messages as fm
from scipy.spatial.transform import Rotation

from baobab.sim.scene_primitives import IDENTITY, Entity, Rgba


def yaw_quaternions(yaws: np.ndarray) -> np.ndarray:
    """Quaternions (x, y, z, w) of rotations by ``yaws`` (rad) about z, one scipy call."""
    if len(yaws) == 0:
        return np.empty((0, 4))
    return np.asarray(Rotation.from_euler("z", yaws.reshape(-1, 1)).as_quat()).reshape(-1, 4)


def timestamp(ns: int) -> fm.Timestamp:
    sec, nsec = divmod(ns, 1_000_000_000)
    return fm.Timestamp(sec, nsec)


def vector3(values: Sequence[float] | np.ndarray) -> fm.Vector3:
    return fm.Vector3(x=float(values[0]), y=float(values[1]), z=float(values[2]))


def quaternion(values: Sequence[float] | np.ndarray) -> fm.Quaternion:
    x, y, z, w = (float(v) for v in values)
    return fm.Quaternion(x=x, y=y, z=z, w=w)


def pose(
    position: Sequence[float] | np.ndarray, orientation: Sequence[float] | np.ndarray
) -> fm.Pose:
    return fm.Pose(position=vector3(position), orientation=quaternion(orientation))


def color(rgba: Rgba) -> fm.Color:
    r, g, b, a = rgba
    return fm.Color(r=r, g=g, b=b, a=a)


def scene_entity(entity: Entity, stamp: fm.Timestamp) -> fm.SceneEntity:
    cubes, spheres, cylinders = [], [], []
    for p in entity.primitives:
        where, size, colour = pose(p.position, p.orientation), vector3(p.size), color(p.colour)
        if p.shape == "cube":
            cubes.append(fm.CubePrimitive(pose=where, size=size, color=colour))
        elif p.shape == "sphere":
            spheres.append(fm.SpherePrimitive(pose=where, size=size, color=colour))
        else:
            cylinders.append(
                fm.CylinderPrimitive(
                    pose=where, size=size, bottom_scale=1.0, top_scale=1.0, color=colour
                )
            )
    arrows = [
        fm.ArrowPrimitive(
            pose=pose(a.position, a.orientation),
            shaft_length=0.7 * a.length,
            shaft_diameter=0.08 * a.length,
            head_length=0.3 * a.length,
            head_diameter=0.2 * a.length,
            color=color(a.colour),
        )
        for a in entity.arrows
    ]
    texts = [
        fm.TextPrimitive(
            pose=pose(label.position, IDENTITY),
            billboard=True,
            font_size=label.font_size,
            color=color(label.colour),
            text=label.text,
        )
        for label in entity.labels
    ]
    lines = [
        fm.LinePrimitive(
            type=fm.LinePrimitiveLineType.LineLoop,
            pose=pose((0.0, 0.0, 0.0), IDENTITY),
            thickness=outline.thickness,
            scale_invariant=False,
            points=[fm.Point3(x=x, y=y, z=z) for x, y, z in outline.points],
            color=color(outline.colour),
        )
        for outline in entity.outlines
    ]
    return fm.SceneEntity(
        timestamp=stamp,
        frame_id=entity.frame_id,
        id=entity.id,
        metadata=[fm.KeyValuePair(key=k, value=v) for k, v in entity.metadata.items()],
        cubes=cubes,
        spheres=spheres,
        cylinders=cylinders,
        arrows=arrows,
        texts=texts,
        lines=lines,
    )


def jsonable(value: Any) -> Any:
    """``value`` with numpy types as Python ones and non-finite floats as None."""
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple | np.ndarray):
        return [jsonable(v) for v in value]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
