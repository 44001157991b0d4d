"""Views of a mission tree: unicode text, Graphviz dot, BehaviorTree.CPP v4 XML for Groot2.

The BehaviorTree.CPP export maps baobab's control nodes onto BT.CPP built-ins
(sequence -> ``Sequence``/``ReactiveSequence``, selector -> ``Fallback``/``ReactiveFallback``,
parallel -> ``Parallel``, retry -> ``RetryUntilSuccessful``, repeat -> ``Repeat``,
timeout -> ``Timeout``, wait -> ``Sleep``, ...), writes every other node in compact form with
its parameters as ports, gives each subtree its own ``<BehaviorTree>`` whose ``${param}``
references become ``{param}`` blackboard ports, and lists every non-built-in node with its
ports in a ``<TreeNodesModel>``.

:func:`to_btcpp_log` writes the variant BehaviorTree.CPP's ``FileLogger2`` embeds in a Groot2
``.btlog``: the expanded tree, one ``<BehaviorTree>`` per subtree *instance*, every node with
``_uid`` (depth-first pre-order from 1, continuing through subtrees: the order of
:func:`preorder` on the compiled tree) and ``_fullpath``, and a model that lists the built-ins
too.
"""

from __future__ import annotations

import itertools
import json
import re
import types
import typing
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterator, Sequence
from typing import Any, Literal

import py_trees
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined

from baobab.missions.compiler import CompiledMission
from baobab.missions.loader import Mission
from baobab.missions.poses import Pose
from baobab.missions.registry import BehaviourType, NodeKind, Registry, default_registry
from baobab.missions.tree_parser import Node

_PLACEHOLDER = re.compile(r"\$\{([A-Za-z_][A-Za-z0-9_]*)\}")
_CATEGORY = {
    NodeKind.ACTION: "Action",
    NodeKind.CONDITION: "Condition",
    NodeKind.DECORATOR: "Decorator",
    NodeKind.COMPOSITE: "Control",
}


def to_unicode(compiled: CompiledMission) -> str:
    """The compiled tree as py_trees draws it in a terminal."""
    return str(py_trees.display.unicode_tree(compiled.root))


def to_dot(compiled: CompiledMission) -> str:
    """The compiled tree as a Graphviz dot graph."""
    return str(py_trees.display.dot_tree(compiled.root).to_string())


def _text(value: Any) -> str:
    """A port value as BehaviorTree.CPP reads it.

    ``${param}`` becomes the blackboard reference ``{param}``; a list of plain values is
    BT.CPP's ``a;b;c``; anything holding a mapping (a pose written as ``{x: 1, y: 2}``) is
    ``json:...``, BT.CPP 4's prefix for structured values, so that it is never mistaken for
    a blackboard reference (a value in braces).
    """
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return _PLACEHOLDER.sub(r"{\1}", value)
    if isinstance(value, int | float):
        return f"{value:g}" if isinstance(value, float) else str(value)
    if isinstance(value, Pose):
        return _text(value.location or {"position": list(value.position)})
    if isinstance(value, list | tuple) and all(
        isinstance(item, str | int | float) for item in value
    ):
        return ";".join(_text(item) for item in value)
    text = json.dumps(value, separators=(", ", ": "), default=str)
    return "json:" + _PLACEHOLDER.sub(r"{\1}", text)


def _msec(seconds: Any) -> str:
    if isinstance(seconds, int | float) and not isinstance(seconds, bool):
        return str(round(seconds * 1000))
    return _text(seconds)


def _memory_tag(
    memory_tag: str, reactive_tag: str
) -> Callable[[dict[str, Any]], tuple[str, dict[str, str]]]:
    def build(raw: dict[str, Any]) -> tuple[str, dict[str, str]]:
        return (reactive_tag if raw.get("memory", True) is False else memory_tag), {}

    return build


def _parallel(raw: dict[str, Any]) -> tuple[str, dict[str, str]]:
    count = "1" if raw.get("policy") == "success_on_one" else "-1"
    return "Parallel", {"success_count": count, "failure_count": "1"}


def _fixed(tag: str, **ports: str) -> Callable[[dict[str, Any]], tuple[str, dict[str, str]]]:
    def build(raw: dict[str, Any]) -> tuple[str, dict[str, str]]:
        return tag, {name: _text(raw.get(key, "")) for name, key in ports.items()}

    return build


BUILTINS: dict[str, Callable[[dict[str, Any]], tuple[str, dict[str, str]]]] = {
    "sequence": _memory_tag("Sequence", "ReactiveSequence"),
    "selector": _memory_tag("Fallback", "ReactiveFallback"),
    "parallel": _parallel,
    "retry": _fixed("RetryUntilSuccessful", num_attempts="num_failures"),
    "repeat": _fixed("Repeat", num_cycles="num_success"),
    "timeout": lambda raw: ("Timeout", {"msec": _msec(raw.get("duration"))}),
    "invert": _fixed("Inverter"),
    "force_success": _fixed("ForceSuccess"),
    "force_failure": _fixed("ForceFailure"),
    "wait": lambda raw: ("Sleep", {"msec": _msec(raw.get("duration"))}),
    "always_success": _fixed("AlwaysSuccess"),
    "always_failure": _fixed("AlwaysFailure"),
}
"""baobab node types that BehaviorTree.CPP has built in: type -> (tag, attributes)."""

BUILTIN_MODELS: dict[str, tuple[str, tuple[tuple[str, str, str | None], ...]]] = {
    "Sequence": ("Control", ()),
    "ReactiveSequence": ("Control", ()),
    "Fallback": ("Control", ()),
    "ReactiveFallback": ("Control", ()),
    "Parallel": ("Control", (("success_count", "int", "-1"), ("failure_count", "int", "1"))),
    "RetryUntilSuccessful": ("Decorator", (("num_attempts", "int", None),)),
    "Repeat": ("Decorator", (("num_cycles", "int", None),)),
    "Timeout": ("Decorator", (("msec", "unsigned int", None),)),
    "Inverter": ("Decorator", ()),
    "ForceSuccess": ("Decorator", ()),
    "ForceFailure": ("Decorator", ()),
    "Sleep": ("Action", (("msec", "unsigned int", None),)),
    "AlwaysSuccess": ("Action", ()),
    "AlwaysFailure": ("Action", ()),
}
"""The BehaviorTree.CPP 4 built-ins :data:`BUILTINS` maps to: tag -> (category, ports as
(name, type, default)), as ``WriteTreeToXML(..., add_builtin_models=true)`` lists them."""

SUBTREE_PORT_TYPES = {
    "int": "int",
    "float": "double",
    "str": "std::string",
    "bool": "bool",
    "pose": "Pose",
}
"""Mission parameter types -> the port types BehaviorTree.CPP writes."""


def to_btcpp(mission: Mission, registry: Registry | None = None) -> str:
    """The mission as BehaviorTree.CPP v4 XML with a ``TreeNodesModel`` (opens in Groot2)."""
    registry = registry or default_registry()
    root = ET.Element("root", {"BTCPP_format": "4", "main_tree_to_execute": mission.name})
    used: dict[str, BehaviourType] = {}
    main = ET.SubElement(root, "BehaviorTree", {"ID": mission.name})
    _emit(main, mission.tree, registry, used, label=lambda node: node.label)
    for name, shape in mission.subtree_shapes.items():
        tree = ET.SubElement(root, "BehaviorTree", {"ID": name})
        _emit(tree, shape, registry, used, label=lambda node: node.raw.get("name"))
    _tree_nodes_model(root, mission, registry, used, builtin_tags=())
    ET.indent(root)
    return ET.tostring(root, encoding="unicode") + "\n"


def to_btcpp_log(mission: Mission, registry: Registry | None = None) -> str:
    """The expanded tree as ``FileLogger2`` writes it into a ``.btlog`` (see the module doc).

    Node ``k`` in :func:`preorder` of the compiled mission carries ``_uid="k + 1"``.
    """
    registry = registry or default_registry()
    root = ET.Element("root", {"BTCPP_format": "4", "main_tree_to_execute": mission.name})
    main = ET.SubElement(root, "BehaviorTree", {"ID": mission.name, "_fullpath": ""})
    used: dict[str, BehaviourType] = {}
    tags: set[str] = set()
    _emit_instance(root, main, mission.tree, used, tags, itertools.count(1), prefix="")
    _tree_nodes_model(root, mission, registry, used, builtin_tags=sorted(tags))
    ET.indent(root)
    return ET.tostring(root, encoding="unicode") + "\n"


def preorder(node: py_trees.behaviour.Behaviour) -> Iterator[py_trees.behaviour.Behaviour]:
    """``node`` and every behaviour below it, depth first, parents before children.

    (py_trees' own ``iterate`` yields children first.) The compiler builds one behaviour
    per mission node, so this is also the order of ``_uid`` in :func:`to_btcpp_log`.
    """
    yield node
    for child in node.children:
        yield from preorder(child)


def _tree_nodes_model(
    root: ET.Element,
    mission: Mission,
    registry: Registry,
    used: dict[str, BehaviourType],
    builtin_tags: Sequence[str],
) -> None:
    model = ET.SubElement(root, "TreeNodesModel")
    for tag in builtin_tags:
        category, ports = BUILTIN_MODELS[tag]
        entry = ET.SubElement(model, category, {"ID": tag})
        for name, port_type, default in ports:
            attributes = {"name": name, "type": port_type}
            if default is not None:
                attributes["default"] = default
            ET.SubElement(entry, "input_port", attributes)
    for behaviour in registry:
        custom = behaviour.name not in BUILTINS and behaviour.kind is not NodeKind.SUBTREE
        if behaviour.name in used and custom:
            _model_entry(model, behaviour)
    for name, spec in mission.subtrees.items():
        entry = ET.SubElement(model, "SubTree", {"ID": name})
        for key, param in spec.params.items():
            attributes = {"name": key, "type": SUBTREE_PORT_TYPES.get(param.type, "any")}
            if param.default is not None:
                attributes["default"] = _text(param.default)
            ET.SubElement(entry, "input_port", attributes).text = param.description or None


def _emit(
    parent: ET.Element,
    node: Any,
    registry: Registry,
    used: dict[str, BehaviourType],
    label: Callable[[Any], str | None],
) -> None:
    behaviour = registry.get(node.type)
    if behaviour is None:  # cannot happen for a loaded mission
        raise KeyError(node.type)
    used[behaviour.name] = behaviour
    if behaviour.kind is NodeKind.SUBTREE:
        args = node.raw.get("args", {})
        attributes = {"ID": str(node.raw["name"])}
        attributes.update({key: _text(value) for key, value in args.items()})
        ET.SubElement(parent, "SubTree", attributes)
        return
    tag, attributes = _tag_and_ports(behaviour, node.raw)
    name = label(node)
    element = ET.SubElement(parent, tag, {**({"name": name} if name else {}), **attributes})
    children: Sequence[Any] = node.children
    for child in children:
        _emit(element, child, registry, used, label)


def _tag_and_ports(behaviour: BehaviourType, raw: dict[str, Any]) -> tuple[str, dict[str, str]]:
    """The XML tag of a (non-subtree) node and its port attributes."""
    builtin = BUILTINS.get(behaviour.name)
    if builtin is not None:
        return builtin(raw)
    return behaviour.xml_id, {key: _text(value) for key, value in raw.items() if key != "name"}


def _emit_instance(
    root: ET.Element,
    parent: ET.Element,
    node: Node,
    used: dict[str, BehaviourType],
    builtin_tags: set[str],
    uids: Iterator[int],
    prefix: str,
) -> None:
    """Emit ``node`` of the expanded tree with ``_uid``/``_fullpath``, subtrees as instances."""
    behaviour = node.behaviour
    uid = str(next(uids))
    if behaviour.kind is NodeKind.SUBTREE:
        tree_id = str(node.raw["name"])
        path = f"{prefix}{tree_id}::{uid}"
        args = {key: _text(value) for key, value in node.raw.get("args", {}).items()}
        ET.SubElement(parent, "SubTree", {"ID": tree_id, **args, "_fullpath": path, "_uid": uid})
        instance = ET.SubElement(root, "BehaviorTree", {"ID": tree_id, "_fullpath": path})
        for child in node.children:
            _emit_instance(root, instance, child, used, builtin_tags, uids, f"{path}/")
        return
    used[behaviour.name] = behaviour
    tag, attributes = _tag_and_ports(behaviour, node.raw)
    if behaviour.name in BUILTINS:
        builtin_tags.add(tag)
    label = node.label
    element = ET.SubElement(
        parent, tag, {"name": label, **attributes, "_fullpath": prefix + label, "_uid": uid}
    )
    for child in node.children:
        _emit_instance(root, element, child, used, builtin_tags, uids, prefix)


def _model_entry(model: ET.Element, behaviour: BehaviourType) -> None:
    entry = ET.SubElement(model, _CATEGORY[behaviour.kind], {"ID": behaviour.xml_id})
    for key, info in behaviour.ports().items():
        attributes = {"name": key, "type": _port_type(info.annotation)}
        default = _default(info)
        if default is not None:
            attributes["default"] = default
        ET.SubElement(entry, "input_port", attributes).text = info.description or None
    ET.SubElement(entry, "MetadataFields").append(
        ET.Element("Metadata", {"description": behaviour.description})
    )


def _default(info: FieldInfo) -> str | None:
    if info.default is PydanticUndefined or info.default is None:
        return None
    return _text(info.default)


def _port_type(annotation: Any) -> str:
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        return _port_type(typing.get_args(annotation)[0])
    if origin in (typing.Union, types.UnionType):
        options = [arg for arg in typing.get_args(annotation) if arg is not type(None)]
        return _port_type(options[0]) if len(options) == 1 else "any"
    if origin is Literal:
        return "std::string"
    if origin in (list, tuple):
        return "vector"
    names = {bool: "bool", int: "int", float: "double", str: "std::string", Pose: "Pose"}
    return names.get(annotation, "any")
