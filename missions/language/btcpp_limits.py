"""What BehaviorTree.CPP 4 cannot express: located errors before a tree is exported.

``baobab tree --format btcpp`` refuses, at the cause, a tree whose XML BehaviorTree.CPP would
reject when it loads it or would run differently: tree IDs that clash with a node type or with
each other, subtree parameters that cannot be ``<SubTree>`` ports, a node shape chosen by a
parameter (BT.CPP's tag is fixed when the XML is written), a ``parallel`` that re-ticks children
that succeeded, durations outside what ``Sleep``/``Timeout`` take (whole ms in an ``unsigned
int``; a ``Timeout`` of 0 ms never expires), and text that BT.CPP would read as a blackboard
entry. Values that come from parameters are checked in the expanded tree, where every call's
arguments are known, and blamed on the node that uses them.
"""

from __future__ import annotations

from collections.abc import Iterator

from baobab.behaviours.registry import NodeKind, Registry
from baobab.missions.language.btcpp_ports import (
    MAX_MSEC,
    MSEC_PORTS,
    is_blackboard_pointer,
    msec,
    port_text,
    references,
)
from baobab.missions.language.errors import MissionError, located
from baobab.missions.language.loader import Mission
from baobab.missions.language.tree_parser import Node, NodeShape
from baobab.sim.yaml_source import KeyPath

BTCPP_NODE_IDS = frozenset(
    {
        "AlwaysFailure", "AlwaysSuccess", "AsyncFallback", "AsyncSequence", "Delay", "Fallback",
        "ForceFailure", "ForceSuccess", "IfThenElse", "Inverter", "KeepRunningUntilFailure",
        "LoopBool", "LoopDouble", "LoopInt", "LoopString", "Parallel", "ParallelAll",
        "Precondition", "ReactiveFallback", "ReactiveSequence", "Repeat", "RetryUntilSuccessful",
        "RunOnce", "Script", "ScriptCondition", "Sequence", "SequenceStar", "SequenceWithMemory",
        "SetBlackboard", "SkipUnlessUpdated", "Sleep", "SubTree", "Switch2", "Switch3",
        "Switch4", "Switch5", "Switch6", "Timeout", "TryCatch", "UnsetBlackboard",
        "WaitValueUpdate", "WasEntryUpdated", "WhileDoElse",
    }
)  # fmt: skip
"""The node types BehaviorTree.CPP 4 registers itself (4.8 and 4.10)."""
SHAPE_PARAMS = {
    "sequence": ("memory",),
    "selector": ("memory",),
    "parallel": ("policy", "synchronise"),
    "subtree": ("name", "args"),
}
"""Parameters that choose the element BT.CPP gets rather than a port value (a subtree's
``args`` must be a mapping; the values in it may use parameters)."""


def check_expressible(mission: Mission, registry: Registry) -> None:
    """Raise a located :class:`MissionError` for the first thing BT.CPP cannot express."""
    _check_tree_ids(mission, registry)
    for name, spec in mission.subtrees.items():
        for key in spec.params:
            problem = _port_name_problem(key)
            if problem is not None:
                raise _error(
                    mission,
                    ("subtrees", name, "params", key),
                    f"subtree parameter '{key}' cannot be a BehaviorTree.CPP port: {problem}; "
                    "expected a name that starts with a letter",
                )
    for body in mission.subtree_shapes.values():
        for shape in _shapes(body):
            for key in SHAPE_PARAMS.get(shape.type, ()):
                value = shape.raw.get(key)
                chosen = not isinstance(value, dict) if key == "args" else bool(references(value))
                if value is not None and chosen:
                    raise _error(
                        mission,
                        (*shape.path, shape.type, key),
                        f"{shape.type} '{key}' from a parameter cannot be exported: "
                        "BehaviorTree.CPP fixes it when the XML is written; "
                        "expected a value written in the subtree",
                    )
    for node, call_line in _instances(mission, mission.tree, None):
        problem = _value_problem(node)
        if problem is not None:
            where = f" (in the subtree called at line {call_line})" if call_line else ""
            raise _error(mission, (*node.path, node.type), problem + where)


def _check_tree_ids(mission: Mission, registry: Registry) -> None:
    used = {node.type for node in mission.tree.walk()}
    used |= {node.type for shape in mission.subtree_shapes.values() for node in _shapes(shape)}
    taken = BTCPP_NODE_IDS | {
        behaviour.xml_id
        for behaviour in registry
        if behaviour.name in used and behaviour.kind is not NodeKind.SUBTREE
    }
    if mission.name in taken:
        raise _error(
            mission,
            ("mission",),
            f"mission name '{mission.name}' is a BehaviorTree.CPP node type, which a "
            "<BehaviorTree> ID must not be; expected another name",
        )
    for name in mission.subtrees:
        if name in taken or name == mission.name:
            what = "the mission's name" if name == mission.name else "a BehaviorTree.CPP node type"
            raise _error(
                mission,
                ("subtrees", name),
                f"subtree name '{name}' is {what}, which its <BehaviorTree> ID must not be; "
                "expected another name",
            )


def _port_name_problem(key: str) -> str | None:
    if key in ("name", "ID"):
        return f"'{key}' is an attribute of <SubTree>"
    if not key[:1].isalpha():
        return "BehaviorTree.CPP reserves names that start with '_'"
    return None


def _value_problem(node: Node) -> str | None:
    """What BT.CPP cannot take among the (final) values of one node of the expanded tree."""
    raw = node.raw
    if node.type == "parallel" and raw.get("synchronise") is False:
        return (
            "parallel with synchronise: false cannot be exported: BehaviorTree.CPP's Parallel "
            "never ticks a child again once it succeeded; expected synchronise: true"
        )
    duration_key = MSEC_PORTS.get(node.type)
    if duration_key is not None:
        seconds = raw.get(duration_key)
        if not isinstance(seconds, int | float):
            return None
        millis = msec(seconds)
        if millis > MAX_MSEC:
            return (
                f"{node.type} {seconds:g} s is {millis} ms, more than BehaviorTree.CPP takes "
                f"(an unsigned int of ms); expected at most {MAX_MSEC / 1000:g} s"
            )
        if node.type == "timeout" and millis == 0:
            return (
                f"timeout {seconds:g} s is 0 ms, which BehaviorTree.CPP's Timeout takes as no "
                "timeout at all; expected at least 0.0005 s"
            )
        return None
    values = raw.get("args", {}) if node.behaviour.kind is NodeKind.SUBTREE else raw
    for key, value in values.items():
        text = port_text(value)
        if key != "name" and is_blackboard_pointer(text):
            return (
                f"'{key}' is '{text}', which BehaviorTree.CPP reads as a blackboard entry; "
                "expected a value that is not in braces"
            )
    return None


def _shapes(shape: NodeShape) -> Iterator[NodeShape]:
    yield shape
    for child in shape.children:
        yield from _shapes(child)


def _instances(
    mission: Mission, node: Node, call_line: int | None
) -> Iterator[tuple[Node, int | None]]:
    """Every node of the expanded tree, with the line of the subtree call it is inside."""
    yield node, call_line
    if node.behaviour.kind is NodeKind.SUBTREE:
        call_line = mission.document.locate(node.type_path)[0]
    for child in node.children:
        yield from _instances(mission, child, call_line)


def _error(mission: Mission, path: KeyPath, message: str) -> MissionError:
    return located(mission.document, path, message)
