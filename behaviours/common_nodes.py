"""Nodes every robot has: sim-time waiting, elapsed-time checks, constant results."""

from __future__ import annotations

from typing import TYPE_CHECKING

from pydantic import Field

from baobab.behaviours.registry import BehaviourType, BuildRequest, NodeKind, NodeParams

if TYPE_CHECKING:  # imported by the factories, when a tree is built (validation needs none)
    import py_trees


class WaitParams(NodeParams):
    """Stand by for ``duration`` seconds of sim time."""

    duration: float = Field(ge=0, allow_inf_nan=False, description="s of sim time")

    def summary(self) -> str:
        """``5 s``."""
        return f"{self.duration:g} s"


class ElapsedParams(NodeParams):
    """Succeed once the run's sim time has reached ``time`` seconds, else fail."""

    time: float = Field(ge=0, allow_inf_nan=False, description="s of sim time since the start")

    def summary(self) -> str:
        """``>= 30 s``."""
        return f">= {self.time:g} s"


class NoParams(NodeParams):
    """No parameters besides the optional ``name``."""


def _wait(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    from baobab.behaviours.timing import SimWait

    params = request.params_as(WaitParams)
    return SimWait(request.name, params.duration, request.capabilities.clock)


def _elapsed(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    from baobab.behaviours.conditions import Elapsed

    params = request.params_as(ElapsedParams)
    return Elapsed(request.name, params.time, request.capabilities.clock)


def _always_success(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    import py_trees

    from baobab.behaviours.actions import Constant

    return Constant(request.name, py_trees.common.Status.SUCCESS)


def _always_failure(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    import py_trees

    from baobab.behaviours.actions import Constant

    return Constant(request.name, py_trees.common.Status.FAILURE)


NODE_TYPES = (
    BehaviourType(
        "wait",
        NodeKind.ACTION,
        WaitParams,
        "wait duration s of sim time",
        _wait,
        shorthand="duration",
    ),
    BehaviourType(
        "elapsed",
        NodeKind.CONDITION,
        ElapsedParams,
        "succeed once the sim time has reached time s",
        _elapsed,
        shorthand="time",
    ),
    BehaviourType("always_success", NodeKind.ACTION, NoParams, "succeed at once", _always_success),
    BehaviourType("always_failure", NodeKind.ACTION, NoParams, "fail at once", _always_failure),
)
"""The capability-free node types."""
