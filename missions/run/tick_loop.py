"""The run loop: tick the tree, advance the sim, apply timed events, record.

Every tick period (0.1 s of sim time, 10 Hz) the loop records the robot's state, ticks the
tree once, records the nodes whose status changed and the tasks that ended, then advances the
simulation to the next tick; controllers, sensors and metric probes run inside at their own
rates. A timed event falls due inside that advance: the sim stops exactly at its time (rounded
up to a physics step) and the event is applied there. The loop ends when the root is no
longer RUNNING, when a cancel event fires or the run is interrupted (the tree is halted, so
running goals are canceled, and the robot is stopped: CANCELED), or when the mission timeout
passes (FAILED, ``MISSION_TIMEOUT``), or when a fault monitor trips or the physics diverges
(FAILED with the fault's 99xx code). A mission never hangs: the timeout is in sim time and
the sim always advances.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

import py_trees

from baobab.behaviours.actions import GoalTaskLeaf
from baobab.missions.language.compiler import CompiledMission
from baobab.missions.language.error_codes import MissionErrorCode
from baobab.missions.run.events import TimedEvents
from baobab.missions.run.progress_display import ProgressSink, ProgressSnapshot
from baobab.missions.run.rig import Rig
from baobab.missions.run.trace import Trace
from baobab.nav.direct_tick import tick_once
from baobab.sim.errors import SimulationError
from baobab.sim.tasks import TaskHandle, TaskStatus

Status = py_trees.common.Status

TICK_PERIOD = 0.1
"""Behaviour-tree tick period (s of sim time): 10 Hz."""
FEEDBACK_PERIOD = 1.0
"""How often running tasks' feedback goes into the trace (s of sim time)."""


@dataclass(frozen=True)
class LoopOutcome:
    """How the loop ended.

    Attributes:
        result: ``SUCCEEDED``, ``FAILED`` or ``CANCELED``.
        error_code: 0, a task's error code, or a :class:`MissionErrorCode`.
        error_name: the code's name.
        error_msg: one line for people.
        sim_time: sim time at the end (s).
        interrupted: True when the run was stopped from outside (a signal).
    """

    result: str
    error_code: int
    error_name: str
    error_msg: str
    sim_time: float
    interrupted: bool = False


class FaultWatch(Protocol):
    """Watches the robot for faults (:mod:`baobab.missions.run.fault_monitors`)."""

    def check(self, now: float) -> tuple[MissionErrorCode, str] | None:
        """The fault seen at ``now`` (s): its code and one line, or None."""
        ...

    def explain_divergence(self, message: str) -> str:
        """A SimulationError's message, naming what became non-finite."""
        ...


class Pacer(Protocol):
    """Slows the loop to the wall clock (``--realtime``, the viewer)."""

    def wait(self, sim_time: float) -> float:
        """Return once the wall clock has caught up with ``sim_time`` (s)."""
        ...


class RunLoop:
    """Runs one compiled mission on its rig, writing the trace.

    Args:
        compiled: the compiled tree.
        rig: the robot, its sim and its servers.
        trace: where records go.
        events: the mission's timed events.
        timeout: the mission timeout (s of sim time).
        progress: receives a snapshot after every tick.
        pacer: paces to the wall clock (``--realtime``); None runs as fast as possible.
        interrupted: polled every tick; a true value stops the run as CANCELED: the name of
            the signal that stopped it (``"SIGTERM"``), or True for SIGINT.
        on_tick: called after every tick (e.g. to sync a viewer).
        tick_period: s of sim time between ticks.
        faults: asked every tick for a fault that ends the run FAILED (before the tree
            ticks), and to explain a divergence.
    """

    def __init__(
        self,
        compiled: CompiledMission,
        rig: Rig,
        trace: Trace,
        events: TimedEvents,
        timeout: float,
        *,
        progress: ProgressSink | None = None,
        pacer: Pacer | None = None,
        interrupted: Callable[[], bool | str | None] | None = None,
        on_tick: Callable[[], None] | None = None,
        tick_period: float = TICK_PERIOD,
        faults: FaultWatch | None = None,
    ) -> None:
        self.compiled = compiled
        self.rig = rig
        self.sim = rig.sim
        self.trace = trace
        self.events = events
        self.timeout = timeout
        self.progress = progress
        self.pacer = pacer
        self.interrupted = interrupted or (lambda: False)
        self.on_tick = on_tick
        self.faults = faults
        self.tick_steps = self.sim.steps_for(tick_period, what="tick period")
        self.timeout_step = math.ceil(timeout / self.sim.physics_dt - 1e-9)
        self.root = compiled.root
        self._behaviours = list(self.root.iterate())
        self._statuses = [Status.INVALID] * len(self._behaviours)
        """The status each of ``_behaviours`` had at the last record (same order)."""
        self._goal_leaves = compiled.goal_leaves()
        self._handles: list[tuple[TaskHandle | None, bool]] = [(None, False)] * len(
            self._goal_leaves
        )
        """Each goal leaf's latest handle and whether its outcome is recorded (same order)."""
        self._last_feedback = -math.inf
        self._last_state = -math.inf
        self._wall_start = time.perf_counter()

    # -- the loop ----------------------------------------------------------------------------

    def run(self) -> LoopOutcome:
        """Run until the tree finishes, the run is canceled, or the timeout passes."""
        sim = self.sim
        self._wall_start = time.perf_counter()
        try:
            self._record_events(self.events.apply_due(sim.time))
            if self.events.canceled_by is not None:
                return self._cancel(self._cancel_message())
            while True:
                now = sim.time
                self._record_sim()
                self._record_state(now)
                fault = None if self.faults is None else self.faults.check(now)
                if fault is not None:
                    return self._fault(*fault)
                self._tick_tree()
                self._record_tree(now)
                self._report(now)
                if self.on_tick is not None:
                    self.on_tick()
                status = self.root.status
                if status is Status.SUCCESS:
                    return self._end("SUCCEEDED", 0, "NONE", "")
                if status is Status.FAILURE:
                    return self._failed()
                if cause := self.interrupted():
                    name = cause if isinstance(cause, str) else "SIGINT"
                    return self._cancel(f"interrupted ({name})", interrupted=True)
                if sim.step_count >= self.timeout_step:
                    return self._timed_out()
                target = min(sim.step_count + self.tick_steps, self.timeout_step)
                if self._advance_to(target):
                    return self._cancel(self._cancel_message())
                if self.pacer is not None:
                    self.pacer.wait(sim.time)
        except SimulationError as exc:
            message = str(exc) if self.faults is None else self.faults.explain_divergence(str(exc))
            return self._fault(MissionErrorCode.SIMULATION_ERROR, message)

    def _tick_tree(self) -> None:
        """Tick the tree once.

        ``BehaviourTree.tick`` walks every node after the tick to offer it to visitors; with
        no visitors or handlers (a compiled mission has none) ticking the root is the same
        tick without that walk, and :func:`~baobab.nav.direct_tick.tick_once` does it
        by plain calls rather than py_trees' generators.
        """
        tree = self.compiled.tree
        if tree.visitors or tree.pre_tick_handlers or tree.post_tick_handlers:
            tree.tick()
            return
        tick_once(tree.root)
        tree.count += 1

    def _advance_to(self, target_step: int) -> bool:
        """Step to ``target_step``, stopping at due events; True when a cancel event fired."""
        sim = self.sim
        while sim.step_count < target_step:
            due = self.events.next_time()
            due_step = None if due is None else math.ceil(due / sim.physics_dt - 1e-9)
            if due_step is not None and due_step <= target_step:
                sim.step_to(due_step)
                self._record_events(self.events.apply_due(sim.time))
                if self.events.canceled_by is not None:
                    return True
            else:
                sim.step_to(target_step)
        return False

    # -- endings -----------------------------------------------------------------------------

    def _halt(self) -> None:
        """Stop the tree (running goals are canceled) and the robot."""
        self.root.stop(Status.INVALID)
        self.rig.stop()
        self._record_tree(self.sim.time)

    def _end(
        self, result: str, code: int, name: str, message: str, *, interrupted: bool = False
    ) -> LoopOutcome:
        now = self.sim.time
        self._record_sim()
        self._record_state(now)
        self.trace.add(
            now, "end", result=result, error_code=int(code), error_name=name, error_msg=message
        )
        return LoopOutcome(result, int(code), name, message, now, interrupted)

    def _cancel(self, message: str, *, interrupted: bool = False) -> LoopOutcome:
        self._halt()
        return self._end("CANCELED", 0, "NONE", message, interrupted=interrupted)

    def _cancel_message(self) -> str:
        event = self.events.canceled_by
        at = 0.0 if event is None else event.at
        return f"canceled by the mission's cancel event at {at:g} s"

    def _fault(self, code: MissionErrorCode, message: str) -> LoopOutcome:
        self._halt()
        return self._end("FAILED", code, code.name, message)

    def _timed_out(self) -> LoopOutcome:
        running = self._running_leaf()
        self._halt()
        doing = f" while '{running}' was running" if running else ""
        return self._end(
            "FAILED",
            MissionErrorCode.MISSION_TIMEOUT,
            "MISSION_TIMEOUT",
            f"the mission timeout of {self.timeout:g} s of sim time passed{doing}",
        )

    def _failed(self) -> LoopOutcome:
        cause = _failure_cause(self.root)
        where = self._where(cause)
        if isinstance(cause, GoalTaskLeaf) and cause.outcome is not None:
            outcome = cause.outcome
            if outcome.status is TaskStatus.FAILED and outcome.error_code:
                message = f"{cause.name} ({where}): {outcome.error_msg}".strip()
                return self._end("FAILED", outcome.error_code, outcome.error_name, message)
        detail = f": {cause.feedback_message}" if cause.feedback_message else ""
        return self._end(
            "FAILED",
            MissionErrorCode.TREE_FAILED,
            "TREE_FAILED",
            f"the tree failed at '{cause.name}' ({where}){detail}",
        )

    # -- recording ---------------------------------------------------------------------------

    def _where(self, behaviour: py_trees.behaviour.Behaviour) -> str:
        node = self.compiled.nodes.get(behaviour.id)
        if node is None:
            return "?"
        line, column = self.compiled.mission.document.locate(node.type_path)
        return f"line {line}:{column}"

    def _record_state(self, now: float) -> None:
        if now != self._last_state:
            self._last_state = now
            self.trace.add(now, "pose", **self.rig.state())

    def _record_tree(self, now: float) -> None:
        statuses = [behaviour.status for behaviour in self._behaviours]
        if statuses != self._statuses:  # a few times a run: walk the nodes for the changes
            for behaviour, status, before in zip(
                self._behaviours, statuses, self._statuses, strict=True
            ):
                if before is not status:
                    self.trace.add(
                        now,
                        "status",
                        node=behaviour.name,
                        at=self._where(behaviour),
                        status=status.value,
                    )
            self._statuses = statuses
        for index, leaf in enumerate(self._goal_leaves):
            previous, recorded = self._handles[index]
            if previous is not None and previous is not leaf.handle and not recorded:
                self._record_outcome(now, leaf, previous)
                recorded = True
            if leaf.handle is not previous:
                previous, recorded = leaf.handle, False
            if previous is not None and previous.outcome is not None and not recorded:
                self._record_outcome(now, leaf, previous)
                recorded = True
            self._handles[index] = (previous, recorded)
        if now - self._last_feedback >= FEEDBACK_PERIOD - 1e-9:
            self._last_feedback = now
            for leaf in self._goal_leaves:
                handle = leaf.handle
                if leaf.status is Status.RUNNING and handle is not None and handle.feedback:
                    scalars = {
                        key: value
                        for key, value in handle.feedback.items()
                        if isinstance(value, int | float | str | bool)
                    }
                    self.trace.add(now, "feedback", node=leaf.name, feedback=scalars)

    def _record_outcome(self, now: float, leaf: GoalTaskLeaf, handle: TaskHandle) -> None:
        outcome = handle.outcome
        if outcome is None:
            return
        self.trace.add(
            now,
            "outcome",
            node=leaf.name,
            at=self._where(leaf),
            task=handle.name,
            status=outcome.status.value,
            error_code=outcome.error_code,
            error_name=outcome.error_name,
            error_msg=outcome.error_msg,
        )

    def _record_sim(self) -> None:
        """What happened inside the simulation (the collision monitor's state changes)."""
        for stamp, kind, fields in self.rig.sim_records():
            self.trace.add(stamp, kind, **fields)

    def _record_events(self, records: list[dict[str, Any]]) -> None:
        self._record_sim()
        for record in records:
            self.trace.add(self.sim.time, "event", **record)

    # -- progress ----------------------------------------------------------------------------

    def _running_leaf(self) -> str:
        for behaviour in self._behaviours:
            if behaviour.status is Status.RUNNING and not behaviour.children:
                return behaviour.name
        return ""

    def _report(self, now: float) -> None:
        if self.progress is None:
            return
        step = None
        feedback: dict[str, Any] = {}
        for index, leaf in enumerate(self._goal_leaves):
            if leaf.status is Status.RUNNING:
                step = (index + 1, len(self._goal_leaves))
                if leaf.handle is not None:
                    feedback = leaf.handle.feedback
                break
        distance = _number(feedback.get("distance_remaining"))
        eta = _number(feedback.get("estimated_time_remaining"))
        if eta is None and distance is not None:
            speed = abs(float(self.rig.state().get("v", 0.0)))
            eta = distance / speed if speed > 0.02 else None
        waypoint = feedback.get("current_waypoint")
        self.progress.update(
            ProgressSnapshot(
                sim_time=now,
                wall_time=time.perf_counter() - self._wall_start,
                timeout=self.timeout,
                leaf=self._running_leaf(),
                distance_remaining=distance,
                eta=eta,
                step=step,
                waypoint=int(waypoint) + 1 if isinstance(waypoint, int) else None,
            )
        )


def _number(value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value)


def _failure_cause(root: py_trees.behaviour.Behaviour) -> py_trees.behaviour.Behaviour:
    """The deepest node along the chain of FAILURE statuses below the failed ``root``."""
    node = root
    while node.children:
        if isinstance(node, py_trees.composites.Composite):
            current = node.current_child
            if current is not None and current.status is Status.FAILURE:
                node = current
                continue
            failed = [child for child in node.children if child.status is Status.FAILURE]
            if not failed:
                return node
            node = failed[-1]
        elif isinstance(node, py_trees.decorators.Decorator):
            if node.decorated.status is not Status.FAILURE:
                return node
            node = node.decorated
        else:
            return node
    return node
