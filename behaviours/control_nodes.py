"""Composites, decorators and subtree calls: the control-flow vocabulary of mission trees.

Composites always state ``memory``. The short form ``sequence: [...]`` (and
``selector: [...]``) means ``memory: true``: resume at the running child, as BehaviorTree.CPP's
``Sequence``/``Fallback``. ``memory: false`` re-checks earlier children on every tick (BT.CPP's
``ReactiveSequence``/``ReactiveFallback``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import Field, model_validator

from baobab.behaviours.registry import (
    BehaviourType,
    BuildRequest,
    NodeData,
    NodeKind,
    NodeParams,
)

if TYPE_CHECKING:  # imported by the factories, when a tree is built (validation needs none)
    import py_trees

Children = Annotated[list[NodeData], Field(min_length=1, description="the child nodes, in order")]
Child = Annotated[NodeData, Field(description="the decorated node")]


class SequenceParams(NodeParams):
    """Children in order; fails at the first failure."""

    memory: bool = Field(
        default=True, description="true: resume at the running child; false: re-tick from the first"
    )
    children: Children

    def summary(self) -> str:
        """``reactive`` for a memoryless composite."""
        return "" if self.memory else "(reactive)"


class SelectorParams(SequenceParams):
    """Children in order until one succeeds; fails when all fail."""


class ParallelParams(NodeParams):
    """All children ticked every tick; any failure fails the parallel."""

    policy: Literal["success_on_all", "success_on_one"] = Field(
        default="success_on_all", description="succeed when all children or when one succeeds"
    )
    synchronise: bool | None = Field(
        default=None,
        description="success_on_all only: skip children that already succeeded (default true)",
    )
    children: Children

    @model_validator(mode="after")
    def _synchronise_needs_all(self) -> ParallelParams:
        if self.synchronise is not None and self.policy != "success_on_all":
            raise ValueError("synchronise applies to policy success_on_all only")
        return self

    def summary(self) -> str:
        """The policy."""
        return self.policy


class RetryParams(NodeParams):
    """Re-run the child after a failure; fails after ``num_failures`` failed attempts."""

    num_failures: int = Field(ge=1, description="attempts in total before giving up")
    child: Child

    def summary(self) -> str:
        """``x3``."""
        return f"x{self.num_failures}"


class TimeoutParams(NodeParams):
    """Fail (and cancel the child) if it is still running after ``duration`` s of sim time."""

    duration: float = Field(gt=0, allow_inf_nan=False, description="s of sim time")
    child: Child

    def summary(self) -> str:
        """``30 s``."""
        return f"{self.duration:g} s"


class RepeatParams(NodeParams):
    """Re-run the child after each success until ``num_success`` successes; -1 = forever."""

    num_success: int = Field(ge=-1, description="successes needed; -1 repeats forever")
    child: Child

    @model_validator(mode="after")
    def _not_zero(self) -> RepeatParams:
        if self.num_success == 0:
            raise ValueError("num_success must be at least 1, or -1 for forever")
        return self

    def summary(self) -> str:
        """``x3`` or ``forever``."""
        return "forever" if self.num_success == -1 else f"x{self.num_success}"


class DecoratorParams(NodeParams):
    """Just the child; ``invert: {is_at: door}`` is short for ``invert: {child: {is_at: door}}``."""

    child: Child


class SubtreeCall(NodeParams):
    """Use a subtree of this file: ``subtree: {name: deliver, args: {table: 3}}``."""

    name: str = Field(description="the subtree's key under subtrees:")
    args: dict[str, Any] = Field(default_factory=dict, description="values of its params")

    def summary(self) -> str:
        """``deliver(table=3)``."""
        args = ", ".join(f"{key}={value}" for key, value in self.args.items())
        return f"{self.name}({args})"


def _sequence(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    import py_trees

    params = request.params_as(SequenceParams)
    return py_trees.composites.Sequence(
        name=request.name, memory=params.memory, children=list(request.children)
    )


def _selector(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    import py_trees

    params = request.params_as(SelectorParams)
    return py_trees.composites.Selector(
        name=request.name, memory=params.memory, children=list(request.children)
    )


def _parallel(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    import py_trees

    params = request.params_as(ParallelParams)
    policy: py_trees.common.ParallelPolicy.Base
    if params.policy == "success_on_all":
        synchronise = True if params.synchronise is None else params.synchronise
        policy = py_trees.common.ParallelPolicy.SuccessOnAll(synchronise=synchronise)
    else:
        policy = py_trees.common.ParallelPolicy.SuccessOnOne()
    return py_trees.composites.Parallel(
        name=request.name, policy=policy, children=list(request.children)
    )


def _retry(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    import py_trees

    params = request.params_as(RetryParams)
    return py_trees.decorators.Retry(
        name=request.name, child=request.child, num_failures=params.num_failures
    )


def _timeout(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    from baobab.behaviours.decorators import SimTimeout

    params = request.params_as(TimeoutParams)
    return SimTimeout(request.name, request.child, params.duration, request.capabilities.clock)


def _repeat(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    import py_trees

    params = request.params_as(RepeatParams)
    return py_trees.decorators.Repeat(
        name=request.name, child=request.child, num_success=params.num_success
    )


def _invert(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    import py_trees

    return py_trees.decorators.Inverter(name=request.name, child=request.child)


def _force_success(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    import py_trees

    return py_trees.decorators.FailureIsSuccess(name=request.name, child=request.child)


def _force_failure(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    import py_trees

    return py_trees.decorators.SuccessIsFailure(name=request.name, child=request.child)


def _subtree(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    import py_trees

    return py_trees.decorators.PassThrough(name=request.name, child=request.child)


NODE_TYPES = (
    BehaviourType(
        "sequence",
        NodeKind.COMPOSITE,
        SequenceParams,
        "run children in order; fail at the first failure",
        _sequence,
        shorthand="children",
    ),
    BehaviourType(
        "selector",
        NodeKind.COMPOSITE,
        SelectorParams,
        "try children in order until one succeeds",
        _selector,
        shorthand="children",
    ),
    BehaviourType(
        "parallel",
        NodeKind.COMPOSITE,
        ParallelParams,
        "tick all children together; policy success_on_all or success_on_one",
        _parallel,
        shorthand="children",
    ),
    BehaviourType(
        "retry",
        NodeKind.DECORATOR,
        RetryParams,
        "re-run the child after a failure, num_failures attempts in all",
        _retry,
    ),
    BehaviourType(
        "timeout",
        NodeKind.DECORATOR,
        TimeoutParams,
        "fail and cancel the child after duration s of sim time",
        _timeout,
    ),
    BehaviourType(
        "repeat",
        NodeKind.DECORATOR,
        RepeatParams,
        "re-run the child after each success, num_success times (-1 forever)",
        _repeat,
    ),
    BehaviourType(
        "invert",
        NodeKind.DECORATOR,
        DecoratorParams,
        "swap the child's success and failure",
        _invert,
        shorthand="child",
    ),
    BehaviourType(
        "force_success",
        NodeKind.DECORATOR,
        DecoratorParams,
        "succeed when the child finishes, whatever its result",
        _force_success,
        shorthand="child",
    ),
    BehaviourType(
        "force_failure",
        NodeKind.DECORATOR,
        DecoratorParams,
        "fail when the child finishes, whatever its result",
        _force_failure,
        shorthand="child",
    ),
    BehaviourType(
        "subtree",
        NodeKind.SUBTREE,
        SubtreeCall,
        "use a subtree of this file with arguments",
        _subtree,
        shorthand="name",
    ),
)
"""The control-flow node types, in the order ``baobab list`` shows them."""
