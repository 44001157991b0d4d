"""``baobab run`` through the run server (:mod:`.run_server`): hand over, forward, wait.

:func:`run_in_server` passes this process's command line, working folder, umask, resource
limits, environment and standard streams to the server, which runs the command in a fork of
its loaded state; this process forwards its SIGINT, SIGTERM and SIGHUP to that worker and
leaves with the worker's exit code, so a caller (a shell, a CI script, ``subprocess``) sees
``baobab run`` as one process, as before. Where there is no server, or it declines, the
command runs here as it always has, and :func:`start_server` starts one for the next run.

Standard library only, and little of it: this runs before anything else loads.
"""

from __future__ import annotations

import contextlib
import os
import resource
import signal
import socket
import sys
from collections.abc import Sequence
from pathlib import Path

from baobab.missions.cli.interrupts import HANDLED, exit_code_for, exit_on_signals
from baobab.missions.cli.run_server_protocol import (
    LIMITS,
    Channel,
    ServedCommand,
    server_command,
    server_enabled,
    socket_path,
)
from baobab.missions.run.exit_codes import EXIT_NOT_INTENDED

IN_WORKER = False
"""True in a run server's worker, which runs its command itself (it never asks a server)."""


def run_in_server(arguments: Sequence[str]) -> int | None:
    """Run ``baobab <arguments>`` in the run server; its exit code, or None to run it here."""
    path = _server_path()
    connection = None if path is None else _connect(path)
    if connection is None:
        return None
    channel = Channel(connection)
    forwarding = _Forwarding()
    for signum in HANDLED:
        signal.signal(signum, forwarding.handle)
    try:
        channel.send(_this_command(arguments), fds=(0, 1, 2))
        while True:
            (kind, value), _fds = channel.receive()
            if kind == "started":
                forwarding.to(value)
            elif kind == "ended":
                return int(value)
            elif kind == "killed":  # the worker could not say it (SIGKILL, the OOM killer)
                name = signal.Signals(value).name
                print(f"baobab run: the run's process was killed by {name}", file=sys.stderr)
            else:  # declined: run here, unless a signal came meanwhile
                return forwarding.exit_code()
    except (EOFError, OSError) as exc:
        if forwarding.worker is None:
            return forwarding.exit_code()
        print(f"baobab run: the run server stopped during the run ({exc})", file=sys.stderr)
        return EXIT_NOT_INTENDED
    finally:
        connection.close()
        exit_on_signals()


class _Forwarding:
    """Signals that come before the worker's pid is known wait, then go to the worker."""

    def __init__(self) -> None:
        self.worker: int | None = None
        self.pending: list[int] = []

    def handle(self, signum: int, _frame: object) -> None:
        if self.worker is None:
            self.pending.append(signum)
        else:
            with contextlib.suppress(ProcessLookupError):
                os.kill(self.worker, signum)

    def to(self, worker: int) -> None:
        self.worker = worker
        for signum in self.pending:
            with contextlib.suppress(ProcessLookupError):
                os.kill(worker, signum)

    def exit_code(self) -> int | None:
        """``128 + signal`` for a signal that came before any worker started, else None."""
        return exit_code_for(self.pending[0]) if self.pending else None


def _server_path() -> Path | None:
    """The socket of this installation's run server; None where this process uses none."""
    if IN_WORKER or not server_enabled(os.environ) or not hasattr(os, "pidfd_open"):
        return None
    return socket_path(os.environ)


def _connect(path: Path) -> socket.socket | None:
    connection = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    try:
        connection.connect(str(path))
    except OSError:
        connection.close()
        return None
    return connection


def _this_command(arguments: Sequence[str]) -> ServedCommand:
    umask = os.umask(0)
    os.umask(umask)
    streams = [
        (getattr(stream, "encoding", "utf-8"), getattr(stream, "errors", None) or "strict")
        for stream in (sys.stdin, sys.stdout, sys.stderr)
    ]
    limits = {name: resource.getrlimit(getattr(resource, name)) for name in LIMITS}
    return ServedCommand(
        argv=[sys.argv[0], *arguments],
        cwd=os.getcwd(),
        umask=umask,
        environ=dict(os.environ),
        streams=streams,
        limits=limits,
    )


def start_server() -> None:
    """Start this installation's run server in the background, unless one answers already.

    It logs what it serves and declines in ``run-<key>.log`` beside its socket.
    """
    path = _server_path()
    if path is None:
        return
    connection = _connect(path)
    if connection is not None:
        connection.close()
        return
    import subprocess

    with contextlib.suppress(OSError), path.with_suffix(".log").open("wb") as log:
        subprocess.Popen(
            server_command(path),
            cwd="/",  # see server_command
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=log,
            start_new_session=True,
        )
