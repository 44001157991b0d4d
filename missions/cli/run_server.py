"""The run server: what every ``baobab run`` loads, loaded once, and a fork of it per run.

Most of a short run's wall time is loading (MuJoCo, numba and the compiled control
dispatcher, pydantic and the mission language, py_trees, matplotlib: about 1.5 s of CPU on
this project's 2-core machine), and none of it depends on the mission. The first ``baobab
run`` on a machine runs in its own processes as always and, once done, starts this server in
the background; later runs hand it their command line (:mod:`.run_client`) and a fork of the
server runs ``baobab`` in their place, from the loaded state:

- the server process only loads and forks: it never runs a mission, so every run starts
  from the same state, as a fresh process would (its digests are the same);
- per connection a *handler* process forks the *worker*, tells the caller the worker's pid
  (the caller forwards its SIGINT, SIGTERM and SIGHUP there), waits for it and reports its
  exit code; a caller that goes away ends its run as a closing terminal would (SIGHUP);
- the worker takes the caller's standard streams (passed over the socket), working folder,
  umask, resource limits, environment and arguments, then runs the ``baobab`` command line
  exactly as the console script does (so ``run`` still simulates in a child process of its
  own and writes the run folder in the worker).

The server declines a request (the caller then runs the command itself) when a module it
loaded has changed on disk since (it then exits, and the caller starts a fresh one), or when
the caller's resource limits are above its own. It exits after :func:`idle_seconds` without a
request. It loads NumPy with one BLAS thread (``OPENBLAS_NUM_THREADS=1`` unless set): a fork
is safe only from a process with one thread (:mod:`baobab.missions.run.child_process`); if
threads run after loading all the same, it declines every request.

    python -P -m baobab.missions.cli.run_server SOCKET     # as run_client starts it (in /)
"""

from __future__ import annotations

import contextlib
import fcntl
import io
import os
import resource
import select
import signal
import socket
import struct
import sys
import time
from pathlib import Path
from typing import NoReturn

from baobab.missions.cli.interrupts import exit_code_for, exit_on_signals
from baobab.missions.cli.run_server_protocol import Channel, ServedCommand, idle_seconds
from baobab.missions.run.child_process import fork_is_safe

Stamps = dict[str, tuple[int, int] | None]
"""A file's modification time (ns) and size, by path; None for a file that is gone."""


def main(argv: list[str] | None = None) -> int:
    """Serve on the socket named by the first argument until idle; 0 once done."""
    path = Path((sys.argv[1:] if argv is None else argv)[0])
    lock = _lock(path.with_suffix(".lock"))
    if lock is None:
        return 0  # another server for this socket is starting or serving
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    preload()
    for quiet in (signal.SIGINT, signal.SIGHUP):  # after preload: loading entry sets its own
        signal.signal(quiet, signal.SIG_IGN)
    fingerprint = code_stamps()
    if fork_is_safe():
        unsafe = None
    else:
        fingerprint = {}  # see _declined
        unsafe = "threads run in the server: it cannot fork safely"
    with contextlib.suppress(FileNotFoundError):
        path.unlink()  # a server that died left it; the lock says none serves it now
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(str(path))
    listener.listen(16)
    identity = path.stat().st_ino
    signal.signal(signal.SIGCHLD, signal.SIG_IGN)  # handlers are reaped as they end
    signal.signal(signal.SIGTERM, _leave)
    _log(
        f"serving {path} as pid {os.getpid()}"
        + (f"; declining every run: {unsafe}" if unsafe else "")
    )
    try:
        serve(listener, lock, fingerprint, unsafe, idle_seconds(os.environ))
    finally:
        with contextlib.suppress(OSError):
            if path.stat().st_ino == identity:
                path.unlink()
    return 0


def _leave(_signum: int, _frame: object) -> None:
    raise SystemExit(0)  # through main's finally: the socket goes


def _lock(path: Path) -> int | None:
    descriptor = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
    try:
        fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(descriptor)
        return None
    return descriptor


def preload() -> None:
    """Load what both processes of a run load before they know their mission."""
    from baobab.missions.cli.startup import loading_modules, skip_pydantic_plugin_discovery

    skip_pydantic_plugin_discovery()
    with loading_modules():
        from baobab.missions.cli import command_line, entry  # noqa: F401  (loaded, for the worker)
        from baobab.missions.cli.run_process import prepare_run_process
        from baobab.missions.run.plotting import load_plotting

        command_line.build_parser("run")
        prepare_run_process()
        load_plotting()


def code_stamps() -> Stamps:
    """The stamps of the loaded modules' files: baobab's, and each top-level package's."""
    paths = set()
    for name, module in list(sys.modules.items()):
        path = getattr(module, "__file__", None)
        if path and (name.startswith("baobab") or "." not in name):
            paths.add(path)
    return {path: _stamp(path) for path in paths}


def _stamp(path: str) -> tuple[int, int] | None:
    try:
        status = os.stat(path)
    except OSError:
        return None
    return status.st_mtime_ns, status.st_size


def serve(
    listener: socket.socket, lock: int, fingerprint: Stamps, unsafe: str | None, idle: float
) -> None:
    """Accept callers until ``idle`` seconds pass without one; a handler process for each."""
    server = os.getpid()
    listener.settimeout(idle)
    while True:
        try:
            connection, _address = listener.accept()
        except TimeoutError:
            return
        if not _same_user(connection) or os.fork():
            connection.close()
            continue
        try:  # the handler: whatever happens, it never returns into this loop
            listener.close()
            os.close(lock)
            connection.setblocking(True)
            handle(Channel(connection), fingerprint, unsafe, server)
        finally:
            os._exit(1)


def _same_user(connection: socket.socket) -> bool:
    credentials = connection.getsockopt(socket.SOL_SOCKET, socket.SO_PEERCRED, 12)
    _pid, uid, _gid = struct.unpack("3i", credentials)
    return uid == os.getuid()


def handle(channel: Channel, fingerprint: Stamps, unsafe: str | None, server: int) -> NoReturn:
    """One caller, in a process of its own: check, fork the worker, wait, report."""
    signal.signal(signal.SIGCHLD, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    try:
        command, fds = channel.receive()
    except (EOFError, OSError, ValueError):
        os._exit(0)
    reason = unsafe or _declined(command, fingerprint)
    if reason is not None:
        _log(f"declined a run: {reason}")
        with contextlib.suppress(OSError):
            channel.send(("declined", reason))
        if reason.startswith("changed"):
            os.kill(server, signal.SIGTERM)  # the caller starts a fresh server
        os._exit(0)
    worker = os.fork()
    if worker == 0:
        channel.connection.close()
        become_worker(command, fds)
    for fd in fds:
        os.close(fd)
    _log(f"worker {worker}: baobab {' '.join(command.argv[1:])}")
    with contextlib.suppress(OSError):
        channel.send(("started", worker))
    code = _wait(worker, channel)
    _log(f"worker {worker} ended with exit code {code}")
    with contextlib.suppress(OSError):
        channel.send(("ended", code))  # 128 + N: killed by signal N, or ended by it
    os._exit(0)


def _declined(command: object, fingerprint: Stamps) -> str | None:
    if not isinstance(command, ServedCommand):
        return "not a request"
    changed = sorted(path for path, stamp in fingerprint.items() if _stamp(path) != stamp)
    if changed:
        return f"changed since the server loaded it: {changed[0]}"
    for name, (_soft, hard) in command.limits.items():
        own_hard = resource.getrlimit(getattr(resource, name))[1]
        unlimited = resource.RLIM_INFINITY
        if own_hard != unlimited and (hard == unlimited or hard > own_hard):
            return f"{name} above the server's"
    return None


def _wait(worker: int, channel: Channel) -> int:
    """Wait for ``worker``; if the caller goes away meanwhile, hang its run up. Its exit code
    (``128 + N`` when signal N killed it; the caller says so, the worker could not)."""
    ended = os.pidfd_open(worker)
    connection = channel.connection
    watched: list[int | socket.socket] = [ended, connection]
    while True:
        ready, _, _ = select.select(watched, [], [])
        if ended in ready:
            break
        if not connection.recv(4096):  # the caller went away (it sends nothing else)
            os.kill(worker, signal.SIGHUP)
            watched = [ended]
    _pid, status = os.waitpid(worker, 0)
    if os.WIFSIGNALED(status):
        with contextlib.suppress(OSError):
            channel.send(("killed", os.WTERMSIG(status)))
        return exit_code_for(os.WTERMSIG(status))
    return os.waitstatus_to_exitcode(status)


def become_worker(command: ServedCommand, fds: list[int]) -> NoReturn:
    """Take the caller's place (see :class:`ServedCommand`) and run the ``baobab`` command line."""
    os.setsid()  # its own process group: the caller forwards the terminal's signals
    for target, fd in enumerate(fds):
        os.dup2(fd, target)
    for fd in fds:
        if fd > 2:
            os.close(fd)
    try:
        os.chdir(command.cwd)
    except OSError as exc:
        os.write(2, f"baobab: the working folder is gone: {exc}\n".encode())
        os._exit(2)
    os.umask(command.umask)
    for name, limits in command.limits.items():
        resource.setrlimit(getattr(resource, name), limits)
    os.environ.clear()
    os.environ.update(command.environ)
    sys.argv = list(command.argv)
    _adopt_streams(command.streams, unbuffered=bool(command.environ.get("PYTHONUNBUFFERED")))
    from baobab.missions.cli import run_client
    from baobab.missions.cli.startup import environment_defaults

    run_client.IN_WORKER = True
    environment_defaults()
    exit_on_signals()
    from baobab.missions.cli.entry import main as baobab

    os._exit(baobab())


def _log(line: str) -> None:
    """One line on standard error: the log file :func:`.run_client.start_server` opened."""
    with contextlib.suppress(OSError):
        os.write(2, f"{time.strftime('%H:%M:%S')} {line}\n".encode("utf-8", "replace"))


def _adopt_streams(streams: list[tuple[str, str]], unbuffered: bool) -> None:
    """Standard streams on descriptors 0-2 as Python makes them (line-buffered on a terminal)."""
    (in_encoding, in_errors), (out_encoding, out_errors), (err_encoding, err_errors) = streams
    stdin = io.TextIOWrapper(
        io.BufferedReader(io.FileIO(0, "r", closefd=False)), in_encoding, in_errors
    )
    stdout = io.TextIOWrapper(
        io.BufferedWriter(io.FileIO(1, "w", closefd=False)),
        out_encoding,
        out_errors,
        line_buffering=os.isatty(1),
        write_through=unbuffered,
    )
    stderr = io.TextIOWrapper(
        io.BufferedWriter(io.FileIO(2, "w", closefd=False)),
        err_encoding,
        err_errors,
        line_buffering=True,
        write_through=unbuffered,
    )
    for name, stream in (("stdin", stdin), ("stdout", stdout), ("stderr", stderr)):
        setattr(sys, name, stream)
        setattr(sys, f"__{name}__", stream)


if __name__ == "__main__":
    raise SystemExit(main())
