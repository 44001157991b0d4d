"""What a run's video says under the sim time: the tasks running now and where they go.

Each running leaf of the tree gets a line with its task, and one with its goal: the pose it
drives or moves to (the one it is on, for a list of poses, from the task's feedback), or else
its parameters as written (a move relative to the cube, a gripper command). Before the first
tick and after the last, the tree's status stands in for the tasks.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import py_trees

from baobab.behaviours.actions import GoalTaskLeaf
from baobab.behaviours.poses import Pose
from baobab.missions.language.compiler import CompiledMission
from baobab.missions.language.tree_parser import Node

Status = py_trees.common.Status


class VideoCaption:
    """Call it for the caption lines of the frame being filmed.

    Args:
        compiled: the run's compiled tree.
    """

    def __init__(self, compiled: CompiledMission) -> None:
        self._root = compiled.root
        self._nodes = compiled.nodes
        self._leaves = [b for b in compiled.root.iterate() if not b.children]

    def __call__(self) -> list[str]:
        """Two lines for each running leaf (task, goal), or the tree's status."""
        lines: list[str] = []
        for leaf in self._leaves:
            node = self._nodes.get(leaf.id)
            if leaf.status is not Status.RUNNING or node is None:
                continue
            task = leaf.name if leaf.name.startswith(node.type) else f"{node.type} {leaf.name}"
            handle = leaf.handle if isinstance(leaf, GoalTaskLeaf) else None
            lines.append(f"task: {task}")
            lines.append(goal_text(node, {} if handle is None else handle.feedback))
        if lines:
            return lines
        status = self._root.status
        return ["tree: not started" if status is Status.INVALID else f"tree: {status.name}"]


def goal_text(node: Node, feedback: Mapping[str, Any]) -> str:
    """``goal: ...`` for ``node``: its pose (the current one of a list), else its parameters."""
    for key in type(node.params).model_fields:
        value = getattr(node.params, key)
        if isinstance(value, Pose):
            return f"goal: {_pose_text(value)}"
        if isinstance(value, list) and value and all(isinstance(p, Pose) for p in value):
            index = _current_index(feedback, len(value))
            return f"goal {index + 1} of {len(value)}: {_pose_text(value[index])}"
    written = ", ".join(f"{key} {value}" for key, value in node.raw.items() if key != "name")
    return f"goal: {written}" if written else "goal: -"


def _current_index(feedback: Mapping[str, Any], count: int) -> int:
    """Which of ``count`` poses a task is on, from Nav2's feedback fields (0 if it says not)."""
    if isinstance(feedback.get("current_waypoint"), int):
        index = feedback["current_waypoint"]
    elif isinstance(feedback.get("number_of_poses_remaining"), int):
        index = count - feedback["number_of_poses_remaining"]
    else:
        index = 0
    return min(max(index, 0), count - 1)


def _pose_text(pose: Pose) -> str:
    """``name (x, y)`` for a planar pose, ``name (x, y, z)`` for a spatial one (m)."""
    numbers = pose.position[:2] if pose.planar else pose.position
    where = "(" + ", ".join(f"{v:.2f}" for v in numbers) + ")"
    return f"{pose.location} {where}" if pose.location else where
