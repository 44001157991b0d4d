"""The navigation server's one running task: started, preempted, canceled and ticked here.

Goals while a task runs (the choice, following Nav2's action servers):

- same type, navigation or FollowPath or FollowWaypoints: preempted in place. The robot keeps
  going towards the new goal, which is planned for on the next tick; navigation time and
  recoveries restart; the old handle ends FAILED with error code 0 ("preempted"), as Nav2
  aborts it with an empty result.
- same type, a behaviour (spin, back up, ...): behaviours cannot be preempted in Nav2; the
  old one is aborted the same way (FAILED, code 0) and the new one starts.
- another type: the running task is canceled (CANCELED) and the new one starts. (Nav2 wants
  an explicit cancel first; doing it here is what a caller would do anyway.)

Canceling (:meth:`TaskSlot.cancel` or the handle's) halts the task and commands zero velocity
at once.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from baobab.nav.controller_server import PathFollower
from baobab.nav.interfaces import MobileBase, ServerTask
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus

CANCELED = TaskOutcome(TaskStatus.CANCELED, 0, "canceled")
"""How a canceled task ends (also a task of one type replaced by one of another)."""


def preempted(name: str) -> TaskOutcome:
    """How a task ends that a new goal of the same type replaced."""
    return TaskOutcome(TaskStatus.FAILED, 0, f"preempted by a new {name} goal")


@dataclass
class _Active:
    handle: TaskHandle
    task: ServerTask
    next_tick: float
    """Sim time (s) of the task's next tick."""


class TaskSlot:
    """At most one running task of one navigation server, and its handle.

    Args:
        base: the robot's base, stopped whenever a task is halted.
        follower: the controller, whose current path is dropped when a task starts.
        clock: the sim time (s).
    """

    def __init__(self, base: MobileBase, follower: PathFollower, clock: Callable[[], float]):
        self._base = base
        self._follower = follower
        self._clock = clock
        self._active: _Active | None = None

    @property
    def task(self) -> ServerTask | None:
        """The running task itself (for inspection), or None."""
        return None if self._active is None else self._active.task

    @property
    def handle(self) -> TaskHandle | None:
        """The handle of the running task, or None."""
        return None if self._active is None else self._active.handle

    def submit(
        self,
        name: str,
        make: Callable[[], ServerTask],
        preempt: Callable[[ServerTask], bool] | None,
    ) -> TaskHandle:
        """Start the task ``make()`` builds, or hand the new goal to the running task.

        Args:
            name: the task type (``navigate_to_pose``, ``spin``, ...).
            make: builds the new task.
            preempt: gives a running task of the same type the new goal; True if it took it
                (None: tasks of this type cannot be preempted).
        """
        handle = TaskHandle(name, self._on_cancel)
        handle.started_at = self._clock()
        active = self._active
        if active is not None:
            # The task's feedback dict goes on with the new goal; the old handle keeps a copy
            # of its last feedback, so it no longer changes (nor is cleared) once it has ended.
            last_feedback = dict(active.task.feedback)
            if active.handle.name == name and preempt is not None and preempt(active.task):
                previous, active.handle = active.handle, handle
                handle.feedback = active.task.feedback
                previous.feedback = last_feedback
                self._finish(previous, preempted(name))
                return handle
            self._active = None
            active.task.halt()
            self._base.stop()
            same = active.handle.name == name
            self._finish(active.handle, preempted(name) if same else CANCELED)
        self._follower.path = None  # no current path until the new task plans or brings one
        task = make()
        handle.feedback = task.feedback
        self._active = _Active(handle, task, next_tick=self._clock())
        return handle

    def cancel(self) -> None:
        """Cancel the running task, if any: CANCELED, robot commanded to stop at once."""
        if self._active is not None:
            self._active.handle.cancel()

    def tick(self, now: float) -> None:
        """Tick the running task when its period has passed; finish it when it ends."""
        active = self._active
        if active is None or now < active.next_tick - 1e-9:
            return
        active.next_tick = now + active.task.period
        outcome = active.task.tick(now)
        if outcome is not None and self._active is active:
            self._active = None
            self._base.stop()
            self._finish(active.handle, outcome)

    def _on_cancel(self, handle: TaskHandle) -> None:
        active = self._active
        if active is None or active.handle is not handle:
            return
        self._active = None
        active.task.halt()
        self._base.stop()
        self._finish(handle, CANCELED)

    def _finish(self, handle: TaskHandle, outcome: TaskOutcome) -> None:
        """End ``handle`` with ``outcome`` now (its ``ended_at`` is the sim time)."""
        if handle.outcome is None:
            handle.ended_at = self._clock()
        handle.finish(outcome)
