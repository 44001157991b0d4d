"""Where ``baobab run`` finds its run server, and the messages the two exchange.

The run server (:mod:`.run_server`) is a process that has loaded, once, what every run loads
and no run changes (MuJoCo, numba and the compiled control dispatcher, pydantic and the
mission language, py_trees, matplotlib); ``baobab run`` (:mod:`.run_client`) hands it its
command line, working folder, environment and standard streams, and a fork of the server runs
the command in the caller's place. This module is the part both sides share, standard library
only: the client imports it before anything else loads.

One server serves one installation and one set of start-up settings: its socket's name is a
digest of the Python environment (``sys.prefix``), the package's folder and the environment
variables that change what loading does (:data:`KEY_VARIABLES`). The socket lives in a folder
only its user can enter (``$XDG_RUNTIME_DIR/baobab``, else ``<tmp>/baobab-<uid>``).

Variables: ``BAOBAB_RUN_SERVER=0`` (or ``off``, ``no``, ``false``) runs every command in its
own process as before; ``BAOBAB_RUN_SERVER_IDLE`` is how long an unused server stays (seconds,
default 600); ``BAOBAB_RUN_SERVER_DIR`` puts the socket elsewhere.
"""

from __future__ import annotations

import hashlib
import os
import pickle
import socket
import struct
import sys
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from baobab.missions.cli.startup import environment_defaults

ENABLED = "BAOBAB_RUN_SERVER"
"""``0``, ``off``, ``no`` or ``false`` turns the run server off."""
IDLE = "BAOBAB_RUN_SERVER_IDLE"
"""Seconds an unused run server stays before it exits (default :data:`DEFAULT_IDLE`)."""
FOLDER = "BAOBAB_RUN_SERVER_DIR"
"""The folder for the server's socket and lock, instead of the default one."""
DEFAULT_IDLE = 600.0
"""Seconds (10 minutes)."""
KEY_VARIABLES = (
    *("MUJOCO", "NUMBA", "PYTHON", "PYOPENGL", "PYDANTIC", "OMP_", "MKL_", "OPENBLAS"),
    *("LD_", "MPL", "EGL", "MESA", "DISPLAY", "WAYLAND_DISPLAY", "HOME", "BAOBAB"),
)
"""Prefixes of the environment variables read while modules load: a server started with other
values is another server."""
LIMITS = ("RLIMIT_AS", "RLIMIT_CPU", "RLIMIT_DATA", "RLIMIT_FSIZE", "RLIMIT_NOFILE", "RLIMIT_CORE")
"""The resource limits a worker takes from its caller (``ulimit -v``, ``-t``, ``-f`` ...)."""
_LENGTH = struct.Struct("!I")
MAX_FDS = 3
"""A request carries the caller's standard input, output and error."""


def server_command(path: Path) -> list[str]:
    """The command line that starts the run server of the socket ``path`` (run it in ``/``:
    with ``-P`` and there, no module of the caller's folder shadows an installed one)."""
    return [sys.executable, "-P", "-m", "baobab.missions.cli.run_server", str(path)]


def server_enabled(environ: Mapping[str, str]) -> bool:
    """Whether ``baobab run`` may use (and start) a run server."""
    return environ.get(ENABLED, "1").strip().lower() not in ("0", "off", "no", "false")


def idle_seconds(environ: Mapping[str, str]) -> float:
    """How long an unused server stays (s); :data:`DEFAULT_IDLE` unless set to a number > 0."""
    try:
        seconds = float(environ.get(IDLE, DEFAULT_IDLE))
    except ValueError:
        return DEFAULT_IDLE
    return seconds if seconds > 0 else DEFAULT_IDLE


def server_folder(environ: Mapping[str, str]) -> Path | None:
    """The folder of the sockets, made if missing; None where it is not this user's alone."""
    chosen = environ.get(FOLDER)
    if chosen:
        folder = Path(chosen)
    elif environ.get("XDG_RUNTIME_DIR"):
        folder = Path(environ["XDG_RUNTIME_DIR"]) / "baobab"
    else:
        folder = Path(tempfile.gettempdir()) / f"baobab-{os.getuid()}"
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        status = folder.stat()
    except OSError:
        return None
    if status.st_uid != os.getuid() or status.st_mode & 0o077:
        return None  # another user could reach the socket
    return folder


def server_key(environ: Mapping[str, str]) -> str:
    """16 hex digits naming the server for this interpreter, installation and settings."""
    effective = dict(environ)
    environment_defaults(effective)  # as the command will have them when its modules load
    digest = hashlib.sha256()
    for part in (sys.prefix, os.path.dirname(os.path.abspath(__file__)), sys.version):
        digest.update(part.encode("utf-8", "surrogateescape") + b"\0")
    for name in sorted(effective):
        if name.startswith(KEY_VARIABLES) and name not in (ENABLED, IDLE, FOLDER):
            digest.update(f"{name}={effective[name]}".encode("utf-8", "surrogateescape") + b"\0")
    return digest.hexdigest()[:16]


def socket_path(environ: Mapping[str, str]) -> Path | None:
    """The socket of this installation's run server, or None where there can be none."""
    folder = server_folder(environ)
    return None if folder is None else folder / f"run-{server_key(environ)}.sock"


@dataclass(frozen=True)
class ServedCommand:
    """What a caller sends: everything of its process that its command may read.

    Attributes:
        argv: ``sys.argv``.
        cwd: the working folder.
        umask: the file creation mask.
        environ: the environment.
        streams: (encoding, errors) of stdin, stdout and stderr.
        limits: (soft, hard) of each of :data:`LIMITS`, by name.
    """

    argv: list[str]
    cwd: str
    umask: int
    environ: dict[str, str]
    streams: list[tuple[str, str]]
    limits: dict[str, tuple[int, int]] = field(default_factory=dict)


class Channel:
    """Messages over a connected stream socket: each a length and a pickle, the first of a
    request with the caller's file descriptors."""

    def __init__(self, connection: socket.socket) -> None:
        self.connection = connection
        self._buffer = b""

    def send(self, message: Any, fds: Sequence[int] = ()) -> None:
        """Send one picklable ``message`` (and the open file descriptors ``fds``)."""
        payload = pickle.dumps(message)
        data = _LENGTH.pack(len(payload)) + payload
        sent = socket.send_fds(self.connection, [data], list(fds)) if fds else 0
        self.connection.sendall(data[sent:])

    def receive(self) -> tuple[Any, list[int]]:
        """The next message and the descriptors that came with it.

        Raises:
            EOFError: the other side closed the connection before a whole message came.
        """
        fds: list[int] = []
        while True:
            if len(self._buffer) >= _LENGTH.size:
                (length,) = _LENGTH.unpack_from(self._buffer)
                end = _LENGTH.size + length
                if len(self._buffer) >= end:
                    payload, self._buffer = self._buffer[_LENGTH.size : end], self._buffer[end:]
                    return pickle.loads(payload), fds
            data, more_fds, _flags, _address = socket.recv_fds(self.connection, 65536, MAX_FDS)
            fds.extend(more_fds)
            if not data:
                for fd in fds:
                    os.close(fd)
                raise EOFError("the connection closed")
            self._buffer += data
