"""Docking leaves: ``dock_robot`` and ``undock_robot`` (Nav2's docking server).

``dock_robot`` docks at a dock of the world by its name (``dock_id``, the dock database's id)
or at a ``dock_pose`` (the docked base's pose, a location name or a pose), navigating to the
staging pose first unless ``navigate_to_staging_pose`` is false. It fails with Nav2's DockRobot
codes (``FAILED_TO_STAGE`` 903, ``FAILED_TO_DETECT_DOCK`` 904, ``FAILED_TO_CONTROL`` 905, ...).
``undock_robot`` backs out of the dock to its staging pose.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pydantic import Field, ValidationInfo, model_validator

from baobab.behaviours.ports import NAVIGATION
from baobab.behaviours.poses import MissionScope, PoseRef
from baobab.behaviours.registry import BehaviourType, BuildRequest, NodeKind, NodeParams
from baobab.sim.errors import unknown_name
from baobab.sim.yaml_source import FieldValueError

if TYPE_CHECKING:  # imported by the factories, when a tree is built (validation needs none)
    import py_trees


class DockRobotParams(NodeParams):
    """Dock at the world's dock ``dock_id``, or at ``dock_pose``; then charge."""

    dock_id: str | None = Field(default=None, description="a dock of the world, by name")
    dock_pose: PoseRef | None = Field(
        default=None, description="where the docked base stands, instead of dock_id"
    )
    navigate_to_staging_pose: bool = Field(
        default=True, description="navigate to the staging pose first"
    )

    @model_validator(mode="after")
    def _one_dock(self, info: ValidationInfo) -> DockRobotParams:
        if (self.dock_id is None) == (self.dock_pose is None):
            raise FieldValueError(("dock_id",), "give either dock_id or dock_pose (one of them)")
        world = MissionScope.of(info).world
        if self.dock_id is not None and world is not None and self.dock_id not in world.docks:
            raise FieldValueError(("dock_id",), unknown_name("dock", self.dock_id, world.docks))
        return self

    def summary(self) -> str:
        """The dock."""
        if self.dock_id is not None:
            return self.dock_id
        assert self.dock_pose is not None
        return self.dock_pose.describe()


class UndockRobotParams(NodeParams):
    """Back out of the dock to its staging pose."""


def _dock_robot(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    params = request.params_as(DockRobotParams)
    dock_id = params.dock_id or ""
    pose = None if params.dock_pose is None else params.dock_pose.pose2d()
    staging = params.navigate_to_staging_pose
    return request.goal_task(lambda caps: caps.navigation_port().dock_robot(dock_id, pose, staging))


def _undock_robot(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    return request.goal_task(lambda caps: caps.navigation_port().undock_robot())


NODE_TYPES = (
    BehaviourType(
        "dock_robot",
        NodeKind.ACTION,
        DockRobotParams,
        "dock at a charging dock and charge",
        _dock_robot,
        capability=NAVIGATION,
        shorthand="dock_id",
    ),
    BehaviourType(
        "undock_robot",
        NodeKind.ACTION,
        UndockRobotParams,
        "back out of the dock",
        _undock_robot,
        capability=NAVIGATION,
    ),
)
"""The docking node types."""
