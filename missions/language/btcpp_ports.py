"""How mission values become BehaviorTree.CPP port values, and the ports each subtree needs.

BehaviorTree.CPP reads a blackboard entry only as a *whole* port value (``{key}``), has no
string templates and no unit conversion, and its ``Sleep``/``Timeout`` take milliseconds in an
``unsigned int`` port, where baobab writes seconds. A subtree body's value is exported as is
when it is a literal, and as ``{param}`` when it is exactly ``${param}``. Anything else that
uses a parameter -- ``wait: ${pause}`` (seconds -> ms), ``navigate_to_pose: table_${table}``
(a template), ``follow_waypoints: [${a}, dock]`` (a structure) -- becomes a *derived port* of
the subtree: the body reads ``{pause_msec}``, ``{goal}``, ``{waypoints}``, and every call site
computes that port's value from its own arguments. A call inside another subtree passes its
derived values on, deriving ports of the caller in turn where they depend on the caller's
parameters; the main tree's calls have only literal arguments, so every value BT.CPP reads is
computed here, once per call site.

Values are handled in *template space*: raw mission data whose strings may hold ``${name}``
references and ``$${`` escapes (a literal ``${``), as a subtree body is written.
"""

from __future__ import annotations

import json
import re
import types
import typing
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

from baobab.behaviours.poses import Pose
from baobab.behaviours.registry import BehaviourType, NodeKind, Registry
from baobab.missions.language.loader import Mission
from baobab.missions.language.params import ParamSpec
from baobab.missions.language.tree_parser import NodeShape

_REFERENCE = re.compile(r"\$(\$?)\{([A-Za-z_][A-Za-z0-9_]*)\}")
MSEC_PORTS = {"wait": "duration", "timeout": "duration"}
"""baobab node types whose parameter (s) BehaviorTree.CPP takes in ms: type -> parameter."""
MSEC_SUFFIX = "_msec"
MSEC_TYPE = "unsigned int"
"""The port type of BehaviorTree.CPP's ``Sleep.msec`` and ``Timeout.msec``."""
MAX_MSEC = 2**32 - 1
SUBTREE_PORT_TYPES = {
    "int": "int",
    "float": "double",
    "str": "std::string",
    "bool": "bool",
    "pose": "Pose",
}
"""Mission parameter types -> the port types BehaviorTree.CPP writes."""


# --- literal values -------------------------------------------------------------------------


def port_text(value: Any) -> str:
    """A literal value as BehaviorTree.CPP reads it from a port.

    A list of plain values is BT.CPP's ``a;b;c``; anything holding a mapping (a pose written as
    ``{x: 1, y: 2}``) is ``json:...``, BT.CPP 4's prefix for structured values, so that it is
    never mistaken for a blackboard reference (a value in braces). Numbers keep every digit.
    """
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return value
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return str(int(value)) if value.is_integer() and abs(value) < 1e15 else repr(value)
    if isinstance(value, Pose):
        return port_text(value.location or {"position": list(value.position)})
    if isinstance(value, list | tuple) and all(
        isinstance(item, str | int | float) for item in value
    ):
        return ";".join(port_text(item) for item in value)
    return "json:" + json.dumps(value, separators=(", ", ": "), default=str)


def msec(seconds: Any) -> int:
    """``seconds`` (a number, or its text) in whole milliseconds, rounded to the nearest."""
    return round(float(seconds) * 1000)


def is_blackboard_pointer(text: str) -> bool:
    """True when BehaviorTree.CPP reads ``text`` as a blackboard entry (``{key}``)."""
    stripped = text.strip(" ")
    return len(stripped) >= 3 and stripped[0] == "{" and stripped[-1] == "}"


# --- template space ---------------------------------------------------------------------------


def escape(value: Any) -> Any:
    """A substituted (final) value in template space: every literal ``${`` escaped."""
    if isinstance(value, dict):
        return {key: escape(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [escape(item) for item in value]
    return value.replace("${", "$${") if isinstance(value, str) else value


def unescape(value: Any) -> Any:
    """A template without references as the final value (``$${`` -> ``${``)."""
    if isinstance(value, dict):
        return {key: unescape(item) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [unescape(item) for item in value]
    return value.replace("$${", "${") if isinstance(value, str) else value


def references(value: Any) -> list[str]:
    """The parameters ``value`` refers to, in order of appearance (escapes excluded)."""
    if isinstance(value, dict):
        return [name for item in value.values() for name in references(item)]
    if isinstance(value, list | tuple):
        return [name for item in value for name in references(item)]
    if not isinstance(value, str):
        return []
    return [match.group(2) for match in _REFERENCE.finditer(value) if not match.group(1)]


def whole_reference(value: Any) -> str | None:
    """``name`` when ``value`` is exactly ``${name}``, else None."""
    if not isinstance(value, str):
        return None
    match = _REFERENCE.fullmatch(value)
    return match.group(2) if match is not None and not match.group(1) else None


def substitute(value: Any, args: Mapping[str, Any]) -> Any:
    """``value`` with each ``${name}`` replaced by ``args[name]`` (both in template space)."""
    if isinstance(value, dict):
        return {key: substitute(item, args) for key, item in value.items()}
    if isinstance(value, list | tuple):
        return [substitute(item, args) for item in value]
    if not isinstance(value, str):
        return value
    name = whole_reference(value)
    if name is not None:
        return args[name]

    def replace(match: re.Match[str]) -> str:
        if match.group(1):
            return match.group(0)
        return _inline(args[match.group(2)])

    return _REFERENCE.sub(replace, value)


def _inline(value: Any) -> str:
    """A value as baobab interpolates it into text (see ``params._format``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def _canonical(value: Any) -> str:
    return json.dumps(value, sort_keys=True, default=str)


# --- subtree ports ----------------------------------------------------------------------------


@dataclass(frozen=True)
class DerivedPort:
    """A subtree port whose value every call site computes from its arguments.

    Attributes:
        key: the port (and blackboard entry) name.
        template: the value in the subtree's template space.
        in_msec: the value is a duration in s, passed in ms.
        port_type: the BT.CPP type of the port it feeds.
    """

    key: str
    template: Any
    in_msec: bool
    port_type: str

    def describe(self) -> str:
        """How the value is computed, for the ``TreeNodesModel``."""
        text = self.template if isinstance(self.template, str) else _canonical(self.template)
        return f"= {text} in ms" if self.in_msec else f"= {text}"


@dataclass
class SubtreePorts:
    """The ports of one subtree: its parameters, then the derived ports its body reads.

    Attributes:
        params: the declared parameters (each is a port too).
        derived: derived ports by (canonical template, in ms).
    """

    params: dict[str, ParamSpec]
    derived: dict[tuple[str, bool], DerivedPort] = field(default_factory=dict)

    def derive(self, template: Any, in_msec: bool, base: str, port_type: str) -> DerivedPort:
        """The derived port for ``template`` (added, under a fresh name, if new)."""
        key = (_canonical(template), in_msec)
        port = self.derived.get(key)
        if port is None:
            taken = set(self.params) | {port.key for port in self.derived.values()}
            name, number = base, 2
            while name in taken:
                name, number = f"{base}_{number}", number + 1
            port = self.derived[key] = DerivedPort(name, template, in_msec, port_type)
        return port

    def defaults(self) -> dict[str, Any]:
        """Each parameter's default, typed, in template space."""
        return {
            key: escape(spec.check(spec.default))
            for key, spec in self.params.items()
            if not spec.required
        }

    def typed(self, key: str, value: Any) -> Any:
        """An argument for parameter ``key`` with the parameter's type, if it is a literal."""
        spec = self.params.get(key)
        if spec is None or references(value):
            return value
        try:
            return escape(spec.check(unescape(value)))
        except ValueError:  # the loader has refused such an argument already
            return value

    def value(self, template: Any, in_msec: bool) -> str:
        """The text of a port whose value is ``template`` in this subtree's template space."""
        if not references(template):
            return final_text(template, in_msec)
        name = whole_reference(template)
        if name is not None and not in_msec:
            return "{" + name + "}"
        return "{" + self.derived[(_canonical(template), in_msec)].key + "}"


def final_text(template: Any, in_msec: bool) -> str:
    """The port text of a template without references (ms for a duration)."""
    value = unescape(template)
    return str(msec(value)) if in_msec else port_text(value)


def call_ports(callee: SubtreePorts, args: Mapping[str, Any]) -> list[tuple[str, Any, bool]]:
    """The callee's ports a call sets: (port, value in the caller's template space, in ms).

    The parameters given in ``args`` come first; then every derived port, computed from
    ``args`` and the callee's defaults. A literal argument takes its parameter's type first
    (``1`` for a float parameter is ``1.0``), as the subtree's expansion does.
    """
    typed = {key: callee.typed(key, value) for key, value in args.items()}
    given = [(key, value, False) for key, value in typed.items()]
    scope = {**callee.defaults(), **typed}
    derived = [
        (port.key, substitute(port.template, scope), port.in_msec)
        for port in callee.derived.values()
    ]
    return given + derived


def subtree_ports(mission: Mission, registry: Registry) -> dict[str, SubtreePorts]:
    """The ports of every subtree of ``mission``, in the order the mission declares them."""
    analysis = _Analysis(mission, registry)
    return {name: analysis.ports_of(name) for name in mission.subtrees}


class _Analysis:
    """Finds each subtree's derived ports, analysing callees before their callers."""

    def __init__(self, mission: Mission, registry: Registry) -> None:
        self.mission = mission
        self.registry = registry
        self.result: dict[str, SubtreePorts] = {}

    def ports_of(self, name: str) -> SubtreePorts:
        """The ports of subtree ``name`` (subtrees do not call themselves: the loader checks)."""
        if name not in self.result:
            ports = SubtreePorts(dict(self.mission.subtrees[name].params))
            self._collect(self.mission.subtree_shapes[name], ports)
            self.result[name] = ports
        return self.result[name]

    def _collect(self, shape: NodeShape, ports: SubtreePorts) -> None:
        behaviour = self.registry.get(shape.type)
        if behaviour is not None and behaviour.kind is NodeKind.SUBTREE:
            callee_name = shape.raw.get("name")
            if isinstance(callee_name, str) and callee_name in self.mission.subtrees:
                callee = self.ports_of(callee_name)
                for key, value, in_msec in call_ports(callee, shape.raw.get("args", {})):
                    _need(ports, value, in_msec, key, _callee_type(callee, key))
            return
        msec_port = MSEC_PORTS.get(shape.type)
        for key, value in shape.raw.items():
            if key != "name":
                port_type = MSEC_TYPE if key == msec_port else _field_type(behaviour, key)
                _need(ports, value, key == msec_port, key, port_type)
        for child in shape.children:
            self._collect(child, ports)


def _need(ports: SubtreePorts, value: Any, in_msec: bool, base: str, port_type: str) -> None:
    """Derive a port of ``ports`` for ``value`` unless it is a literal or a plain reference."""
    if not references(value) or (whole_reference(value) is not None and not in_msec):
        return
    name = whole_reference(value)
    if in_msec and name is not None:
        base = name + MSEC_SUFFIX
    ports.derive(value, in_msec, base, MSEC_TYPE if in_msec else port_type)


def _callee_type(callee: SubtreePorts, key: str) -> str:
    if key in callee.params:
        return SUBTREE_PORT_TYPES.get(callee.params[key].type, "any")
    port = next((p for p in callee.derived.values() if p.key == key), None)
    return port.port_type if port is not None else "any"


def _field_type(behaviour: BehaviourType | None, key: str) -> str:
    if behaviour is None:
        return "any"
    info = behaviour.params.model_fields.get(key)
    return port_type(info.annotation) if info is not None else "any"


def port_type(annotation: Any) -> str:
    """The BT.CPP type name of a parameter annotation, as the ``TreeNodesModel`` writes it."""
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        return port_type(typing.get_args(annotation)[0])
    if origin in (typing.Union, types.UnionType):
        options = [arg for arg in typing.get_args(annotation) if arg is not type(None)]
        return port_type(options[0]) if len(options) == 1 else "any"
    if origin is Literal:
        return "std::string"
    if origin in (list, tuple):
        return "vector"
    names = {bool: "bool", int: "int", float: "double", str: "std::string", Pose: "Pose"}
    return names.get(annotation, "any")
