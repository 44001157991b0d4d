"""Compile a validated mission tree into a py_trees tree wired to capability ports.

The compiler clears py_trees' process-global blackboard, builds every node with its registry
factory (children first), and returns the tree together with a map from each behaviour back
to the mission node it came from, so runners and traces can name ``file:line:col`` for it.
"""

from __future__ import annotations

import uuid
from dataclasses import dataclass

import py_trees

from baobab.behaviours.actions import GoalTaskLeaf
from baobab.behaviours.ports import Capabilities
from baobab.behaviours.registry import BuildRequest
from baobab.missions.language.errors import located
from baobab.missions.language.loader import Mission
from baobab.missions.language.tree_parser import Node


@dataclass(frozen=True)
class CompiledMission:
    """A mission's py_trees tree and where each behaviour came from.

    Attributes:
        mission: the validated mission.
        tree: the behaviour tree (not yet ticked).
        nodes: the mission node of each behaviour, by behaviour id.
    """

    mission: Mission
    tree: py_trees.trees.BehaviourTree
    nodes: dict[uuid.UUID, Node]

    @property
    def root(self) -> py_trees.behaviour.Behaviour:
        """The root behaviour."""
        return self.tree.root

    def goal_leaves(self) -> list[GoalTaskLeaf]:
        """Every goal-task leaf, depth first (for outcome reports)."""
        return [b for b in self.tree.root.iterate() if isinstance(b, GoalTaskLeaf)]

    def where(self, behaviour: py_trees.behaviour.Behaviour) -> str:
        """``file:line:col`` of the mission node ``behaviour`` was built from."""
        document = self.mission.document
        line, column = document.locate(self.nodes[behaviour.id].type_path)
        return f"{document.path}:{line}:{column}"


def compile_mission(
    mission: Mission, capabilities: Capabilities, *, require_ports: bool = True
) -> CompiledMission:
    """Build the py_trees tree of ``mission`` over ``capabilities``.

    Args:
        mission: a mission from :func:`~baobab.missions.language.loader.load_mission`.
        capabilities: the sim clock and the ports of the robot's servers.
        require_ports: check that every capability the tree uses has a port (off only to
            display a tree without running it; leaves then fail when they first start).

    Raises:
        MissionError: at the first node whose capability has no port.
    """
    py_trees.blackboard.Blackboard.clear()
    if require_ports:
        for node in mission.tree.walk():
            capability = node.behaviour.capability
            if capability is not None and not capabilities.provides(capability):
                raise located(
                    mission.document,
                    node.type_path,
                    f"{node.type} needs capability '{capability}', which this run does not provide",
                )
    nodes: dict[uuid.UUID, Node] = {}
    root = _build(mission.tree, capabilities, nodes)
    return CompiledMission(mission, py_trees.trees.BehaviourTree(root), nodes)


def _build(
    node: Node, capabilities: Capabilities, nodes: dict[uuid.UUID, Node]
) -> py_trees.behaviour.Behaviour:
    children = [_build(child, capabilities, nodes) for child in node.children]
    request = BuildRequest(node.params, node.label, children, capabilities)
    behaviour = node.behaviour.factory(request)
    nodes[behaviour.id] = node
    return behaviour
