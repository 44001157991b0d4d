"""Poses in mission files, and the scope that gives location names and free space a meaning.

A pose is written as ``{x, y, yaw}`` or ``{x, y, yaw_deg}`` (planar), as
``{position: [x, y, z], orientation: [qx, qy, qz, qw]}`` (spatial; the quaternion is
normalised, a zero one is refused), or as a location name. A planar robot uses a spatial
pose's x, y and the yaw of its orientation. Pydantic fields typed :data:`PoseRef`,
:data:`GoalPose` or :data:`ArmPose` resolve names and check free space while they validate,
reading the :class:`MissionScope` from the validation context.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any

from pydantic import (
    ConfigDict,
    Field,
    GetJsonSchemaHandler,
    PlainValidator,
    ValidationInfo,
    model_validator,
)
from pydantic_core import CoreSchema

from baobab.robots.catalog import RobotInfo
from baobab.sim.errors import unknown_name
from baobab.sim.point_clearance import obstacle_distances_at
from baobab.sim.world import Pose2D, World
from baobab.sim.yaml_models import YamlModel
from baobab.sim.yaml_source import FieldValueError

Finite = Annotated[float, Field(allow_inf_nan=False)]
IDENTITY_XYZW = (0.0, 0.0, 0.0, 1.0)
SCOPE_KEY = "mission_scope"
"""The key of the :class:`MissionScope` in a pydantic validation context."""


@dataclass(frozen=True)
class Pose:
    """A resolved pose: position (m) and unit quaternion (x, y, z, w) in the world frame.

    Attributes:
        position: x, y, z (m).
        orientation: unit quaternion x, y, z, w.
        location: the location name it was written as, if any.
        planar: True when written as x, y, yaw (z = 0, rotation about z only).
    """

    position: tuple[float, float, float]
    orientation: tuple[float, float, float, float] = IDENTITY_XYZW
    location: str | None = None
    planar: bool = True

    @classmethod
    def from_planar(cls, x: float, y: float, yaw: float) -> Pose:
        """A planar pose at (x, y) (m) heading ``yaw`` (rad)."""
        return cls((x, y, 0.0), (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)))

    @property
    def x(self) -> float:
        """x (m)."""
        return self.position[0]

    @property
    def y(self) -> float:
        """y (m)."""
        return self.position[1]

    @property
    def yaw(self) -> float:
        """Heading (rad): the rotation about z of the orientation (ZYX Euler yaw)."""
        qx, qy, qz, qw = self.orientation
        if qx == 0.0 and qy == 0.0:  # a rotation about z only: its angle, exactly
            return math.remainder(2.0 * math.atan2(qz, qw), math.tau)
        from scipy.spatial.transform import Rotation  # ~0.4 s to import: only when needed

        return float(Rotation.from_quat(self.orientation).as_euler("ZYX")[0])

    def pose2d(self) -> Pose2D:
        """The planar pose a mobile base uses."""
        return Pose2D(x=self.x, y=self.y, yaw=self.yaw)

    def named(self, location: str) -> Pose:
        """The same pose, remembered as coming from ``location``."""
        return Pose(self.position, self.orientation, location, self.planar)

    def describe(self) -> str:
        """``'table_3' (0.79, -8.27)`` or ``(0.79, -8.27)`` for messages."""
        where = f"({self.x:.2f}, {self.y:.2f})"
        return f"'{self.location}' {where}" if self.location else where


class _Strict(YamlModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class PlanarPose(_Strict):
    """A planar pose: ``x``, ``y`` (m) and a heading as ``yaw`` (rad) or ``yaw_deg`` (deg)."""

    x: Finite
    y: Finite
    yaw: Finite | None = Field(default=None, description="heading (rad), default 0")
    yaw_deg: Finite | None = Field(default=None, description="heading (deg), instead of yaw")

    @model_validator(mode="after")
    def _one_heading(self) -> PlanarPose:
        if self.yaw is not None and self.yaw_deg is not None:
            raise FieldValueError(("yaw_deg",), "give either yaw (rad) or yaw_deg (deg), not both")
        return self

    def to_pose(self) -> Pose:
        """The resolved pose."""
        yaw = math.radians(self.yaw_deg) if self.yaw_deg is not None else (self.yaw or 0.0)
        return Pose.from_planar(self.x, self.y, yaw)


class SpatialPose(_Strict):
    """A 3D pose: ``position`` [x, y, z] (m), ``orientation`` [qx, qy, qz, qw] (normalised)."""

    position: tuple[Finite, Finite, Finite]
    orientation: tuple[Finite, Finite, Finite, Finite] = Field(
        default=IDENTITY_XYZW, description="quaternion x, y, z, w; normalised on load"
    )

    @model_validator(mode="after")
    def _unit_quaternion(self) -> SpatialPose:
        if vector_norm(self.orientation) < 1e-9:
            raise FieldValueError(("orientation",), "orientation quaternion has zero norm")
        return self

    def to_pose(self) -> Pose:
        """The resolved pose, with a unit quaternion."""
        norm = vector_norm(self.orientation)
        x, y, z, w = (float(v) / norm for v in self.orientation)
        return Pose(self.position, (x, y, z, w), planar=False)


def vector_norm(vector: Sequence[float]) -> float:
    """Euclidean norm, summed in order as numpy's norm does for short vectors (bit-identical)."""
    return math.sqrt(sum(float(v) * float(v) for v in vector))


@functools.cache
def _written_pose_schemas() -> tuple[dict[str, Any], ...]:
    return PlanarPose.model_json_schema(), SpatialPose.model_json_schema()


@dataclass(frozen=True)
class PoseJsonSchema:
    """``WithJsonSchema`` for pose fields, made when a JSON Schema is asked for.

    Generating the pose models' JSON Schemas takes a few milliseconds, which every command
    would pay at import (``baobab validate`` never needs them).

    Attributes:
        names: a location name is also accepted (``anyOf`` begins with a string).
    """

    names: bool

    def __get_pydantic_json_schema__(
        self, core_schema: CoreSchema, handler: GetJsonSchemaHandler
    ) -> dict[str, Any]:
        """The pose schema, as ``WithJsonSchema`` gives it (a shallow copy)."""
        name = [{"type": "string", "description": "a location name"}] if self.names else []
        return {"anyOf": [*name, *_written_pose_schemas()]}


POSE_SCHEMA = PoseJsonSchema(names=False)
"""JSON Schema of a written pose (planar or spatial), as a field annotation."""
POSE_REF_SCHEMA = PoseJsonSchema(names=True)
"""JSON Schema of a location name or a written pose, as a field annotation."""


def parse_pose(value: Any) -> Pose:
    """A written pose (planar or spatial mapping, no names) -> :class:`Pose`."""
    if not isinstance(value, dict):
        raise ValueError(
            f"expected a pose {{x, y, yaw}} or {{position, orientation}}, got {value!r}"
        )
    if "position" in value or "orientation" in value:
        return SpatialPose.model_validate(value).to_pose()
    return PlanarPose.model_validate(value).to_pose()


@dataclass(frozen=True)
class MissionScope:
    """What poses in one mission may refer to: robot, world geometry and named locations."""

    robot: RobotInfo
    world: World | None
    locations: Mapping[str, Pose]
    folder: Path | None = None
    """The mission file's folder, which files the mission names are relative to."""

    @staticmethod
    def of(info: ValidationInfo) -> MissionScope:
        """The scope in a validation context; a programming error if it is missing."""
        scope = (info.context or {}).get(SCOPE_KEY)
        if not isinstance(scope, MissionScope):
            raise RuntimeError("mission models validate with a MissionScope in the context")
        return scope

    def location(self, name: str) -> Pose:
        """The pose of a named location, or a ValueError listing the valid names."""
        pose = self.locations.get(name)
        if pose is None:
            raise ValueError(unknown_name("location", name, self.locations))
        return pose

    def resolve(self, value: Any) -> Pose:
        """A location name or a written pose -> :class:`Pose`."""
        if isinstance(value, str):
            return self.location(value)
        if isinstance(value, dict):
            return parse_pose(value)
        raise ValueError(
            "expected a location name or a pose {x, y, yaw} / {position, orientation}, "
            f"got {value!r}"
        )

    def free_space_problem(self, pose: Pose) -> str | None:
        """Why a mobile base cannot stand at ``pose`` (off the floor, in an obstacle), or None.

        A circular footprint is checked by its centre's distance; a polygon at the pose's yaw,
        against the obstacles and the floor edge.
        """
        footprint = self.robot.footprint
        if self.world is None or footprint is None:
            return None
        world = self.world
        if not world.contains(pose.x, pose.y):
            x_min, y_min, x_max, y_max = world.bounds
            return (
                f"{pose.describe()} is outside the floor of world '{world.name}' "
                f"(x {x_min:g}..{x_max:g}, y {y_min:g}..{y_max:g})"
            )
        if not footprint.is_circle:
            name, clearance = footprint.clearance_in(world, pose.pose2d())
            if clearance > 0.0:
                return None
            return (
                f"{pose.describe()} is too narrow for robot '{self.robot.name}': its footprint "
                f"at yaw {pose.yaw:.2f} rad reaches {-clearance:.3f} m into '{name}'"
            )
        distances = obstacle_distances_at(world, pose.x, pose.y)
        if not distances:
            return None
        name, distance = min(distances, key=lambda item: item[1])  # the first of equals
        radius = self.robot.footprint_radius
        if distance <= 0.0:
            return f"{pose.describe()} is inside obstacle '{name}'"
        if distance < radius:
            return (
                f"{pose.describe()} is inside obstacle '{name}' for this robot: "
                f"{distance:.3f} m from it, less than the {radius} m footprint radius"
            )
        return None


def _pose_ref(value: Any, info: ValidationInfo) -> Pose:
    return MissionScope.of(info).resolve(value)


def _goal_pose(value: Any, info: ValidationInfo) -> Pose:
    scope = MissionScope.of(info)
    pose = scope.resolve(value)
    problem = scope.free_space_problem(pose)
    if problem is not None:
        raise ValueError(f"goal {problem}")
    return pose


def _arm_pose(value: Any, info: ValidationInfo) -> Pose:
    pose = MissionScope.of(info).resolve(value)
    if pose.planar:
        what = f"location '{pose.location}'" if pose.location else "this pose"
        raise ValueError(
            f"{what} is planar (x, y, yaw); an arm target needs "
            "{position: [x, y, z], orientation: [qx, qy, qz, qw]}"
        )
    return pose


PoseRef = Annotated[Pose, PlainValidator(_pose_ref), POSE_REF_SCHEMA]
"""A location name or a written pose."""

GoalPose = Annotated[Pose, PlainValidator(_goal_pose), POSE_REF_SCHEMA]
"""A pose a mobile base must reach: on the floor and clear of obstacles by its footprint."""

ArmPose = Annotated[Pose, PlainValidator(_arm_pose), POSE_REF_SCHEMA]
"""A spatial tool pose (or the name of a spatial location)."""
