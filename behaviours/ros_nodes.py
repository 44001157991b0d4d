"""The ``ros_node`` leaf: an rclpy node file running on the mission's robot, so that the
mission's ``expect:`` judges what the node did.

    ros_node: {script: ros/point2point_nav.py, params: {goal_tolerance: 0.05}}

The node file (relative to the mission file) runs as ``baobab ros run`` runs it, with the
robot on its ROS topics: its ``main()`` starts when the leaf starts, and the leaf stays
RUNNING for as long as the node's code runs. It succeeds when the code ends by itself, fails
when it raises (the traceback goes to standard error), and when its parent halts it (a
``parallel`` that succeeded on a sibling, a ``timeout``) the code gets a ``KeyboardInterrupt``
and its nodes are destroyed. ``params`` become ``-p`` overrides, ``remappings`` ``-r`` rules,
``node_name`` renames the node (``-r __node:=``), ``args`` come before ``--ros-args``.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

from pydantic import (
    Field,
    PrivateAttr,
    StringConstraints,
    ValidationInfo,
    field_validator,
    model_validator,
)

from baobab.behaviours.ports import ROS_NODES
from baobab.behaviours.poses import MissionScope
from baobab.behaviours.registry import BehaviourType, BuildRequest, NodeKind, NodeParams
from baobab.sim.yaml_source import FieldValueError

if TYPE_CHECKING:  # imported by the factory, when a tree is built (validation needs none)
    import py_trees

RosName = Annotated[str, StringConstraints(pattern=r"^[~/A-Za-z_][A-Za-z0-9_/~]*$")]


class RosNodeParams(NodeParams):
    """Run an rclpy node file on the mission's robot while the parent keeps this leaf."""

    script: str = Field(description="the node file, relative to the mission file")
    params: dict[str, Any] = Field(
        default_factory=dict,
        description="parameter overrides (--ros-args -p name:=value): booleans, numbers, "
        "texts or lists of one of these",
    )
    remappings: dict[RosName, RosName] = Field(
        default_factory=dict, description="topic renames (--ros-args -r from:=to)"
    )
    node_name: RosName | None = Field(default=None, description="rename the node (-r __node:=)")
    args: list[str] = Field(default_factory=list, description="arguments before --ros-args")

    _path: Path = PrivateAttr(default=Path())

    @field_validator("params")
    @classmethod
    def _parameter_values(cls, params: dict[str, Any]) -> dict[str, Any]:
        scalar = bool | int | float | str
        for name, value in params.items():
            items = value if isinstance(value, list) else [value]
            kinds = {float if type(item) is int else type(item) for item in items}
            if not all(isinstance(item, scalar) for item in items) or len(kinds) > 1:
                raise FieldValueError(
                    (name,),
                    "a parameter is a boolean, a number, a text or a list of one of these",
                )
        return params

    @model_validator(mode="after")
    def _script_exists(self, info: ValidationInfo) -> RosNodeParams:
        folder = MissionScope.of(info).folder
        path = Path(self.script) if folder is None else folder / self.script
        if not self.script.endswith(".py") or not path.is_file():
            raise FieldValueError(
                ("script",), f"no Python node file '{self.script}' next to the mission ({path})"
            )
        self._path = path
        return self

    @property
    def path(self) -> Path:
        """The node file (resolved against the mission's folder)."""
        return self._path

    def summary(self) -> str:
        """The script's name."""
        return Path(self.script).name

    def argv(self) -> list[str]:
        """The node file's command line after its path."""
        import yaml

        words = [*self.args, "--ros-args"]
        if self.node_name is not None:
            words += ["-r", f"__node:={self.node_name}"]
        for source, target in self.remappings.items():
            words += ["-r", f"{source}:={target}"]
        for name, value in self.params.items():
            text = yaml.safe_dump(value, default_flow_style=True).strip()
            words += ["-p", f"{name}:={text.removesuffix('...').strip()}"]
        return words


def _ros_node(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    from baobab.behaviours.actions import GoalTaskLeaf

    params = request.params_as(RosNodeParams)
    caps = request.capabilities
    return GoalTaskLeaf(
        request.name, lambda: caps.ros_nodes_port().start_node(params.path, params.argv())
    )


NODE_TYPES = (
    BehaviourType(
        "ros_node",
        NodeKind.ACTION,
        RosNodeParams,
        "run an rclpy node file on the robot while the parent keeps it",
        _ros_node,
        capability=ROS_NODES,
        shorthand="script",
    ),
)
"""The node types of this module (:mod:`baobab.behaviours.builtin` registers them)."""
