"""The ``follow_object`` leaf: keep Nav2's desired distance from a moving object of the world.

The object is named by its pose ``topic`` (``followObjectByTopic``: heard while the lidar sees
it) or its TF ``frame`` (``followObjectByFrame``: always known), checked against the world's
moving objects. The leaf succeeds after ``max_duration`` s (0: it runs until halted, e.g. by a
``timeout`` or a parallel), and fails with Nav2's FollowObject codes
(``FAILED_TO_DETECT_OBJECT`` 902 when the object stays lost).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated

from pydantic import Field, ValidationInfo, model_validator

from baobab.behaviours.ports import NAVIGATION
from baobab.behaviours.poses import MissionScope
from baobab.behaviours.registry import BehaviourType, BuildRequest, NodeKind, NodeParams
from baobab.sim.errors import unknown_name
from baobab.sim.moving_objects import absolute_topic
from baobab.sim.yaml_source import FieldValueError

if TYPE_CHECKING:  # imported by the factory, when a tree is built (validation needs none)
    import py_trees


class FollowObjectParams(NodeParams):
    """Follow the moving object whose pose is on ``topic``, or whose TF frame is ``frame``."""

    topic: str | None = Field(default=None, description="the object's pose topic")
    frame: str | None = Field(default=None, description="the object's TF frame, instead")
    max_duration: Annotated[float, Field(ge=0, allow_inf_nan=False)] = Field(
        default=0.0, description="s of following before success; 0: until halted"
    )

    @model_validator(mode="after")
    def _one_source(self, info: ValidationInfo) -> FollowObjectParams:
        if (self.topic is None) == (self.frame is None):
            raise FieldValueError(("topic",), "give either topic or frame (one of them)")
        world = MissionScope.of(info).world
        if world is None:
            return self
        if self.topic is not None:
            topics = [item.pose_topic for item in world.moving_objects]
            if absolute_topic(self.topic) not in topics:
                what = "moving object topic"
                raise FieldValueError(("topic",), unknown_name(what, self.topic, topics))
        elif self.frame not in (frames := [item.tf_frame for item in world.moving_objects]):
            what = "moving object frame"
            raise FieldValueError(("frame",), unknown_name(what, str(self.frame), frames))
        return self

    def summary(self) -> str:
        """The topic or frame."""
        return str(self.topic if self.topic is not None else self.frame)


def _follow_object(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    params = request.params_as(FollowObjectParams)
    topic, frame, limit = params.topic or "", params.frame or "", params.max_duration
    return request.goal_task(lambda caps: caps.navigation_port().follow_object(topic, frame, limit))


NODE_TYPES = (
    BehaviourType(
        "follow_object",
        NodeKind.ACTION,
        FollowObjectParams,
        "keep a distance behind a moving object",
        _follow_object,
        capability=NAVIGATION,
        shorthand="topic",
    ),
)
"""The following node type."""
