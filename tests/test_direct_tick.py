"""The direct tick does what py_trees' generator tick does, call for call, on random trees."""

from __future__ import annotations

import random

import py_trees
import pytest

from baobab.behaviours.decorators import SimTimeout
from baobab.nav.direct_tick import tick_once

Status = py_trees.common.Status
Behaviour = py_trees.behaviour.Behaviour


class Scripted(Behaviour):
    """A leaf whose ``update`` draws its status from its own seeded generator and which logs
    its lifecycle calls."""

    def __init__(self, name: str, log: list[str], seed: int, invalid: bool) -> None:
        super().__init__(name=name)
        self._log = log
        self._rng = random.Random(seed)
        self._choices: list[object] = [Status.RUNNING, Status.SUCCESS, Status.FAILURE]
        if invalid:
            self._choices.append("bogus")  # py_trees turns it into INVALID

    def initialise(self) -> None:
        self._log.append(f"{self.name}.initialise")

    def update(self) -> Status:
        status = self._rng.choice(self._choices)
        self._log.append(f"{self.name}.update->{status}")
        return status  # type: ignore[return-value]

    def terminate(self, new_status: Status) -> None:
        self._log.append(f"{self.name}.terminate({new_status})")


class Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def _tree(rng: random.Random, log: list[str], clock: Clock, depth: int) -> Behaviour:
    """A random tree of every composite and decorator kind a mission builds (and OneShot,
    whose own ``tick`` the direct tick must fall back to)."""
    name = f"n{len(log)}_{rng.randrange(10**6)}"
    log.append("")  # keeps names unique; the log is cleared before ticking
    kind = rng.choice(["leaf"] * 3 + ["composite"] * 3 + ["decorator"] * 3 if depth else ["leaf"])
    if kind == "leaf":
        return Scripted(name, log, rng.randrange(10**9), invalid=rng.random() < 0.1)
    if kind == "composite":
        children = [_tree(rng, log, clock, depth - 1) for _ in range(rng.randrange(0, 4))]
        make = rng.choice(["sequence", "selector", "parallel"])
        if make == "parallel":
            policy = rng.choice(
                [
                    py_trees.common.ParallelPolicy.SuccessOnAll(synchronise=rng.random() < 0.5),
                    py_trees.common.ParallelPolicy.SuccessOnOne(),
                ]
            )
            return py_trees.composites.Parallel(name, policy=policy, children=children)
        memory = rng.random() < 0.5
        if make == "sequence":
            return py_trees.composites.Sequence(name, memory=memory, children=children)
        return py_trees.composites.Selector(name, memory=memory, children=children)
    child = _tree(rng, log, clock, depth - 1)
    kinds = ["retry", "repeat", "invert", "pass", "success", "failure", "timeout", "once"]
    make = rng.choice(kinds)
    decorators = py_trees.decorators
    if make == "retry":
        return decorators.Retry(name, child, num_failures=rng.randrange(1, 4))
    if make == "repeat":
        return decorators.Repeat(name, child, num_success=rng.randrange(1, 4))
    if make == "invert":
        return decorators.Inverter(name, child)
    if make == "pass":
        return decorators.PassThrough(name, child)
    if make == "success":
        return decorators.FailureIsSuccess(name, child)
    if make == "failure":
        return decorators.SuccessIsFailure(name, child)
    if make == "timeout":
        return SimTimeout(name, child, duration=rng.choice([0.1, 0.35]), clock=clock)
    once = rng.choice(list(py_trees.common.OneShotPolicy))
    return decorators.OneShot(name, child, policy=once)


def _run(seed: int, direct: bool) -> list[str]:
    """Build the tree of ``seed`` and tick it 40 times (halting it now and then); the log of
    lifecycle calls and every node's status and current child after each tick."""
    rng = random.Random(seed)
    log: list[str] = []
    clock = Clock()
    root = _tree(rng, log, clock, depth=4)
    log.clear()
    for tick in range(40):
        clock.now = 0.1 * tick
        if tick % 13 == 12:
            root.stop(Status.INVALID)
            log.append("halt")
        elif direct:
            tick_once(root)
        else:
            root.tick_once()
        for node in root.iterate():
            current = getattr(node, "current_child", None)
            log.append(f"{node.name}:{node.status}:{None if current is None else current.name}")
    return log


@pytest.mark.parametrize("seed", range(300))
def test_the_direct_tick_makes_the_calls_the_generator_tick_makes(seed: int) -> None:
    assert _run(seed, direct=True) == _run(seed, direct=False)


def test_the_random_trees_reach_every_status() -> None:
    """The comparison above means something: the trees finish, fail, run and halt."""
    seen = {entry.split(":")[1] for seed in range(40) for entry in _run(seed, True) if ":" in entry}
    assert {str(status) for status in Status} <= seen
