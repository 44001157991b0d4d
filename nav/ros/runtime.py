"""The ROS runtime: rclpy nodes running in one process, on simulation time, deterministically.

A :class:`RosRuntime` owns the run's graph (:mod:`~baobab.nav.ros.graph`), the scheduler of
node code (:mod:`~baobab.nav.ros.actors`) and, when given one, the :class:`Simulation`. Its
loop repeats:

1. publish what the simulation's topics have due (``/odom``, ``/tf``, ``/scan``, ...) and
   the timed events (an injected message, a key press);
2. let every node actor that can go on run until each waits again: executors run the timers
   that are due and the subscriptions that have messages, in rclpy's order;
3. step the physics to the next instant something is due: a timer, a sim topic, an event, a
   sleeping actor's deadline, or the end of the run.

Sim time never waits for the wall clock, so a run goes as fast as it computes; the same node
files, world and seed give the same messages at the same sim times.
"""

from __future__ import annotations

import hashlib
import heapq
import itertools
import sys
from collections.abc import Callable, Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from baobab.nav.ros import ros_shims, waiting
from baobab.nav.ros.actors import Actor, Scheduler, cooperative_threads
from baobab.nav.ros.graph import Graph
from baobab.nav.ros.pynput.keyboard import VirtualKeyboard, use_keyboard
from baobab.nav.ros.qos import QoSProfile
from baobab.nav.rosmsg import to_plain
from baobab.nav.rostime import S_TO_NS, set_sim_time_source

if TYPE_CHECKING:
    from baobab.sim.simulation import Simulation

VIRTUAL_STEP_NS = 1_000_000
"""Time resolution without a simulation (ns): sim time then moves in 1 ms steps."""


@dataclass
class SimSource:
    """A topic the simulation publishes every ``period_ns``: ``build(now_ns)`` makes the message
    (or None to skip); it is built only while the topic has subscribers or taps."""

    topic: str
    period_ns: int
    next_ns: int
    build: Callable[[int], Any]
    publisher: Any


@dataclass(frozen=True)
class NodeFailure:
    """An actor whose code raised: which, the exception, and the nodes its code had made."""

    actor: Actor
    error: BaseException
    node_names: tuple[str, ...] = ()


@dataclass
class RunEnd:
    """How a run ended: its sim time (s) and the node failures (empty when it went well)."""

    sim_time: float
    failures: list[NodeFailure] = field(default_factory=list)


class _SimEndpoint:
    """A publisher or subscription of the simulation itself (not of a node)."""

    def __init__(self, topic_name: str, msg_type: type, qos_profile: QoSProfile) -> None:
        self.topic_name = topic_name
        self.msg_type = msg_type
        self.qos_profile = qos_profile
        self.callback: Callable[[Any], None] = lambda message: None

    def receive(self, message: Any) -> None:
        self.callback(message)

    def warn_incompatible(self, policy: str) -> None:
        print(
            f"[WARN] [{waiting_time()}] [baobab_sim]: a publisher on '{self.topic_name}' offers "
            f"incompatible QoS ({policy}): the simulation does not receive it",
            file=sys.stderr,
        )


def waiting_time() -> str:
    from baobab.nav.rostime import sim_time_ns

    seconds, nanoseconds = divmod(sim_time_ns(), S_TO_NS)
    return f"{seconds}.{nanoseconds:09d}"


class RosRuntime:
    """Runs node code against a simulation (module docstring).

    Args:
        sim: the simulation to step; None runs nodes on a virtual clock alone.
    """

    def __init__(self, sim: Simulation | None = None) -> None:
        self.sim = sim
        self.graph = Graph()
        self.scheduler = Scheduler(self.now_ns)
        self._step_ns = VIRTUAL_STEP_NS if sim is None else round(sim.physics_dt * S_TO_NS)
        self._virtual_ns = 0
        self._sources: list[SimSource] = []
        self._events: list[tuple[int, int, Callable[[], None]]] = []
        self._order = itertools.count()
        self._contexts: list[Any] = []
        self.keyboard = VirtualKeyboard()
        """The keyboard ``pynput`` listeners of node code hear (:meth:`VirtualKeyboard.press`)."""
        self._digest = hashlib.sha256()
        self.graph.tap(None, self._trace)

    # -- time -------------------------------------------------------------------------------

    def now_ns(self) -> int:
        """The current sim time (ns)."""
        if self.sim is None:
            return self._virtual_ns
        return self.sim.step_count * self._step_ns

    def _advance_to(self, time_ns: int) -> None:
        step = -(-time_ns // self._step_ns)
        if self.sim is None:
            self._virtual_ns = max(self._virtual_ns, step * self._step_ns)
        else:
            self.sim.step_to(step)

    # -- the simulation's side --------------------------------------------------------------

    def advertise(self, topic: str, msg_type: type, qos: QoSProfile) -> _SimEndpoint:
        """A publisher of the simulation on ``topic``."""
        endpoint = _SimEndpoint(topic, msg_type, qos)
        self.graph.add_publisher(endpoint)
        return endpoint

    def subscribe(
        self, topic: str, msg_type: type, qos: QoSProfile, callback: Callable[[Any], None]
    ) -> None:
        """Handle each message published on ``topic`` at once (what the simulation takes in)."""
        endpoint = _SimEndpoint(topic, msg_type, qos)
        endpoint.callback = callback
        self.graph.add_subscription(endpoint)

    def add_source(
        self,
        topic: str,
        msg_type: type,
        qos: QoSProfile,
        rate_hz: float,
        build: Callable[[int], Any],
        *,
        phase_ns: int = 0,
    ) -> None:
        """Publish ``build(now_ns)`` on ``topic`` at ``rate_hz``, from now + ``phase_ns``."""
        publisher = self.advertise(topic, msg_type, qos)
        period = round(S_TO_NS / rate_hz)
        self._sources.append(SimSource(topic, period, self.now_ns() + phase_ns, build, publisher))

    def at(self, time_s: float, action: Callable[[], None]) -> None:
        """Run ``action()`` (in the loop, before node code) once sim time reaches ``time_s``."""
        heapq.heappush(self._events, (round(time_s * S_TO_NS), next(self._order), action))

    def publish_at(
        self, time_s: float, topic: str, message: Any, qos: QoSProfile | None = None
    ) -> None:
        """Publish ``message`` on ``topic`` once sim time reaches ``time_s`` (an injected
        message, as ``ros2 topic pub --once`` sends one)."""
        publisher = self.advertise(topic, type(message), qos or QoSProfile(depth=10))
        self.at(time_s, lambda: self.graph.publish(publisher, message))

    def node_names(self, actor: Actor) -> list[str]:
        """The names of the nodes ``actor``'s code created (in its rclpy context)."""
        context = getattr(actor, "rclpy_context", None)
        return [] if context is None else context.node_names()

    def publish(self, publisher: Any, message: Any) -> None:
        """Publish ``message`` from the simulation's ``publisher`` (it is not copied)."""
        self.graph.publish(publisher, message, fresh=True)

    def _publish_due(self, now: int) -> None:
        for source in self._sources:
            if source.next_ns > now:
                continue
            if self.graph.has_receivers(source.topic):
                message = source.build(now)
                if message is not None:
                    self.graph.publish(source.publisher, message, fresh=True)
            missed = (now - source.next_ns) // source.period_ns + 1
            source.next_ns += missed * source.period_ns
        while self._events and self._events[0][0] <= now:
            _, _, action = heapq.heappop(self._events)
            action()

    def _next_instant(self, now: int, end: int) -> int:
        candidates = [end]
        candidates.extend(
            source.next_ns
            for source in self._sources
            if source.next_ns > now and self.graph.has_receivers(source.topic)
        )
        candidates.extend(
            due for timer in self.graph.timers if (due := timer.next_call_ns) is not None
        )
        if self._events:
            candidates.append(self._events[0][0])
        deadline = self.scheduler.next_deadline()
        if deadline is not None:
            candidates.append(deadline)
        later = [time for time in candidates if time > now]
        return min(later) if later else now + self._step_ns

    def _trace(self, topic: str, message: Any) -> None:
        self._digest.update(f"{self.now_ns()} {topic} {to_plain(message)}\n".encode())

    @property
    def trace_digest(self) -> str:
        """sha256 over every message published so far on a topic something reads (with its sim
        time and topic): the same node files, world and seed give the same digest."""
        return self._digest.hexdigest()

    # -- node code --------------------------------------------------------------------------

    @contextmanager
    def active(self) -> Iterator[RosRuntime]:
        """Serve the ROS modules and make this the running runtime inside the block."""
        with ExitStack() as stack:
            stack.enter_context(ros_shims())
            stack.enter_context(cooperative_threads(self.scheduler))
            set_sim_time_source(lambda: self.now_ns() / S_TO_NS)
            waiting.set_run(self.scheduler, self.graph)
            use_keyboard(self.keyboard)
            stack.callback(use_keyboard, None)
            stack.callback(waiting.set_run, None, None)
            stack.callback(set_sim_time_source, None)
            yield self

    def start(
        self, main: Callable[[], object], *, name: str, argv: list[str], origin: str
    ) -> Actor:
        """Run ``main()`` as node code with its own default rclpy context (call inside
        :meth:`active`); it starts when the run does."""
        from baobab.nav.ros.rclpy.context import set_fresh_default_context

        def body() -> None:
            context = set_fresh_default_context()
            self._contexts.append(context)
            actor = self.scheduler.current()
            if actor is not None:
                actor.rclpy_context = context
            main()

        return self.scheduler.spawn(body, name=name, argv=argv, origin=origin)

    def serve(self) -> NodeFailure | None:
        """One instant: publish what is due, then let node code that can go on run.

        Returns:
            The failure of node code that raised, if any (the actor has ended).
        """
        self._publish_due(self.now_ns())
        failed = self.scheduler.run_ready()
        if failed is None or failed.error is None:
            return None
        return self._failure(failed, failed.error)

    def next_instant(self, end_ns: int) -> int:
        """The sim time (ns) of the next instant something is due, at most ``end_ns``."""
        return self._next_instant(self.now_ns(), end_ns)

    def run(self, duration: float) -> RunEnd:
        """Run for ``duration`` seconds of sim time, or until no node code is left, or until
        node code fails (call inside :meth:`active`).

        Returns:
            The end time and the failures; a failure stops the run at once.
        """
        end = self.now_ns() + round(duration * S_TO_NS)
        failures: list[NodeFailure] = []
        try:
            while True:
                failure = self.serve()
                if failure is not None:
                    failures.append(failure)
                    break
                if self.now_ns() >= end or not self.scheduler.live:
                    break
                self._advance_to(self.next_instant(end))
        finally:
            self.scheduler.end_all()
            failures.extend(
                self._failure(actor, actor.error)
                for actor in self.scheduler.actors
                if actor.error is not None
                and not isinstance(actor.error, KeyboardInterrupt)
                and all(failure.actor is not actor for failure in failures)
            )
            self.shut_down_nodes()
        return RunEnd(self.now_ns() / S_TO_NS, failures)

    def stop(self, actor: Actor) -> None:
        """End one actor and the threads it started, and destroy the nodes its code made."""
        self.scheduler.end(actor)
        context = getattr(actor, "rclpy_context", None)
        if context is not None:
            context.try_shutdown()

    def _failure(self, actor: Actor, error: BaseException) -> NodeFailure:
        return NodeFailure(actor, error, tuple(self.node_names(actor)))

    def shut_down_nodes(self) -> None:
        """Destroy what node code left: the nodes of each node file's context."""
        for context in self._contexts:
            context.try_shutdown()
