"""Views of a mission tree: unicode text, Graphviz dot, BehaviorTree.CPP v4 XML for Groot2.

The BehaviorTree.CPP export maps baobab's control nodes onto BT.CPP built-ins
(sequence -> ``Sequence``/``ReactiveSequence``, selector -> ``Fallback``/``ReactiveFallback``,
parallel -> ``Parallel``, retry -> ``RetryUntilSuccessful``, repeat -> ``Repeat``,
timeout -> ``Timeout``, wait -> ``Sleep``, ...), writes every other node in compact form with
its parameters as ports, gives each subtree its own ``<BehaviorTree>`` whose ``${param}``
references become ``{param}`` blackboard ports, and lists every non-built-in node with its
ports in a ``<TreeNodesModel>``.
"""

from __future__ import annotations

import re
import types
import typing
import xml.etree.ElementTree as ET
from collections.abc import Callable, Sequence
from typing import Any, Literal

import py_trees
import yaml
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined

from baobab.missions.compiler import CompiledMission
from baobab.missions.loader import Mission
from baobab.missions.poses import Pose
from baobab.missions.registry import BehaviourType, NodeKind, Registry, default_registry

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
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return _PLACEHOLDER.sub(r"{\1}", value)
    if isinstance(value, int | float):
        return f"{value:g}" if isinstance(value, float) else str(value)
    if isinstance(value, Pose):
        return _text(value.location or {"position": list(value.position)})
    flow = yaml.safe_dump(value, default_flow_style=True, width=10_000, sort_keys=False)
    return _PLACEHOLDER.sub(r"{\1}", flow.strip())


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
    model = ET.SubElement(root, "TreeNodesModel")
    for behaviour in registry:
        custom = behaviour.name not in BUILTINS and behaviour.kind is not NodeKind.SUBTREE
        if behaviour.name in used and custom:
            _model_entry(model, behaviour)
    for name, spec in mission.subtrees.items():
        entry = ET.SubElement(model, "SubTree", {"ID": name})
        for key, param in spec.params.items():
            attributes = {"name": key, "type": param.type}
            if param.default is not None:
                attributes["default"] = _text(param.default)
            ET.SubElement(entry, "input_port", attributes).text = param.description or None
    ET.indent(root)
    return ET.tostring(root, encoding="unicode") + "\n"


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
    builtin = BUILTINS.get(behaviour.name)
    if builtin is not None:
        tag, attributes = builtin(node.raw)
    else:
        tag = behaviour.xml_id
        attributes = {key: _text(value) for key, value in node.raw.items() if key != "name"}
    name = label(node)
    element = ET.SubElement(parent, tag, {**({"name": name} if name else {}), **attributes})
    children: Sequence[Any] = node.children
    for child in children:
        _emit(element, child, registry, used, label)


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
