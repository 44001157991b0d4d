"""Arm nodes: Cartesian tool moves, the gripper, and a check on where an object lies.

A pick reads naturally with relative targets, which are resolved when the move starts::

    - move_to: {relative_to: cube, offset: [0, 0, 0.10], orientation: [1, 0, 0, 0]}  # pregrasp
    - gripper: open
    - move_to: {relative_to: cube, offset: [0, 0, 0.0], duration: 1.5}              # descend
    - gripper: close
    - move_to: {relative_to: tcp, offset: [0, 0, 0.15]}                              # lift
    - move_to: {pose: place_above, duration: 3.0}                                    # place target

Offsets are in the world frame (m). Without ``orientation`` the tool keeps the orientation of a
given ``pose``, or else its current orientation.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Annotated, Literal

from pydantic import Field, ValidationInfo, model_validator

from baobab.behaviours.ports import ARM, Capabilities
from baobab.behaviours.poses import ArmPose, MissionScope, vector_norm
from baobab.behaviours.registry import BehaviourType, BuildRequest, NodeKind, NodeParams
from baobab.sim.errors import unknown_name
from baobab.sim.tasks import TaskHandle
from baobab.sim.yaml_source import FieldValueError

if TYPE_CHECKING:  # imported by the factories, when a tree is built (validation needs none)
    import py_trees

Finite = Annotated[float, Field(allow_inf_nan=False)]
TCP = "tcp"
"""``relative_to: tcp`` moves relative to the tool's current position."""


def _check_object(name: str, info: ValidationInfo, key: str, allow_tcp: bool) -> None:
    robot = MissionScope.of(info).robot
    valid = [*robot.scene_objects, *([TCP] if allow_tcp else [])]
    if name not in valid:
        raise FieldValueError((key,), unknown_name("object", name, valid))


class MoveToParams(NodeParams):
    """Move the tool centre point to a pose, or to an offset from an object or the tool."""

    pose: ArmPose | None = Field(default=None, description="spatial pose or location name")
    relative_to: str | None = Field(default=None, description="an object name, or tcp")
    offset: tuple[Finite, Finite, Finite] = Field(
        default=(0.0, 0.0, 0.0), description="added to the target position, world frame, m"
    )
    orientation: tuple[Finite, Finite, Finite, Finite] | None = Field(
        default=None, description="tool quaternion x, y, z, w; default: keep"
    )
    duration: float = Field(default=2.0, gt=0, allow_inf_nan=False, description="s")

    @model_validator(mode="after")
    def _one_target(self, info: ValidationInfo) -> MoveToParams:
        if (self.pose is None) == (self.relative_to is None):
            raise ValueError("give exactly one of pose or relative_to")
        if self.relative_to is not None:
            _check_object(self.relative_to, info, "relative_to", allow_tcp=True)
        if self.orientation is not None and vector_norm(self.orientation) < 1e-9:
            raise FieldValueError(("orientation",), "orientation quaternion has zero norm")
        return self

    def summary(self) -> str:
        """The target."""
        if self.pose is not None:
            return self.pose.location or "pose"
        return f"{self.relative_to} + {list(self.offset)}"


class GripperParams(NodeParams):
    """Open or close the gripper."""

    command: Literal["open", "close"]

    def summary(self) -> str:
        """The command."""
        return self.command


class ObjectAtParams(NodeParams):
    """Succeed when ``object`` lies within ``tolerance`` m of ``target``, else fail."""

    object: str = Field(description="a free object of the scene, e.g. cube")
    target: ArmPose = Field(description="spatial pose or location name; its position counts")
    tolerance: float = Field(default=0.02, gt=0, allow_inf_nan=False, description="m")

    @model_validator(mode="after")
    def _known_object(self, info: ValidationInfo) -> ObjectAtParams:
        _check_object(self.object, info, "object", allow_tcp=False)
        return self

    def summary(self) -> str:
        """``cube @ place``."""
        return f"{self.object} @ {self.target.location or 'pose'}"


def _normalised(quaternion: Sequence[float]) -> tuple[float, ...]:
    norm = vector_norm(quaternion)
    return tuple(float(v) / norm for v in quaternion)


def _send_move(params: MoveToParams, caps: Capabilities) -> TaskHandle:
    arm = caps.arm_port()
    if params.pose is not None:
        position, orientation = params.pose.position, params.pose.orientation
    elif params.relative_to == TCP:
        position, orientation = arm.tcp_pose()
    else:
        position, orientation = arm.object_position(str(params.relative_to)), arm.tcp_pose()[1]
    if params.orientation is not None:
        orientation = params.orientation
    target = [p + o for p, o in zip(position, params.offset, strict=True)]
    return arm.move_to(target, _normalised(orientation), params.duration)


def _move_to(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    params = request.params_as(MoveToParams)
    return request.goal_task(lambda caps: _send_move(params, caps))


def _gripper(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    command = request.params_as(GripperParams).command
    return request.goal_task(lambda caps: caps.arm_port().gripper(command))


def _object_at(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    from baobab.behaviours.conditions import ObjectNear

    params = request.params_as(ObjectAtParams)
    caps = request.capabilities
    return ObjectNear(
        request.name,
        lambda: caps.arm_port().object_position(params.object),
        params.target.position,
        params.tolerance,
    )


NODE_TYPES = (
    BehaviourType(
        "move_to",
        NodeKind.ACTION,
        MoveToParams,
        "move the tool to a pose or an offset from an object or the tool",
        _move_to,
        capability=ARM,
        shorthand="pose",
    ),
    BehaviourType(
        "gripper",
        NodeKind.ACTION,
        GripperParams,
        "open or close the gripper",
        _gripper,
        capability=ARM,
        shorthand="command",
    ),
    BehaviourType(
        "object_at",
        NodeKind.CONDITION,
        ObjectAtParams,
        "succeed when an object lies within tolerance of a target",
        _object_at,
        capability=ARM,
    ),
)
"""The arm node types."""
