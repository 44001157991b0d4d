"""Nav2's control nodes for py_trees: each one's ticking, retry and halt rules, on sim time."""

from __future__ import annotations

from collections.abc import Iterator

import py_trees
import pytest
from py_trees.behaviour import Behaviour

from baobab.nav.bt import (
    Condition,
    PipelineSequence,
    RateController,
    ReactiveFallback,
    RecoveryNode,
    RoundRobin,
)

Status = py_trees.common.Status
S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING


class Scripted(Behaviour):
    """Returns the statuses of ``script`` in turn (the last one repeats); logs its life."""

    def __init__(self, name: str, *script: Status) -> None:
        super().__init__(name=name)
        self.script = list(script)
        self.ticks = 0
        self.starts = 0
        self.halts = 0

    def initialise(self) -> None:
        self.starts += 1

    def update(self) -> Status:
        status = self.script[min(self.ticks, len(self.script) - 1)]
        self.ticks += 1
        return status

    def terminate(self, new_status: Status) -> None:
        if new_status is Status.INVALID and self.status is Status.RUNNING:
            self.halts += 1


class Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def tick(root: Behaviour, times: int = 1) -> Status:
    for _ in range(times):
        root.tick_once()
    return root.status


def statuses(root: Behaviour, times: int) -> Iterator[Status]:
    for _ in range(times):
        yield tick(root)


def test_pipeline_sequence_reticks_earlier_children_while_a_later_one_runs() -> None:
    planner = Scripted("planner", S)
    controller = Scripted("controller", R, R, S)
    root = PipelineSequence("pipeline", [planner, controller])
    assert list(statuses(root, 3)) == [R, R, S]
    assert planner.ticks == 3  # replanned on every tick while the controller ran
    assert controller.starts == 1  # the controller kept running, it did not restart


def test_pipeline_sequence_fails_when_an_earlier_child_fails_and_halts_the_runner() -> None:
    planner = Scripted("planner", S, F)
    controller = Scripted("controller", R)
    root = PipelineSequence("pipeline", [planner, controller])
    assert list(statuses(root, 2)) == [R, F]
    assert controller.halts == 1


def test_pipeline_sequence_waits_on_a_running_first_child() -> None:
    first = Scripted("first", R, S)
    second = Scripted("second", S)
    root = PipelineSequence("pipeline", [first, second])
    assert list(statuses(root, 2)) == [R, S]
    assert second.ticks == 1


def test_recovery_node_retries_after_each_successful_recovery() -> None:
    action = Scripted("action", F, F, S)
    recovery = Scripted("recovery", S)
    root = RecoveryNode("recover", 2, [action, recovery])
    assert tick(root) is S  # fail, recover, fail, recover, succeed: all in one tick
    assert (action.ticks, recovery.ticks, root.retry_count) == (3, 2, 2)


def test_recovery_node_fails_after_the_last_retry_or_when_the_recovery_fails() -> None:
    action = Scripted("action", F)
    recovery = Scripted("recovery", S)
    root = RecoveryNode("recover", 2, [action, recovery])
    assert tick(root) is F
    assert (action.ticks, recovery.ticks) == (3, 2)
    action, recovery = Scripted("action", F), Scripted("recovery", F)
    assert tick(RecoveryNode("recover", 5, [action, recovery])) is F
    assert (action.ticks, recovery.ticks) == (1, 1)
    assert tick(RecoveryNode("none", 0, [Scripted("a", F), Scripted("r", S)])) is F


def test_recovery_node_runs_a_running_recovery_over_ticks() -> None:
    action = Scripted("action", F, S)
    recovery = Scripted("recovery", R, R, S)
    root = RecoveryNode("recover", 1, [action, recovery])
    assert list(statuses(root, 3)) == [R, R, S]
    assert root.retry_count == 1
    assert tick(root) is S and root.retry_count == 0  # a new activation has a full budget
    with pytest.raises(ValueError, match="exactly 2 children"):
        RecoveryNode("bad", 1, [Scripted("only", S)])


def test_round_robin_resumes_after_the_child_that_last_succeeded() -> None:
    children = [Scripted("clear", S), Scripted("spin", S), Scripted("wait", S)]
    root = RoundRobin("recoveries", children)
    order = []
    for _ in range(4):
        before = [child.ticks for child in children]
        assert tick(root) is S
        order += [c.name for c, n in zip(children, before, strict=True) if c.ticks > n]
        root.stop(Status.INVALID)  # the parent resets the finished node between activations
    assert order == ["clear", "spin", "wait", "clear"]


def test_round_robin_skips_failing_children_and_fails_when_all_fail() -> None:
    spin, wait = Scripted("spin", F), Scripted("wait", S)
    root = RoundRobin("recoveries", [spin, wait])
    assert tick(root) is S and (spin.ticks, wait.ticks) == (1, 1)
    assert tick(RoundRobin("all", [Scripted("a", F), Scripted("b", F)])) is F


def test_round_robin_halted_while_running_starts_over() -> None:
    first, second = Scripted("first", S), Scripted("second", R)
    root = RoundRobin("recoveries", [first, second])
    assert tick(root) is S  # first
    assert tick(root) is R  # second runs
    root.stop(Status.INVALID)
    assert second.halts == 1 and root.index == 0
    tick(root)
    assert first.ticks == 2


def test_rate_controller_ticks_its_child_at_most_at_the_rate() -> None:
    clock = Clock()
    child = Scripted("plan", S)
    root = RateController("rate", child, 1.0, clock)
    ticked_at = []
    for step in range(45):  # 20 Hz for 2.2 s
        clock.now = step * 0.05
        before = child.ticks
        tick(root)
        if child.ticks > before:
            ticked_at.append(round(clock.now, 2))
    assert ticked_at == [0.0, 1.0, 2.0]
    assert root.status is R  # between child ticks the node reports RUNNING


def test_rate_controller_ticks_a_running_child_every_time_and_on_demand() -> None:
    clock = Clock()
    child = Scripted("plan", R, R, S, S)
    forced = [False]
    root = RateController("rate", child, 1.0, clock, tick_now=lambda: forced[0])
    for step in range(4):
        clock.now = step * 0.05
        tick(root)
    assert child.ticks == 3  # running, running, success; then wait for the period
    forced[0] = True
    clock.now = 0.25
    tick(root)
    assert child.ticks == 4
    with pytest.raises(ValueError, match="hz > 0"):
        RateController("bad", Scripted("x", S), 0.0, clock)


class GoalSeen(Behaviour):
    """Remembers a value on its first tick after a reset and succeeds once it changes."""

    def __init__(self, value: list[int]) -> None:
        super().__init__(name="GoalUpdated")
        self.value = value
        self.seen: int | None = None

    def update(self) -> Status:
        if self.seen is None or self.seen == self.value[0]:
            self.seen = self.value[0]
            return F
        return S

    def terminate(self, new_status: Status) -> None:
        if new_status is Status.INVALID:
            self.seen = None


def test_reactive_fallback_rechecks_the_condition_and_resets_it_per_activation() -> None:
    goal = [0]
    condition = GoalSeen(goal)
    recovery = Scripted("recovery", R)
    root = ReactiveFallback("fallback", [condition, recovery])
    assert tick(root, 2) is R
    goal[0] = 1  # the goal changes while the recovery runs: it is aborted
    assert tick(root) is S
    assert recovery.halts == 1
    # A later activation starts with the goal as it is then, not as first seen.
    assert tick(root) is R


def test_condition_reports_its_predicate() -> None:
    assert tick(Condition("yes", lambda: True)) is S
    assert tick(Condition("no", lambda: False)) is F
