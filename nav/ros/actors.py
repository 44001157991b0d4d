"""Node code on sim time: each node file's ``main()`` is an *actor*, run one at a time.

User code blocks: ``rclpy.spin(node)`` never returns, ``rate.sleep()`` and ``time.sleep()``
wait, ``lookup_transform`` waits up to a timeout. Under ROS these block a process; here every
node file runs in one process on simulation time, so each actor runs in its own thread but
holds a baton: exactly one thread (an actor or the simulation loop) runs at any moment, and
handing the baton over is the only way to switch. An actor that blocks tells the
:class:`Scheduler` what it waits for (a sim time, a condition such as "a callback is ready",
or both) and gives the baton back; the simulation loop steps the physics to the next moment
something is due and hands the baton to the actors that can go on, in the order they were
created. Nothing depends on the operating system's thread timing, so runs are deterministic.

Threads a node starts (``threading.Thread(target=rclpy.spin, ...)``) become actors too, in
the order they are started, and inherit the starter's context variables (its rclpy context);
``join()`` on them and ``time.sleep`` wait on sim time (see :func:`cooperative_threads`).
Other blocking primitives shared between actors (locks, queues, events) are not coordinated.

When the run is over, each actor still blocked gets a ``KeyboardInterrupt`` at the call that
blocks, as ``Ctrl-C`` ends ``ros2 run``; if it blocks again, :class:`RunEnded` unwinds it.
"""

from __future__ import annotations

import contextvars
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from enum import Enum

from baobab.sim.errors import BaobabError

MAX_WAKES_PER_INSTANT = 100_000
"""How often actors may wake at one sim time before the run is declared stuck."""

Ready = Callable[[], bool]
"""A condition an actor waits for, evaluated by the simulation loop."""


class RunEnded(BaseException):
    """Unwinds an actor that blocks again after the end-of-run interrupt."""


class StuckError(BaobabError):
    """Actors keep waking each other at one sim time, so time cannot advance."""


class ActorState(Enum):
    """Where an actor is in its life."""

    NEW = "new"
    BLOCKED = "blocked"
    RUNNING = "running"
    DONE = "done"


class Actor:
    """One thread of user code (a node file's ``main()``, or a thread it started)."""

    def __init__(self, name: str, argv: list[str], origin: str) -> None:
        self.name = name
        self.argv = argv
        self.origin = origin
        """The node file the actor's code comes from (for messages)."""
        self.state = ActorState.NEW
        self.deadline_ns: int | None = None
        self.ready: Ready | None = None
        self.error: BaseException | None = None
        self.interrupts = 0
        self.canceled = False
        self.thread: threading.Thread | None = None
        self.rclpy_context: object = None
        """The default rclpy context of a node file's actor (set by the runtime)."""
        self.parent: Actor | None = None
        """The actor that started this one's thread, if any."""
        self._go = threading.Semaphore(0)

    def runnable(self, now_ns: int) -> bool:
        """True when the actor can go on at ``now_ns``."""
        if self.state is ActorState.NEW:
            return True
        if self.state is not ActorState.BLOCKED:
            return False
        if self.interrupts:
            return True
        if self.deadline_ns is not None and self.deadline_ns <= now_ns:
            return True
        return self.ready is not None and self.ready()


class Scheduler:
    """Hands the baton between the simulation loop and the actors (module docstring)."""

    def __init__(self, now_ns: Callable[[], int]) -> None:
        self._now_ns = now_ns
        self.actors: list[Actor] = []
        self._back = threading.Semaphore(0)
        self._by_thread: dict[int, Actor] = {}
        self._loop_argv = sys.argv

    # -- creating actors --------------------------------------------------------------------

    def spawn(
        self, target: Callable[[], object], *, name: str, argv: list[str], origin: str
    ) -> Actor:
        """A new actor running ``target`` in a copy of the caller's context; it starts when
        the simulation loop next hands out the baton."""
        actor = Actor(name, argv, origin)
        context = contextvars.copy_context()
        thread = threading.Thread(
            target=self._bootstrap, args=(actor, context, target), name=name, daemon=True
        )
        self._register(actor, thread)
        thread.start()
        return actor

    def adopt(self, thread: threading.Thread) -> Actor:
        """Make a thread started by an actor an actor too (called before it starts)."""
        starter = self.current()
        assert starter is not None  # only called from an actor's thread
        actor = Actor(f"{starter.name}/{thread.name}", starter.argv, starter.origin)
        actor.parent = starter
        context = contextvars.copy_context()
        run = thread.run
        thread.run = lambda: self._bootstrap(actor, context, run)  # type: ignore[method-assign]
        self._register(actor, thread)
        return actor

    def _register(self, actor: Actor, thread: threading.Thread) -> None:
        actor.thread = thread
        self.actors.append(actor)

    def _bootstrap(
        self, actor: Actor, context: contextvars.Context, target: Callable[[], object]
    ) -> None:
        actor._go.acquire()
        ident = threading.get_ident()
        self._by_thread[ident] = actor
        try:
            if not actor.canceled:
                actor.state = ActorState.RUNNING
                context.run(target)
        except (RunEnded, KeyboardInterrupt):
            if not actor.interrupts:
                actor.error = KeyboardInterrupt()
        except BaseException as exc:  # the user's code failed: reported by the runtime
            actor.error = exc
        finally:
            actor.state = ActorState.DONE
            del self._by_thread[ident]  # the system may give the identifier to a new thread
            self._back.release()

    def current(self) -> Actor | None:
        """The actor whose thread calls this, or None (the simulation loop, another thread)."""
        return self._by_thread.get(threading.get_ident())

    # -- blocking (called from an actor's thread) -------------------------------------------

    def block(self, deadline_ns: int | None, ready: Ready | None) -> None:
        """Wait until sim time ``deadline_ns`` or until ``ready()`` holds, whichever first.

        Raises:
            KeyboardInterrupt: the run ended while waiting (the first time).
            RunEnded: the run had ended, and the actor blocked again.
            RuntimeError: called from a thread that is not an actor.
        """
        actor = self.current()
        if actor is None:
            raise RuntimeError("only node code run by the ROS runtime can wait on sim time")
        if actor.interrupts:
            self._raise_interrupt(actor)
        actor.deadline_ns, actor.ready = deadline_ns, ready
        actor.state = ActorState.BLOCKED
        self._back.release()
        actor._go.acquire()
        actor.state = ActorState.RUNNING
        actor.deadline_ns = actor.ready = None
        if actor.interrupts:
            self._raise_interrupt(actor)

    @staticmethod
    def _raise_interrupt(actor: Actor) -> None:
        actor.interrupts += 1
        if actor.interrupts == 2:
            raise KeyboardInterrupt
        raise RunEnded

    # -- the simulation loop's side ---------------------------------------------------------

    def _resume(self, actor: Actor) -> None:
        """Hand ``actor`` the baton and wait until it gives it back."""
        self._loop_argv = sys.argv
        sys.argv = actor.argv
        try:
            actor._go.release()
            self._back.acquire()
        finally:
            sys.argv = self._loop_argv

    def run_ready(self) -> Actor | None:
        """Let every actor that can go on at the current sim time run, until none can.

        Returns:
            The first actor that ended with an error (it stops the run), else None.

        Raises:
            StuckError: actors keep waking each other without sim time advancing.
        """
        now = self._now_ns()
        wakes = 0
        while True:
            actor = next((item for item in self.actors if item.runnable(now)), None)
            if actor is None:
                return None
            self._resume(actor)
            if actor.error is not None and not isinstance(actor.error, KeyboardInterrupt):
                return actor
            wakes += 1
            if wakes > MAX_WAKES_PER_INSTANT:
                names = ", ".join(item.name for item in self.actors if item.runnable(now))
                raise StuckError(
                    f"nodes keep waking each other at t={now / 1e9:.3f} s without sim time "
                    f"advancing ({names}): a callback that publishes what wakes it?"
                )

    def next_deadline(self) -> int | None:
        """The earliest sim time (ns) a blocked actor waits until, or None."""
        deadlines = [
            actor.deadline_ns
            for actor in self.actors
            if actor.state is ActorState.BLOCKED and actor.deadline_ns is not None
        ]
        return min(deadlines) if deadlines else None

    @property
    def live(self) -> bool:
        """True while some actor has not finished."""
        return any(actor.state is not ActorState.DONE for actor in self.actors)

    def end_all(self) -> None:
        """End every actor: interrupt the blocked ones (module docstring), cancel new ones."""
        self._end(list(self.actors))

    def end(self, actor: Actor) -> None:
        """End ``actor`` and the actors its code started, as :meth:`end_all` ends them all."""
        family = [actor]
        for item in self.actors:
            if item.parent in family:
                family.append(item)
        self._end(family)

    def _end(self, actors: list[Actor]) -> None:
        for _ in range(3):
            for actor in actors:
                if actor.state is ActorState.NEW:
                    actor.canceled = True
                    self._resume(actor)
                elif actor.state is ActorState.BLOCKED:
                    actor.interrupts = max(actor.interrupts, 1)
                    self._resume(actor)
            if all(actor.state is ActorState.DONE for actor in actors):
                return


@contextmanager
def cooperative_threads(scheduler: Scheduler) -> Iterator[None]:
    """Inside the block, threads started by actors become actors, and ``time.sleep`` and
    ``Thread.join`` called by an actor wait on sim time (module docstring)."""
    real_sleep, real_start, real_join = time.sleep, threading.Thread.start, threading.Thread.join

    def sleep(seconds: float) -> None:
        if scheduler.current() is None:
            real_sleep(seconds)
            return
        if seconds < 0:
            raise ValueError("sleep length must be non-negative")
        scheduler.block(scheduler._now_ns() + round(seconds * 1e9), None)

    def start(thread: threading.Thread) -> None:
        if scheduler.current() is not None:
            scheduler.adopt(thread)
        real_start(thread)

    def join(thread: threading.Thread, timeout: float | None = None) -> None:
        target = next((actor for actor in scheduler.actors if actor.thread is thread), None)
        if target is None or scheduler.current() is None:
            real_join(thread, timeout)
            return
        deadline = None if timeout is None else scheduler._now_ns() + round(timeout * 1e9)
        scheduler.block(deadline, lambda: target.state is ActorState.DONE)

    time.sleep = sleep  # type: ignore[assignment]
    threading.Thread.start = start  # type: ignore[method-assign,assignment]
    threading.Thread.join = join  # type: ignore[method-assign,assignment]
    try:
        yield
    finally:
        time.sleep = real_sleep
        threading.Thread.start = real_start  # type: ignore[method-assign]
        threading.Thread.join = real_join  # type: ignore[method-assign]
