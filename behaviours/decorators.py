"""Decorators baobab adds to py_trees: a sim-time timeout.

The other mission decorators (retry, repeat, invert, force_success, force_failure) are
py_trees' own, which count ticks and outcomes and never read a clock.
"""

from __future__ import annotations

import py_trees

from baobab.behaviours.ports import Clock

Status = py_trees.common.Status


class SimTimeout(py_trees.decorators.Decorator):
    """Fail the child if it is still RUNNING ``duration`` seconds of sim time after activation.

    The child is ticked first, so a child that finishes on the deadline tick keeps its result
    (as py_trees' wall-clock ``Timeout`` does). On timeout the child is stopped with INVALID,
    which cancels any goal it has in flight, and the decorator returns FAILURE.

    Args:
        name: the node's label.
        child: the decorated subtree.
        duration: the allowance (s, sim time, > 0).
        clock: returns the sim time (s).
    """

    def __init__(
        self, name: str, child: py_trees.behaviour.Behaviour, duration: float, clock: Clock
    ) -> None:
        super().__init__(name=name, child=child)
        if not duration > 0:
            raise ValueError(f"duration must be > 0 s, got {duration}")
        self.duration = duration
        self._clock = clock
        self.deadline = 0.0

    def initialise(self) -> None:
        """Arm the deadline at the current sim time."""
        self.deadline = self._clock() + self.duration
        self.feedback_message = ""

    def update(self) -> Status:
        """Reflect the child's status, or stop it and fail once the deadline has passed."""
        child_status = self.decorated.status
        if child_status is Status.RUNNING and self._clock() >= self.deadline:
            self.feedback_message = f"timed out after {self.duration:g} s"
            self.decorated.stop(Status.INVALID)
            return Status.FAILURE
        if child_status is Status.RUNNING:
            self.feedback_message = f"{self.deadline - self._clock():.2f} s left"
        return child_status
