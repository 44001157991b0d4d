"""Node files inside a mission run: the ``ros_node`` leaf's and ``publish`` events' runtime.

A mission's run loop owns the stepping of its simulation, so here the ROS runtime does not
step: it asks the simulation to call it back at each instant something is due (a one-shot
periodic callback, moved to the next instant every time it fires), and at that instant
publishes the robot's topics and lets node code run, exactly as ``baobab ros run`` does
between physics steps. A node file started by a leaf is a goal-style task
(:class:`~baobab.sim.tasks.TaskHandle`): RUNNING while its code runs, SUCCEEDED when its
``main()`` returns, FAILED when it raises (its traceback goes to standard error), CANCELED
when the leaf is halted (its code gets a ``KeyboardInterrupt``, as at the end of
``ros2 run``, and its nodes are destroyed).
"""

from __future__ import annotations

import sys
from contextlib import ExitStack
from pathlib import Path
from typing import Any

from baobab.nav.navigator_robot import SimulatedArm, SimulatedRobot
from baobab.nav.ros.actors import Actor, ActorState
from baobab.nav.ros.node_files import failure_report, node_file_main, node_file_paths
from baobab.nav.ros.runtime import NodeFailure, RosRuntime
from baobab.nav.ros.sim_topics import ArmTopics, MobileRobotTopics
from baobab.sim.simulation import PeriodicHandle, Simulation
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus

NODE_FAILED = 1
"""The error code of a ``ros_node`` task whose code raised."""

_NEVER = 10**6
"""The period (in physics steps) of the one-shot callback: it is moved before it repeats."""


class MissionNodes:
    """The ROS runtime of one mission run (module docstring).

    Args:
        sim: the mission's simulation.
        mobile: the mobile robot to put on topics, or None.
        arm: the arm to put on topics, or None.
    """

    def __init__(
        self,
        sim: Simulation,
        *,
        mobile: SimulatedRobot | None = None,
        arm: SimulatedArm | None = None,
    ) -> None:
        self.sim = sim
        self.runtime = RosRuntime(sim)
        if mobile is not None:
            MobileRobotTopics(self.runtime, mobile)
        if arm is not None:
            ArmTopics(self.runtime, arm)
        self._stack: ExitStack | None = None
        self._wake: PeriodicHandle | None = None
        self._tasks: dict[Actor, TaskHandle] = {}
        self._paths: list[Path] = []

    def _activate(self) -> None:
        if self._stack is None:
            self._stack = ExitStack()
            self._stack.enter_context(self.runtime.active())
            self._schedule(self.sim.step_count)

    def _schedule(self, step: int) -> None:
        if self._wake is not None:
            self._wake.cancel()
        self._wake = self.sim.every(
            self.sim.physics_dt * _NEVER,
            self._instant,
            name="ros nodes",
            first_call=step * self.sim.physics_dt,
        )

    def _instant(self, _now: float) -> None:
        failure = self.runtime.serve()
        if failure is not None:
            self._failed(failure)
        self._settle()
        dt_ns = round(self.sim.physics_dt * 1e9)
        next_ns = self.runtime.next_instant(self.runtime.now_ns() + _NEVER * dt_ns)
        self._schedule(-(-next_ns // dt_ns))

    def _settle(self) -> None:
        for actor, handle in list(self._tasks.items()):
            if actor.state is ActorState.DONE and handle.outcome is None:
                handle.finish(TaskOutcome(TaskStatus.SUCCEEDED))
                del self._tasks[actor]

    def _failed(self, failure: NodeFailure) -> None:
        print(
            failure_report(failure.actor.origin, list(failure.node_names), failure.error),
            file=sys.stderr,
        )
        root = failure.actor
        while root.parent is not None:
            root = root.parent
        handle = self._tasks.pop(root, None)
        if handle is not None:
            message = f"{Path(root.origin).name}: {type(failure.error).__name__}: {failure.error}"
            handle.finish(TaskOutcome(TaskStatus.FAILED, NODE_FAILED, message, "NODE_FAILED"))

    def start_node(self, path: Path, argv: list[str]) -> TaskHandle:
        """Run the node file at ``path`` with ``argv`` from the next instant on.

        Raises:
            ScriptError: the file cannot be read or does not compile.
        """
        main = node_file_main(path)
        self._activate()
        if path not in self._paths:
            assert self._stack is not None
            self._stack.enter_context(node_file_paths([path]))
            self._paths.append(path)
        actor = self.runtime.start(main, name=path.stem, argv=[str(path), *argv], origin=str(path))
        handle = TaskHandle(f"ros_node {path.name}", lambda _: self._cancel(actor))
        self._tasks[actor] = handle
        self._schedule(self.sim.step_count)
        return handle

    def _cancel(self, actor: Actor) -> None:
        self.runtime.stop(actor)
        handle = self._tasks.pop(actor, None)
        if handle is not None:
            handle.finish(TaskOutcome(TaskStatus.CANCELED, 0, "the node was stopped"))

    def publish_at_once(self, topic: str, message: Any) -> None:
        """Publish ``message`` on ``topic`` now (a mission's ``publish`` event)."""
        self._activate()
        self.runtime.publish_at(self.runtime.now_ns() / 1e9, topic, message)
        self._schedule(self.sim.step_count)

    def close(self) -> None:
        """End every node and stop serving ROS modules (idempotent)."""
        if self._wake is not None:
            self._wake.cancel()
            self._wake = None
        if self._stack is not None:
            self.runtime.scheduler.end_all()
            self.runtime.shut_down_nodes()
            self._stack.close()
            self._stack = None
