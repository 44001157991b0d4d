"""A job in a forked child process, with its messages and its result sent back through a pipe.

``baobab run`` simulates in a child and writes the run folder in the parent, so the simulation
stack (MuJoCo, numba's LLVM and the compiled kernels) and the plotting stack (matplotlib) are
never in one process: neither process holds both, and a crash in native code (MuJoCo, a
kernel) ends the run with a message naming the signal. The parent loads its plotting stack
while the child simulates (``meanwhile``), on the other core.

The child is forked after the mission is loaded, so it starts from the parent's state with no
second start-up (and with the parent's signal handlers). It runs in a process group of its
own: the parent forwards each SIGINT, SIGTERM and SIGHUP it gets (the terminal's Ctrl-C reaches
only the parent), so the child handles them exactly as one process would. The signals are
blocked around the fork, so none arrives in the parent before it can forward it.

Forking is safe only from a process with one thread: a lock another thread holds at the fork
stays locked in the child for ever (seen here: a test process whose earlier runs had started
Mesa's EGL threads hung the child in ``mujoco.Renderer``). :func:`fork_is_safe` says whether
this process qualifies; ``baobab run`` runs in its own process when it does (the ``baobab``
command, which loads no NumPy before the fork) and in the calling process when it does not.
"""

from __future__ import annotations

import contextlib
import functools
import os
import pickle
import signal
import sys
import threading
import traceback
from collections.abc import Callable
from multiprocessing.connection import Connection, Pipe
from typing import Any, NoReturn, TypeVar

from baobab.sim.errors import BaobabError, SourceError

T = TypeVar("T")
P = TypeVar("P")
Send = Callable[[Any], None]

_MESSAGE, _RETURN, _RAISE = "message", "return", "raise"


class ChildProcessDiedError(BaobabError):
    """The child process ended without sending its result (killed, or a crash in native code)."""


def fork_is_safe() -> bool:
    """Whether this process can fork a child safely: Linux, and one thread (native ones too)."""
    if not hasattr(os, "fork"):
        return False
    try:
        return len(os.listdir("/proc/self/task")) == 1
    except OSError:  # no procfs (macOS): forking after system frameworks start is not safe
        return False


FORWARDED = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
"""The signals the parent passes on to the child."""


def run_in_child(
    job: Callable[[Send], T],
    on_message: Send,
    on_signal: Callable[[int], None] | None = None,
    meanwhile: Callable[[], object] | None = None,
) -> T:
    """Run ``job(send)`` in a forked child and return what it returns.

    Args:
        job: called in the child with ``send``, which passes a picklable message to
            ``on_message`` in the parent; what it returns (or raises) must be picklable.
        on_message: called in the parent with each message, in order.
        on_signal: told (in the parent) of each :data:`FORWARDED` signal it passes on.
        meanwhile: called in the parent right after the fork, while the child works (the
            child's messages wait in the pipe until it returns): work the parent needs
            afterwards, done on another core.

    Raises:
        BaseException: what ``job`` raised (KeyboardInterrupt and baobab's errors keep their
            type; an exception that cannot be pickled arrives as a RuntimeError with the
            child's traceback).
        ChildProcessDiedError: the child ended without a result.

    Call it only where :func:`fork_is_safe` (or the job touches nothing other threads lock).
    """
    forwarding = threading.current_thread() is threading.main_thread()

    def in_child(reader: Connection, writer: Connection) -> NoReturn:
        if forwarding:
            signal.pthread_sigmask(signal.SIG_UNBLOCK, FORWARDED)
        _child(job, reader, writer, own_group=forwarding)

    child, reader = _fork(in_child, forwarding)
    return _supervise(child, reader, on_message, on_signal, meanwhile, forwarding)


class StartedChild:
    """A child forked before its job is known: it prepares (imports) while this process works.

    :func:`start_child` forks it; :meth:`run` sends it a job, :meth:`discard` ends it unused
    (or once done). Signals to forward stay blocked in the child until its job handles them:
    the job calls :func:`handle_forwarded_signals` once it has installed its handlers.
    """

    def __init__(self, child: _Child, reader: Connection, jobs: Connection) -> None:
        self._child = child
        self._reader = reader
        self._jobs = jobs
        self._used = False

    def run(
        self,
        job: Callable[[P, Send], T],
        payload: P,
        on_message: Send,
        on_signal: Callable[[int], None] | None = None,
        meanwhile: Callable[[], object] | None = None,
        earlier: Callable[[], int | None] = lambda: None,
    ) -> T:
        """Run ``job(payload, send)`` in the child, as :func:`run_in_child` runs its job.

        ``job`` (a module-level function) and ``payload`` travel pickled. ``earlier`` says
        which signal this process got before the child was told to run, if any: the child
        gets it too, once its job handles signals.
        """
        if self._used:
            raise RuntimeError("a started child runs one job")
        self._used = True
        signal.pthread_sigmask(signal.SIG_BLOCK, FORWARDED)  # until they are forwarded
        try:
            self._jobs.send((job, payload))
        except OSError:
            pass  # the child died while preparing: _supervise reports how
        finally:
            self._jobs.close()
        return _supervise(
            self._child, self._reader, on_message, on_signal, meanwhile, True, earlier()
        )

    def discard(self) -> None:
        """End the child if it never ran a job, and reap it (idempotent)."""
        if not self._used:
            self._used = True
            self._jobs.close()
            self._reader.close()
            self._child.kill()
            self._child.wait()


def start_child(prepare: Callable[[], object]) -> StartedChild:
    """Fork a child that runs ``prepare()`` (say, imports) and then waits for a job.

    Call it only from the main thread, where :func:`fork_is_safe`. A ``prepare`` that raises
    is ignored: the job meets the same problem and reports it. The child leaves quietly if
    this process goes away without sending a job.
    """
    jobs_reader, jobs_writer = Pipe(duplex=False)

    def in_child(reader: Connection, writer: Connection) -> NoReturn:
        jobs_writer.close()
        try:
            with contextlib.suppress(Exception):
                prepare()
            job, payload = jobs_reader.recv()
        except BaseException:  # no job: the parent is gone or changed its mind
            os._exit(0)
        jobs_reader.close()
        _child(functools.partial(job, payload), reader, writer, own_group=True)

    child, reader = _fork(in_child, True)
    jobs_reader.close()
    signal.pthread_sigmask(signal.SIG_UNBLOCK, FORWARDED)  # this process's own, until run()
    return StartedChild(child, reader, jobs_writer)


def handle_forwarded_signals() -> None:
    """In a started child's job, once it handles :data:`FORWARDED`: let them arrive."""
    signal.pthread_sigmask(signal.SIG_UNBLOCK, FORWARDED)


def _fork(
    in_child: Callable[[Connection, Connection], NoReturn], forwarding: bool
) -> tuple[_Child, Connection]:
    """Fork with :data:`FORWARDED` blocked; they stay blocked here until _supervise forwards
    them (or the caller unblocks them)."""
    reader, writer = Pipe(duplex=False)
    for stream in (sys.stdout, sys.stderr):
        stream.flush()
    if forwarding:
        signal.pthread_sigmask(signal.SIG_BLOCK, FORWARDED)
    try:
        pid = os.fork()
    except OSError:
        signal.pthread_sigmask(signal.SIG_UNBLOCK, FORWARDED)
        raise
    if pid == 0:
        in_child(reader, writer)
    writer.close()
    child = _Child(pid)
    if forwarding:
        _join_own_group(pid)
    return child, reader


def _supervise(
    child: _Child,
    reader: Connection,
    on_message: Send,
    on_signal: Callable[[int], None] | None,
    meanwhile: Callable[[], object] | None,
    forwarding: bool,
    earlier: int | None = None,
) -> Any:
    """Forward signals to ``child`` (blocked until now: none is lost, none counted twice),
    pass on its messages, return its result; reap it. ``earlier``: a signal to pass on now."""
    previous = {}
    if forwarding:

        def forward(signum: int, _frame: object) -> None:
            child.interrupt(signum)
            if on_signal is not None:
                on_signal(signum)

        previous = {signum: signal.signal(signum, forward) for signum in FORWARDED}
        if earlier is not None:
            child.interrupt(earlier)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, FORWARDED)
    finished = False
    try:
        if meanwhile is not None:
            meanwhile()
        result = _receive(reader, on_message, child)
        finished = True
        return result
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        reader.close()
        if not finished:
            child.kill()
        child.wait()


class _Child:
    """The forked child, reaped exactly once (a reaped pid may be reused by another process)."""

    def __init__(self, pid: int) -> None:
        self.pid = pid
        self.status: int | None = None

    def interrupt(self, signum: int = signal.SIGINT) -> None:
        """Forward signal ``signum`` (a SIGINT by default)."""
        if self.status is None:
            os.kill(self.pid, signum)

    def wait(self) -> int:
        """The child's exit status, once it has ended."""
        if self.status is None:
            self.status = os.waitpid(self.pid, 0)[1]
        return self.status

    def kill(self) -> None:
        """End the child at once (the parent is leaving early); not yet reaped, it is ours."""
        if self.status is None:
            os.kill(self.pid, signal.SIGKILL)

    def death(self) -> str:
        """How the child ended without a result, for people."""
        status = self.wait()
        if os.WIFSIGNALED(status):
            number = os.WTERMSIG(status)
            return f"the run's process was ended by signal {number} ({signal.Signals(number).name})"
        return f"the run's process exited with status {os.WEXITSTATUS(status)} without a result"


def _child(
    job: Callable[[Send], Any], reader: Connection, writer: Connection, *, own_group: bool
) -> NoReturn:
    reader.close()
    if own_group:
        _join_own_group(0)
    try:
        try:
            value = job(lambda message: writer.send((_MESSAGE, message)))
            writer.send((_RETURN, value))
        except BaseException as exc:  # every outcome goes to the parent
            writer.send((_RAISE, _portable(exc)))
    except BaseException:  # the parent is gone: nobody to tell
        pass
    finally:
        for stream in (sys.stdout, sys.stderr):  # os._exit skips the interpreter's last flush
            with contextlib.suppress(Exception):
                stream.flush()
        os._exit(0)


def _receive(reader: Connection, on_message: Send, child: _Child) -> Any:
    while True:
        try:
            kind, payload = reader.recv()
        except EOFError:
            raise ChildProcessDiedError(child.death()) from None
        if kind == _MESSAGE:
            on_message(payload)
        elif kind == _RETURN:
            return payload
        else:
            raise payload


def _portable(exc: BaseException) -> BaseException:
    """``exc`` if it survives pickling, else the nearest exception that does."""
    try:
        pickle.loads(pickle.dumps(exc))
        return exc
    except Exception:  # any pickling failure
        pass
    if isinstance(exc, SourceError):
        return SourceError(exc.path, exc.line, exc.column, exc.message)
    if isinstance(exc, BaobabError):
        return BaobabError(str(exc))
    text = "".join(traceback.format_exception(exc))
    return RuntimeError(f"in the run's process:\n{text}")


def _join_own_group(pid: int) -> None:
    """Put the child in a process group of its own (called on both sides to close the race)."""
    with contextlib.suppress(OSError):  # done by the other side already, or the child ended
        os.setpgid(pid, pid if pid else 0)
