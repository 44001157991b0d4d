"""The behaviour registry: every node type a mission tree may use, registered once.

An entry names the type as written in YAML, its kind (composite, decorator, action,
condition, subtree), a pydantic parameter model, the capability it needs, a one-line
description and a factory that builds the py_trees behaviour. Validation, ``baobab list``,
the JSON Schema and the BehaviorTree.CPP ``TreeNodesModel`` are all read from here, so they
cannot drift apart.
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Annotated, Any, TypeVar

from pydantic import ConfigDict, Field, WithJsonSchema
from pydantic.fields import FieldInfo

from baobab.behaviours.ports import Capabilities
from baobab.sim.errors import BaobabError
from baobab.sim.tasks import TaskHandle
from baobab.sim.yaml_models import YamlModel

if TYPE_CHECKING:  # factories import py_trees when they build, so validation never loads it
    import py_trees

P = TypeVar("P", bound="NodeParams")
NODE_SCHEMA_MARKER = "x-baobab-node"
"""Stands for ``{"$ref": "#/$defs/Node"}`` until the mission's JSON Schema is assembled
(:mod:`baobab.missions.language.json_schema`)."""
NodeData = Annotated[Any, WithJsonSchema({NODE_SCHEMA_MARKER: True})]
"""One behaviour-tree node as written: a single-key mapping ``{type: parameters}``."""
STRUCTURAL_FIELDS = ("name", "children", "child")
"""Parameter fields every node may have or that hold children: not ports of the node."""


class RegistryError(BaobabError):
    """A behaviour type was registered twice, or under an invalid name."""


class NodeKind(enum.Enum):
    """How a node type relates to its children."""

    COMPOSITE = "composite"
    DECORATOR = "decorator"
    ACTION = "action"
    CONDITION = "condition"
    SUBTREE = "subtree"


class NodeParams(YamlModel):
    """Base of every node's parameter model: unknown keys are refused.

    The models build their validators when first used, not when defined: a mission uses a
    few of the node types, and building every one would be most of ``baobab validate``'s
    start-up time.
    """

    model_config = ConfigDict(extra="forbid", frozen=True, defer_build=True)

    name: str | None = Field(default=None, description="label in tree views and traces")

    def summary(self) -> str:
        """A few words that tell this node apart in a tree view (e.g. the goal's name)."""
        return ""


@dataclass(frozen=True)
class BuildRequest:
    """What a factory gets: validated parameters, the label, built children and the ports."""

    params: NodeParams
    name: str
    children: Sequence[py_trees.behaviour.Behaviour]
    capabilities: Capabilities

    def params_as(self, model: type[P]) -> P:
        """The parameters, typed as the factory's own model."""
        if not isinstance(self.params, model):
            raise TypeError(f"expected {model.__name__}, got {type(self.params).__name__}")
        return self.params

    @property
    def child(self) -> py_trees.behaviour.Behaviour:
        """The one child of a decorator."""
        return self.children[0]

    def goal_task(self, send: Callable[[Capabilities], TaskHandle]) -> py_trees.behaviour.Behaviour:
        """A leaf that sends one goal per activation, ``send(capabilities)``, and reports the
        task's status (:class:`~baobab.behaviours.actions.GoalTaskLeaf`)."""
        from baobab.behaviours.actions import GoalTaskLeaf  # py_trees: only to build a tree

        capabilities = self.capabilities
        return GoalTaskLeaf(self.name, lambda: send(capabilities))


Factory = Callable[[BuildRequest], "py_trees.behaviour.Behaviour"]


@dataclass(frozen=True)
class BehaviourType:
    """One registered node type.

    Attributes:
        name: the type as written in YAML (``navigate_to_pose``).
        kind: composite, decorator, action, condition or subtree.
        params: the pydantic parameter model (a :class:`NodeParams`).
        description: one line for ``baobab list``, the schema and Groot.
        factory: builds the py_trees behaviour.
        capability: the robot capability the node needs, or None.
        shorthand: the parameter a bare value fills (``wait: 5`` -> ``duration``); for
            composites ``children`` (a list), for decorators ``child`` (a node mapping).
        pose_shorthand: a bare pose mapping (``{x: 1, y: 2}``) fills ``shorthand``.
    """

    name: str
    kind: NodeKind
    params: type[NodeParams]
    description: str
    factory: Factory
    capability: str | None = None
    shorthand: str | None = None
    pose_shorthand: bool = False

    @property
    def xml_id(self) -> str:
        """BehaviorTree.CPP-style ID: ``navigate_to_pose`` -> ``NavigateToPose``."""
        return "".join(part.capitalize() for part in self.name.split("_"))

    def ports(self) -> dict[str, FieldInfo]:
        """The parameter fields that are data ports (not name or children)."""
        return {
            key: info
            for key, info in self.params.model_fields.items()
            if key not in STRUCTURAL_FIELDS
        }


class Registry:
    """Behaviour types by name; each name may be registered once."""

    def __init__(self) -> None:
        self._types: dict[str, BehaviourType] = {}

    def register(self, behaviour_type: BehaviourType) -> BehaviourType:
        """Add a type; :class:`RegistryError` if the name is taken or malformed."""
        name = behaviour_type.name
        if not name.isidentifier() or name != name.lower():
            raise RegistryError(f"behaviour type name '{name}' must be a lower_case identifier")
        if name in self._types:
            raise RegistryError(f"behaviour type '{name}' is already registered")
        shorthand = behaviour_type.shorthand
        if shorthand is not None and shorthand not in behaviour_type.params.model_fields:
            raise RegistryError(f"shorthand '{shorthand}' is not a parameter of '{name}'")
        self._types[name] = behaviour_type
        return behaviour_type

    def get(self, name: str) -> BehaviourType | None:
        """The type called ``name``, or None."""
        return self._types.get(name)

    def __contains__(self, name: object) -> bool:
        return name in self._types

    def __iter__(self) -> Iterator[BehaviourType]:
        return iter(self._types.values())

    def __len__(self) -> int:
        return len(self._types)

    def names(self) -> list[str]:
        """Registered names in registration order."""
        return list(self._types)


def node_label(behaviour_type: BehaviourType, params: NodeParams) -> str:
    """The node's label: its ``name`` if given, else the type and a short summary."""
    if behaviour_type.kind is NodeKind.SUBTREE:
        return f"subtree {params.summary()}"
    if params.name:
        return params.name
    return f"{behaviour_type.name} {params.summary()}".strip()
