"""Nav2's behaviour-tree control nodes, for py_trees, on sim time.

Nav2's default trees (reference/nav2.md §4) use four control nodes py_trees lacks:

- :class:`PipelineSequence`: re-ticks the children before the running one, so the planner
  branch keeps replanning while the controller runs.
- :class:`RecoveryNode`: ``[action, recovery]``; on the action's failure run the recovery and
  retry the action, at most ``number_of_retries`` times.
- :class:`RoundRobin`: tick the children in turn, resuming where the last activation ended.
- :class:`RateController`: tick the child at most ``hz`` times per second of sim time.

:class:`ReactiveFallback` is py_trees' memoryless ``Selector`` that also resets its children
on activation; Nav2's reactive sequence and (memoryful) sequence are py_trees' ``Sequence``.

The tree ticks at 20 Hz, so baobab's nodes tick their children by a direct call
(:meth:`Direct.step`, through :func:`tick_child`) instead of py_trees' nested generators, which
pass every node of the traversal up through every parent; py_trees' own nodes inside the tree
(the sequences) tick by :mod:`~baobab.nav.direct_tick`'s plain calls too, and
:meth:`Direct.tick` is the generator form of :meth:`Direct.step` for a py_trees caller.

BehaviorTree.CPP and py_trees differ in one way that matters here. In BT.CPP a parent *halts*
only running children and *resets* finished ones; py_trees stops both with ``INVALID``. The
nodes below tell the two apart by the status the node had when it was stopped, so a finished
round robin keeps its position (as in Nav2) while a halted one starts over.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from typing import ClassVar

import py_trees
from py_trees.behaviour import Behaviour

from baobab.nav.direct_tick import tick_once

Status = py_trees.common.Status
Clock = Callable[[], float]
"""Returns the sim time (s)."""


class Direct(Behaviour):
    """A node that ticks by a direct call: :meth:`step` does the whole tick and returns the
    new status; :meth:`tick`, py_trees' generator, runs it and yields the node once."""

    ticks_directly: ClassVar[bool] = True
    """Marks the nodes :mod:`~baobab.nav.direct_tick` ticks by :meth:`step` (a class attribute
    is read faster than ``isinstance`` answers for py_trees' abstract base class)."""

    def step(self) -> Status:
        """Tick once; the node's new status."""
        raise NotImplementedError

    def tick(self) -> Iterator[Behaviour]:
        """:meth:`step`, as py_trees' tick generator (yields the node itself)."""
        self.step()
        yield self


def tick_child(child: Behaviour) -> Status:
    """Tick ``child`` once (:func:`~baobab.nav.direct_tick.tick_once`: baobab's nodes by
    :meth:`Direct.step`, py_trees' own by plain calls) and return its new status."""
    tick_once(child)
    return child.status


class Leaf(Direct):
    """A py_trees leaf with the same lifecycle and less overhead per tick.

    ``step`` and ``stop`` do what :class:`py_trees.behaviour.Behaviour`'s ``tick`` and ``stop``
    do (initialise when not running, update, stop on a finished status, then record it)
    without formatting debug messages nobody reads or listing the status enum on every tick;
    the leaves tick at 20 Hz.
    """

    def step(self) -> Status:
        """Initialise if not running, update, stop when finished; the new status."""
        if self.status is not Status.RUNNING:
            self.initialise()
        new_status = self.update()
        if type(new_status) is not Status:  # py_trees: not in list(Status); no enum hashing
            self.logger.error(f"invalid status [{new_status}][{self.name}], setting INVALID")
            new_status = Status.INVALID
        if new_status is not Status.RUNNING:
            self.stop(new_status)
        self.status = new_status
        return new_status

    def stop(self, new_status: Status) -> None:
        """Terminate with ``new_status`` and record it (py_trees' ``stop`` without the log)."""
        self.terminate(new_status)
        self.status = new_status
        self.iterator = self.tick()


def _reset(children: Sequence[Behaviour]) -> None:
    for child in children:
        if child.status is not Status.INVALID:
            child.stop(Status.INVALID)


def _halt_running(children: Sequence[Behaviour]) -> None:
    for child in children:
        if child.status is Status.RUNNING:
            child.stop(Status.INVALID)


class PipelineSequence(Direct, py_trees.composites.Composite):
    """Nav2's ``PipelineSequence``: a sequence that keeps ticking the children it has passed.

    Each tick goes through the children from the first. A child that fails fails the whole
    sequence (running children are halted). A running child ends the tick unless a later
    child has already been started, in which case the tick goes on to it. The sequence
    succeeds when the last child succeeds.
    """

    def __init__(self, name: str, children: Sequence[Behaviour] | None = None) -> None:
        super().__init__(name, children)
        self._last_started = 0

    def step(self) -> Status:
        """Tick the children as described in the class docstring."""
        if self.status is not Status.RUNNING:
            _reset(self.children)
            self._last_started = 0
            self.initialise()
        for index, child in enumerate(self.children):
            status = tick_child(child)
            if status is Status.FAILURE:
                self._finish(Status.FAILURE)
                return self.status
            if status is Status.RUNNING and index >= self._last_started:
                self._last_started = index
                self.current_child = child
                self.status = Status.RUNNING
                return Status.RUNNING
        self._finish(Status.SUCCESS)
        return self.status

    def _finish(self, status: Status) -> None:
        _halt_running(self.children)
        self._last_started = 0
        self.stop(status)

    def stop(self, new_status: Status = Status.INVALID) -> None:
        """Halt (``INVALID``) or finish; a halt starts the next activation from scratch."""
        if new_status is Status.INVALID:
            self._last_started = 0
        super().stop(new_status)


class RecoveryNode(Direct, py_trees.composites.Composite):
    """Nav2's ``RecoveryNode``: ``[action, recovery]`` with a retry budget.

    The action's success is the node's success. When the action fails and fewer than
    ``number_of_retries`` retries were used, the recovery runs; if it succeeds the action is
    retried at once (same tick), if it fails the node fails. After the last retry the next
    failure of the action fails the node.

    Args:
        name: the node's label.
        number_of_retries: recoveries allowed per activation (>= 0).
        children: exactly two behaviours, the action and its recovery.
    """

    def __init__(self, name: str, number_of_retries: int, children: Sequence[Behaviour]) -> None:
        if len(children) != 2:
            raise ValueError(f"RecoveryNode '{name}' needs exactly 2 children")
        if number_of_retries < 0:
            raise ValueError(f"RecoveryNode '{name}' needs number_of_retries >= 0")
        super().__init__(name, children)
        self.number_of_retries = number_of_retries
        self.retry_count = 0
        self._index = 0

    def step(self) -> Status:
        """Tick the action, and the recovery when the action failed."""
        if self.status is not Status.RUNNING:
            _reset(self.children)
            self.retry_count = 0
            self._index = 0
            self.initialise()
        while True:
            child = self.children[self._index]
            status = tick_child(child)
            if status is Status.RUNNING:
                self.current_child = child
                self.status = Status.RUNNING
                return Status.RUNNING
            if self._index == 0:
                if status is Status.FAILURE and self.retry_count < self.number_of_retries:
                    self._index = 1
                    continue
                self._finish(status)
            elif status is Status.SUCCESS:
                self.retry_count += 1
                self._index = 0
                continue
            else:
                self._finish(Status.FAILURE)
            return self.status

    def _finish(self, status: Status) -> None:
        self._index = 0
        self.stop(status)

    def stop(self, new_status: Status = Status.INVALID) -> None:
        """Halt or finish; the retry budget is restored on the next activation."""
        if new_status is Status.INVALID:
            self._index = 0
        super().stop(new_status)


class RoundRobin(Direct, py_trees.composites.Composite):
    """Nav2's ``RoundRobin``: one child per activation, in turn.

    An activation starts at the child after the one that last finished and moves on while
    children fail. The first success ends the activation with SUCCESS (the next activation
    starts at the following child); when every child failed once it fails and starts over
    from the first child. A halt (stopped while running) also starts over from the first.
    """

    def __init__(self, name: str, children: Sequence[Behaviour] | None = None) -> None:
        super().__init__(name, children)
        self.index = 0
        self._failures = 0

    def step(self) -> Status:
        """Tick the current child; move on when it finishes."""
        if self.status is not Status.RUNNING:
            _reset(self.children)
            self._failures = 0
            self.initialise()
        count = len(self.children)
        while self._failures < count:
            child = self.children[self.index]
            status = tick_child(child)
            if status is Status.RUNNING:
                self.current_child = child
                self.status = Status.RUNNING
                return Status.RUNNING
            self.index = (self.index + 1) % count
            if status is Status.SUCCESS:
                self._failures = 0
                self.stop(Status.SUCCESS)
                return self.status
            self._failures += 1
        self.index = 0
        self._failures = 0
        self.stop(Status.FAILURE)
        return self.status

    def stop(self, new_status: Status = Status.INVALID) -> None:
        """A halt of a running round robin sends it back to its first child."""
        if new_status is Status.INVALID and self.status is Status.RUNNING:
            self.index = 0
            self._failures = 0
        super().stop(new_status)


class RateController(Direct, py_trees.decorators.Decorator):
    """Nav2's ``RateController``: tick the child at most ``hz`` times per second of sim time.

    The child is ticked on the first tick of an activation, on every tick while it runs, and
    again once ``1 / hz`` seconds passed since it last succeeded; in between the node returns
    RUNNING. ``tick_now`` (baobab's addition) forces a tick, e.g. when the goal changed, so a
    preempting goal is planned for at once instead of at the next period.

    Args:
        name: the node's label.
        child: the rate-limited subtree.
        hz: the highest tick rate (Hz, > 0).
        clock: the sim clock (s).
        tick_now: optional predicate; True ticks the child now whatever the rate.
    """

    def __init__(
        self,
        name: str,
        child: Behaviour,
        hz: float,
        clock: Clock,
        tick_now: Callable[[], bool] | None = None,
    ) -> None:
        if not hz > 0:
            raise ValueError(f"RateController '{name}' needs hz > 0, got {hz}")
        super().__init__(name=name, child=child)
        self.period = 1.0 / hz
        self._clock = clock
        self._tick_now = tick_now
        self._start = 0.0
        self._first = True

    def step(self) -> Status:
        """Tick the child when due, else report RUNNING."""
        now = self._clock()
        if self.status in (Status.INVALID, Status.FAILURE):
            self._start = now
            self._first = True
            self.initialise()
        due = (
            self._first
            or self.decorated.status is Status.RUNNING
            or now - self._start >= self.period - 1e-9
            or (self._tick_now is not None and self._tick_now())
        )
        if not due:
            self.status = Status.RUNNING
            return Status.RUNNING
        self._first = False
        status = tick_child(self.decorated)
        if status is Status.RUNNING:
            self.status = Status.RUNNING
        else:
            if status is Status.SUCCESS:
                self._start = self._clock()
            self.stop(status)
        return self.status

    def update(self) -> Status:
        """Unused: :meth:`step` decides."""
        return self.status


class Condition(Leaf):
    """A leaf that returns SUCCESS when ``predicate()`` holds, else FAILURE."""

    def __init__(self, name: str, predicate: Callable[[], bool]) -> None:
        super().__init__(name=name)
        self._predicate = predicate

    def update(self) -> Status:
        """Evaluate the predicate."""
        return Status.SUCCESS if self._predicate() else Status.FAILURE


class ReactiveFallback(py_trees.composites.Selector):
    """Nav2's ``ReactiveFallback``: every tick re-checks the children from the first.

    py_trees' memoryless ``Selector`` with one BT.CPP detail added: children are reset when
    an activation starts, so a condition that remembers state (``GoalUpdated``) starts fresh.
    """

    def __init__(self, name: str, children: Sequence[Behaviour]) -> None:
        super().__init__(name, memory=False, children=list(children))

    def tick(self) -> Iterator[Behaviour]:
        """Reset the children on activation, then tick like a memoryless selector."""
        if self.status is not Status.RUNNING:
            _reset(self.children)
        yield from super().tick()


def reactive_sequence(name: str, children: Sequence[Behaviour]) -> py_trees.composites.Sequence:
    """Nav2's ``ReactiveSequence``: re-checks earlier children every tick."""
    return py_trees.composites.Sequence(name, memory=False, children=list(children))


def sequence(name: str, children: Sequence[Behaviour]) -> py_trees.composites.Sequence:
    """BT.CPP's ``Sequence`` (with memory): resumes at the running child."""
    return py_trees.composites.Sequence(name, memory=True, children=list(children))
