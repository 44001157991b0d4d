"""Views of a mission tree: unicode text, Graphviz dot, BehaviorTree.CPP v4 XML for Groot2.

The BehaviorTree.CPP export maps baobab's control nodes onto BT.CPP built-ins
(sequence -> ``Sequence``/``ReactiveSequence``, selector -> ``Fallback``/``ReactiveFallback``,
parallel -> ``Parallel``, retry -> ``RetryUntilSuccessful``, repeat -> ``Repeat``,
timeout -> ``Timeout``, wait -> ``Sleep``, durations in ms), writes every other node in compact
form with its parameters as ports, gives each subtree its own ``<BehaviorTree>`` whose
``${param}`` references become ``{param}`` blackboard ports (or derived ports, see
:mod:`~baobab.missions.language.btcpp_ports`), and lists every non-built-in node and every
subtree with
its ports in a ``<TreeNodesModel>``. A tree BT.CPP cannot express is refused first
(:func:`~baobab.missions.language.btcpp_limits.check_expressible`).

:func:`to_btcpp_log` writes the variant BehaviorTree.CPP's ``FileLogger2`` embeds in a Groot2
``.btlog``: the expanded tree, one ``<BehaviorTree>`` per subtree *instance*, every node with
``_uid`` (depth-first pre-order from 1, continuing through subtrees: the order of
:func:`preorder` on the compiled tree) and ``_fullpath``, and a model that lists the built-ins
too.
"""

from __future__ import annotations

import itertools
import xml.etree.ElementTree as ET
from collections.abc import Callable, Iterator, Sequence
from typing import Any

import py_trees
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined

from baobab.behaviours.builtin import default_registry
from baobab.behaviours.registry import BehaviourType, NodeKind, Registry
from baobab.missions.language.btcpp_limits import check_expressible
from baobab.missions.language.btcpp_ports import (
    MSEC_TYPE,
    SUBTREE_PORT_TYPES,
    SubtreePorts,
    call_ports,
    escape,
    final_text,
    port_text,
    port_type,
    references,
    substitute,
    subtree_ports,
)
from baobab.missions.language.compiler import CompiledMission
from baobab.missions.language.loader import Mission
from baobab.missions.language.tree_parser import Node, NodeShape

Render = Callable[[Any, bool], str]
"""A port's text from its value (in the template space of where the node is) and whether it
is a duration BT.CPP takes in ms."""
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


def _literal(value: Any, in_msec: bool) -> str:
    """The port text of a value of the main tree or of a subtree instance (no references)."""
    return final_text(escape(value), in_msec)


Builtin = Callable[[dict[str, Any], Render], tuple[str, dict[str, str]]]


def _memory_tag(memory_tag: str, reactive_tag: str) -> Builtin:
    def build(raw: dict[str, Any], render: Render) -> tuple[str, dict[str, str]]:
        return (reactive_tag if raw.get("memory", True) is False else memory_tag), {}

    return build


def _parallel(raw: dict[str, Any], render: Render) -> tuple[str, dict[str, str]]:
    count = "1" if raw.get("policy") == "success_on_one" else "-1"
    return "Parallel", {"success_count": count, "failure_count": "1"}


def _fixed(tag: str, **ports: str) -> Builtin:
    def build(raw: dict[str, Any], render: Render) -> tuple[str, dict[str, str]]:
        return tag, {name: render(raw.get(key, ""), False) for name, key in ports.items()}

    return build


def _in_msec(tag: str) -> Builtin:
    def build(raw: dict[str, Any], render: Render) -> tuple[str, dict[str, str]]:
        return tag, {"msec": render(raw.get("duration"), True)}

    return build


BUILTINS: dict[str, Builtin] = {
    "sequence": _memory_tag("Sequence", "ReactiveSequence"),
    "selector": _memory_tag("Fallback", "ReactiveFallback"),
    "parallel": _parallel,
    "retry": _fixed("RetryUntilSuccessful", num_attempts="num_failures"),
    "repeat": _fixed("Repeat", num_cycles="num_success"),
    "timeout": _in_msec("Timeout"),
    "invert": _fixed("Inverter"),
    "force_success": _fixed("ForceSuccess"),
    "force_failure": _fixed("ForceFailure"),
    "wait": _in_msec("Sleep"),
    "always_success": _fixed("AlwaysSuccess"),
    "always_failure": _fixed("AlwaysFailure"),
}
"""baobab node types that BehaviorTree.CPP has built in: type -> builder of (tag, port
attributes) from the node's parameters and how its values are rendered."""

BUILTIN_MODELS: dict[str, tuple[str, tuple[tuple[str, str, str | None], ...]]] = {
    "Sequence": ("Control", ()),
    "ReactiveSequence": ("Control", ()),
    "Fallback": ("Control", ()),
    "ReactiveFallback": ("Control", ()),
    "Parallel": ("Control", (("success_count", "int", "-1"), ("failure_count", "int", "1"))),
    "RetryUntilSuccessful": ("Decorator", (("num_attempts", "int", None),)),
    "Repeat": ("Decorator", (("num_cycles", "int", None),)),
    "Timeout": ("Decorator", (("msec", MSEC_TYPE, None),)),
    "Inverter": ("Decorator", ()),
    "ForceSuccess": ("Decorator", ()),
    "ForceFailure": ("Decorator", ()),
    "Sleep": ("Action", (("msec", MSEC_TYPE, None),)),
    "AlwaysSuccess": ("Action", ()),
    "AlwaysFailure": ("Action", ()),
}
"""The BehaviorTree.CPP 4 built-ins :data:`BUILTINS` maps to: tag -> (category, ports as
(name, type, default)), as ``WriteTreeToXML(..., add_builtin_models=true)`` lists them."""


def to_btcpp(mission: Mission, registry: Registry | None = None) -> str:
    """The mission as BehaviorTree.CPP v4 XML with a ``TreeNodesModel`` (opens in Groot2).

    Raises:
        MissionError: the tree cannot be expressed in BT.CPP (located at the cause).
    """
    registry = registry or default_registry()
    check_expressible(mission, registry)
    ports = subtree_ports(mission, registry)
    root = ET.Element("root", {"BTCPP_format": "4", "main_tree_to_execute": mission.name})
    emitter = _Emitter(registry, ports)
    main = ET.SubElement(root, "BehaviorTree", {"ID": mission.name})
    emitter.emit(main, mission.tree, _literal, label=lambda node: node.label)
    for name, shape in mission.subtree_shapes.items():
        tree = ET.SubElement(root, "BehaviorTree", {"ID": name})
        emitter.emit(tree, shape, ports[name].value, label=lambda node: node.raw.get("name"))
    _tree_nodes_model(root, ports, registry, emitter.used, builtin_tags=())
    ET.indent(root)
    return ET.tostring(root, encoding="unicode") + "\n"


def to_btcpp_log(mission: Mission, registry: Registry | None = None) -> str:
    """The expanded tree as ``FileLogger2`` writes it into a ``.btlog`` (see the module doc).

    Node ``k`` in :func:`preorder` of the compiled mission carries ``_uid="k + 1"``. The log is
    for viewing, so the checks of :func:`to_btcpp` are not made.
    """
    registry = registry or default_registry()
    ports = subtree_ports(mission, registry)
    root = ET.Element("root", {"BTCPP_format": "4", "main_tree_to_execute": mission.name})
    main = ET.SubElement(root, "BehaviorTree", {"ID": mission.name, "_fullpath": ""})
    emitter = _Emitter(registry, ports)
    emitter.emit_instance(root, main, mission.tree, itertools.count(1), prefix="")
    _tree_nodes_model(root, ports, registry, emitter.used, sorted(emitter.builtin_tags))
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


class _Emitter:
    """Writes tree elements, noting the node types and built-in tags it used."""

    def __init__(self, registry: Registry, ports: dict[str, SubtreePorts]) -> None:
        self.registry = registry
        self.ports = ports
        self.used: dict[str, BehaviourType] = {}
        self.builtin_tags: set[str] = set()

    def emit(
        self,
        parent: ET.Element,
        node: Node | NodeShape,
        render: Render,
        label: Callable[[Any], str | None],
    ) -> None:
        """Emit ``node`` (of the main tree or a subtree body) and everything below it."""
        behaviour = self._behaviour(node.type)
        if behaviour.kind is NodeKind.SUBTREE:
            args = node.raw.get("args", {})
            in_scope = escape(args) if isinstance(node, Node) else args
            ET.SubElement(parent, "SubTree", self._call(node.raw["name"], in_scope, render))
            return
        tag, attributes = self._tag_and_ports(behaviour, node.raw, render)
        name = label(node)
        element = ET.SubElement(parent, tag, {**({"name": name} if name else {}), **attributes})
        children: Sequence[Node | NodeShape] = node.children
        for child in children:
            self.emit(element, child, render, label)

    def emit_instance(
        self, root: ET.Element, parent: ET.Element, node: Node, uids: Iterator[int], prefix: str
    ) -> None:
        """Emit ``node`` of the expanded tree with ``_uid``/``_fullpath``, subtrees as instances."""
        behaviour = self._behaviour(node.type)
        uid = str(next(uids))
        if behaviour.kind is NodeKind.SUBTREE:
            tree_id = str(node.raw["name"])
            path = f"{prefix}{tree_id}::{uid}"
            attributes = self._call(tree_id, escape(node.raw.get("args", {})), _literal)
            ET.SubElement(parent, "SubTree", {**attributes, "_fullpath": path, "_uid": uid})
            instance = ET.SubElement(root, "BehaviorTree", {"ID": tree_id, "_fullpath": path})
            for child in node.children:
                self.emit_instance(root, instance, child, uids, f"{path}/")
            return
        tag, attributes = self._tag_and_ports(behaviour, node.raw, _literal)
        if behaviour.name in BUILTINS:
            self.builtin_tags.add(tag)
        label = node.label
        element = ET.SubElement(
            parent, tag, {"name": label, **attributes, "_fullpath": prefix + label, "_uid": uid}
        )
        for child in node.children:
            self.emit_instance(root, element, child, uids, prefix)

    def _behaviour(self, type_name: str) -> BehaviourType:
        behaviour = self.registry.get(type_name)
        if behaviour is None:  # cannot happen for a loaded mission
            raise KeyError(type_name)
        self.used[behaviour.name] = behaviour
        return behaviour

    def _call(self, name: Any, args: dict[str, Any], render: Render) -> dict[str, str]:
        """The attributes of a ``<SubTree>`` element: its ID and the ports the call sets."""
        attributes = {"ID": str(name)}
        for key, value, in_msec in call_ports(self.ports[str(name)], args):
            attributes[key] = render(value, in_msec)
        return attributes

    @staticmethod
    def _tag_and_ports(
        behaviour: BehaviourType, raw: dict[str, Any], render: Render
    ) -> tuple[str, dict[str, str]]:
        """The XML tag of a (non-subtree) node and its port attributes."""
        builtin = BUILTINS.get(behaviour.name)
        if builtin is not None:
            return builtin(raw, render)
        ports = {key: render(value, False) for key, value in raw.items() if key != "name"}
        return behaviour.xml_id, ports


def _tree_nodes_model(
    root: ET.Element,
    ports: dict[str, SubtreePorts],
    registry: Registry,
    used: dict[str, BehaviourType],
    builtin_tags: Sequence[str],
) -> None:
    model = ET.SubElement(root, "TreeNodesModel")
    for tag in builtin_tags:
        category, builtin_ports = BUILTIN_MODELS[tag]
        entry = ET.SubElement(model, category, {"ID": tag})
        for name, type_name, default in builtin_ports:
            attributes = {"name": name, "type": type_name}
            if default is not None:
                attributes["default"] = default
            ET.SubElement(entry, "input_port", attributes)
    for behaviour in registry:
        custom = behaviour.name not in BUILTINS and behaviour.kind is not NodeKind.SUBTREE
        if behaviour.name in used and custom:
            _model_entry(model, behaviour)
    for name, subtree in ports.items():
        _subtree_model_entry(ET.SubElement(model, "SubTree", {"ID": name}), subtree)


def _subtree_model_entry(entry: ET.Element, subtree: SubtreePorts) -> None:
    """A subtree's ports: its parameters, then its derived ports (with their defaults)."""
    for key, param in subtree.params.items():
        attributes = {"name": key, "type": SUBTREE_PORT_TYPES.get(param.type, "any")}
        if param.default is not None:
            attributes["default"] = port_text(param.default)
        ET.SubElement(entry, "input_port", attributes).text = param.description or None
    defaults = subtree.defaults()
    for port in subtree.derived.values():
        attributes = {"name": port.key, "type": port.port_type}
        if set(references(port.template)) <= set(defaults):
            attributes["default"] = final_text(substitute(port.template, defaults), port.in_msec)
        ET.SubElement(entry, "input_port", attributes).text = port.describe()


def _model_entry(model: ET.Element, behaviour: BehaviourType) -> None:
    entry = ET.SubElement(model, _CATEGORY[behaviour.kind], {"ID": behaviour.xml_id})
    for key, info in behaviour.ports().items():
        attributes = {"name": key, "type": port_type(info.annotation)}
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
    return port_text(info.default)
