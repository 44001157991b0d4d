"""Behaviour-tree nodes as written -> validated :class:`Node` trees, subtrees expanded.

Each node is a single-key mapping ``{type: parameters}``. Parameters may be written in full
(``wait: {duration: 5}``) or in a short form: a bare value fills the type's shorthand parameter
(``wait: 5``, ``navigate_to_pose: kitchen``, ``gripper: open``), a list fills a composite's
children (``sequence: [...]``), a bare pose mapping fills a pose shorthand
(``navigate_to_pose: {x: 1, y: 2}``), a single node fills a decorator's child
(``invert: {is_at: door}``), and an empty value means no parameters.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

from pydantic import ValidationError

from baobab.behaviours.poses import SCOPE_KEY, MissionScope
from baobab.behaviours.registry import BehaviourType, NodeKind, NodeParams, Registry, node_label
from baobab.missions.language.errors import MissionError, describe_validation_error, located
from baobab.missions.language.models import SubtreeSpec
from baobab.missions.language.params import Substitution
from baobab.sim.errors import unknown_name
from baobab.sim.yaml_source import KeyPath, LocatedDocument

MAX_TREE_NODES = 10_000
"""Bound on the expanded tree (subtrees can multiply nodes)."""
POSE_KEYS = frozenset({"x", "y", "yaw", "yaw_deg", "position", "orientation"})


@dataclass(frozen=True)
class NodeShape:
    """A node's structure without validated parameters (used for subtree templates).

    Attributes:
        type: the node type.
        raw: its parameters as written, short forms expanded, children removed.
        children: child shapes.
        path: key path of the node mapping in the document.
    """

    type: str
    raw: dict[str, Any]
    children: tuple[NodeShape, ...]
    path: KeyPath


@dataclass(frozen=True)
class Node:
    """A validated node.

    Attributes:
        behaviour: its registry entry.
        params: validated parameters.
        raw: parameters as written (after substitution), short forms expanded, children removed.
        children: validated children; a subtree call has its expanded body as the one child.
        path: key path of the node mapping in the document (a subtree body's nodes point into
            ``subtrees:``).
    """

    behaviour: BehaviourType
    params: NodeParams
    raw: dict[str, Any]
    children: tuple[Node, ...]
    path: KeyPath

    @property
    def type(self) -> str:
        """The node type."""
        return self.behaviour.name

    @property
    def type_path(self) -> KeyPath:
        """Key path of the node's type key (where messages about the node point)."""
        return (*self.path, self.type)

    @property
    def label(self) -> str:
        """Its label in trees and traces."""
        return node_label(self.behaviour, self.params)

    def walk(self) -> list[Node]:
        """This node and all below it, depth first."""
        nodes = [self]
        for child in self.children:
            nodes.extend(child.walk())
        return nodes


@dataclass
class _Split:
    """One node taken apart: its type, the value as written, parameters, child entries."""

    behaviour: BehaviourType
    written: Any
    params: dict[str, Any]
    children: list[tuple[Any, KeyPath]] = field(default_factory=list)

    def data_params(self) -> dict[str, Any]:
        """The parameters without the children."""
        return {k: v for k, v in self.params.items() if k not in ("children", "child")}


class TreeParser:
    """Parses the main tree and expands subtrees, raising located :class:`MissionError`.

    Args:
        document: the mission document (for line and column).
        registry: the node types.
        scope: robot, world and locations, for capability and pose checks.
        subtrees: the file's subtrees.
        origins: key paths whose values came from a ``${param}`` (extended here).
    """

    def __init__(
        self,
        document: LocatedDocument,
        registry: Registry,
        scope: MissionScope,
        subtrees: Mapping[str, SubtreeSpec],
        origins: dict[KeyPath, str],
    ) -> None:
        self.document = document
        self.registry = registry
        self.scope = scope
        self.subtrees = subtrees
        self.origins = origins
        self._count = 0

    def _error(self, path: KeyPath, message: str) -> MissionError:
        return located(self.document, path, message, self.origins)

    # --- structure ------------------------------------------------------------------------

    def _split(self, raw: Any, path: KeyPath) -> _Split:
        if not isinstance(raw, dict):
            hint = ""
            if isinstance(raw, str) and raw in self.registry:
                hint = f" (write '{raw}: {{}}' for a node without parameters)"
            raise self._error(path, f"expected a node {{type: parameters}}, got {raw!r}{hint}")
        if not raw:
            raise self._error(path, "empty node; expected {type: parameters}")
        if len(raw) > 1:
            keys = list(raw)
            raise self._error(
                (*path, keys[1]),
                f"a node has exactly one key, its type; found {', '.join(keys)} "
                "(put parameters under the type, e.g. 'wait: {duration: 5}')",
            )
        ((type_name, written),) = raw.items()
        behaviour = self.registry.get(type_name)
        if behaviour is None:
            message = unknown_name("behaviour", type_name, self.registry.names())
            raise self._error((*path, type_name), message)
        at = (*path, type_name)
        params = self._expand_short_form(behaviour, written, at)
        split = _Split(behaviour, written, params)
        if behaviour.kind is NodeKind.COMPOSITE and isinstance(params.get("children"), list):
            base = at if isinstance(written, list) else (*at, "children")
            split.children = [
                (child, (*base, index)) for index, child in enumerate(params["children"])
            ]
        elif behaviour.kind is NodeKind.DECORATOR and "child" in params:
            base = at if "child" not in written else (*at, "child")
            split.children = [(params["child"], base)]
        return split

    def _expand_short_form(
        self, behaviour: BehaviourType, written: Any, at: KeyPath
    ) -> dict[str, Any]:
        fields = behaviour.params.model_fields
        if written is None:
            return {}
        if isinstance(written, dict):
            keys = set(written)
            if (
                behaviour.kind is NodeKind.DECORATOR
                and behaviour.shorthand == "child"
                and len(written) == 1
                and not keys & set(fields)
            ):
                return {"child": written}
            if behaviour.pose_shorthand and keys and keys <= POSE_KEYS:
                return {str(behaviour.shorthand): written}
            return dict(written)
        if behaviour.shorthand is None or behaviour.shorthand == "child":
            ports = [name for name in fields if name != "name"]
            example = (
                f"{behaviour.name}: {{{ports[0]}: ...}}" if ports else f"{behaviour.name}: {{}}"
            )
            raise self._error(
                at, f"{behaviour.name} takes a mapping of parameters, e.g. '{example}'"
            )
        if isinstance(written, list) and behaviour.kind is not NodeKind.COMPOSITE:
            annotation = str(fields[behaviour.shorthand].annotation)
            if "list" not in annotation:
                raise self._error(at, f"{behaviour.name} does not take a list")
        return {behaviour.shorthand: written}

    def shape(self, raw: Any, path: KeyPath) -> NodeShape:
        """The structure of a node tree, checking node types only (subtree templates)."""
        split = self._split(raw, path)
        children = tuple(self.shape(child, child_path) for child, child_path in split.children)
        return NodeShape(split.behaviour.name, split.data_params(), children, path)

    # --- validation -----------------------------------------------------------------------

    def parse(self, raw: Any, path: KeyPath, stack: tuple[str, ...] = ()) -> Node:
        """Validate the node at ``path`` and everything below it.

        Args:
            raw: the node as written (after substitution).
            path: its key path in the document.
            stack: the subtrees being expanded around it (to refuse cycles).
        """
        self._count += 1
        if self._count > MAX_TREE_NODES:
            raise self._error(
                path, f"the expanded tree has more than {MAX_TREE_NODES} nodes (MAX_TREE_NODES)"
            )
        split = self._split(raw, path)
        behaviour = split.behaviour
        type_name = behaviour.name
        at = (*path, type_name)
        if behaviour.capability and behaviour.capability not in self.scope.robot.capabilities:
            robot = self.scope.robot
            raise self._error(
                at,
                f"{type_name} needs capability '{behaviour.capability}'; robot '{robot.name}' "
                f"has: {robot.describe_capabilities()}",
            )
        try:
            params = behaviour.params.model_validate(split.params, context={SCOPE_KEY: self.scope})
        except ValidationError as exc:
            raise describe_validation_error(
                self.document,
                exc,
                data=split.written,
                base_path=at,
                label=type_name,
                model=behaviour.params,
                origins=self.origins,
                nouns={(): "parameter"},
            ) from None
        if behaviour.kind is NodeKind.SUBTREE:
            children: tuple[Node, ...] = (self._expand(params, at, stack),)
        else:
            children = tuple(
                self.parse(child, child_path, stack) for child, child_path in split.children
            )
        return Node(behaviour, params, split.data_params(), children, path)

    def _expand(self, call: NodeParams, at: KeyPath, stack: tuple[str, ...]) -> Node:
        name = str(call.name)
        args: dict[str, Any] = getattr(call, "args", {})
        spec = self.subtrees.get(name)
        if spec is None:
            raise self._error((*at, "name"), unknown_name("subtree", name, self.subtrees))
        if name in stack:
            chain = " -> ".join([*stack[stack.index(name) :], name])
            raise self._error((*at, "name"), f"subtree '{name}' uses itself: {chain}")
        for key in args:
            if key not in spec.params:
                message = unknown_name("argument", key, spec.params, f"subtree '{name}'")
                raise self._error((*at, "args", key), message)
        values: dict[str, Any] = {}
        for key, param in spec.params.items():
            if key in args:
                try:
                    values[key] = param.check(args[key])
                except ValueError as exc:
                    raise self._error(
                        (*at, "args", key), f"argument '{key}' of subtree '{name}': {exc}"
                    ) from None
            elif param.required:
                raise self._error(
                    at, f"subtree '{name}' needs argument '{key}' ({param.type}) in args"
                )
            else:
                values[key] = param.check(param.default)
        line = self.document.locate(at)[0]
        substitution = Substitution(
            self.document,
            values,
            {key: param.type for key, param in spec.params.items()},
            f"subtree '{name}'",
            note=f", from subtree '{name}' used at line {line}",
        )
        body_path: KeyPath = ("subtrees", name, "tree")
        body = substitution.apply(spec.tree, body_path)
        self.origins.update(substitution.origins)
        return self.parse(body, body_path, (*stack, name))

    def check_template(self, name: str, spec: SubtreeSpec) -> NodeShape:
        """Check an (un-substituted) subtree body: node types and parameter names."""
        path: KeyPath = ("subtrees", name, "tree")
        dry_run = Substitution(
            self.document,
            dict.fromkeys(spec.params, 0),
            {key: param.type for key, param in spec.params.items()},
            f"subtree '{name}'",
        )
        dry_run.apply(spec.tree, path)
        return self.shape(spec.tree, path)
