"""Sim-time waiting: py_trees' own ``Timer`` reads the wall clock, this reads the sim clock."""

from __future__ import annotations

import py_trees

from baobab.behaviours.ports import Clock

Status = py_trees.common.Status


class SimWait(py_trees.behaviour.Behaviour):
    """RUNNING until ``duration`` seconds of sim time have passed since activation.

    Args:
        name: the node's label.
        duration: how long to wait (s, sim time, >= 0).
        clock: returns the sim time (s).
    """

    def __init__(self, name: str, duration: float, clock: Clock) -> None:
        super().__init__(name=name)
        if duration < 0:
            raise ValueError(f"duration must be >= 0 s, got {duration}")
        self.duration = duration
        self._clock = clock
        self._end = 0.0

    def initialise(self) -> None:
        """Start the wait at the current sim time."""
        self._end = self._clock() + self.duration

    def update(self) -> Status:
        """SUCCESS at the first tick at or after the end time, else RUNNING."""
        remaining = self._end - self._clock()
        if remaining <= 0.0:
            self.feedback_message = "done"
            return Status.SUCCESS
        self.feedback_message = f"{remaining:.2f} s left"
        return Status.RUNNING
