"""Reading a user's input file: a regular file of bounded size, or a located one-line error.

Every file baobab reads on a user's behalf (missions, worlds, baselines, campaign missions,
``baobab nav2`` scripts) goes through :func:`read_input_file`. A path may name anything:
``/dev/zero`` and ``/dev/urandom`` never end, a FIFO blocks until someone writes to it, a
directory or a socket cannot be read. So the kind of file is checked before it is opened
(``stat``), the file is opened without waiting for a writer, checked again on the open
descriptor (the path may have changed in between), and read up to the size limit and one byte
more: a file that grows while it is read, or a ``/proc`` file whose size reads 0, is still
refused before it is held whole.
"""

from __future__ import annotations

import errno
import os
import stat
from collections.abc import Callable
from pathlib import Path

from baobab.sim.errors import SourceError

MAX_INPUT_BYTES = 2_000_000
"""The largest input file read (bytes): missions, worlds, baselines and scripts."""

ErrorType = Callable[[str, int, int, str], SourceError]

_KINDS = (
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def file_kind_problem(mode: int) -> str | None:
    """Why a file of ``st_mode`` ``mode`` cannot be read as input (``is a FIFO ...``), or None."""
    if stat.S_ISREG(mode):
        return None
    return next((f"is {name}" for test, name in _KINDS if test(mode)), "is not a regular file")


def read_input_file(
    path: str | Path,
    error_type: ErrorType = SourceError,
    *,
    expected: str = "a file",
    limit: int = MAX_INPUT_BYTES,
) -> bytes:
    """The bytes of the regular file at ``path``, at most ``limit`` of them.

    Args:
        path: the file, as the user gave it (messages name it so).
        error_type: the located error to raise (``MissionError``, ``WorldError``...).
        expected: what the file should be, for messages (``a YAML file``).
        limit: the largest size accepted (bytes).

    Raises:
        error_type: at 1:1 of ``path``: no such file, permission denied, a directory, device,
            FIFO or socket, a file over ``limit`` bytes, or another read error.
    """
    shown = str(path)

    def refuse(message: str) -> SourceError:
        return error_type(shown, 1, 1, message)

    try:
        problem = file_kind_problem(os.stat(path).st_mode)
        if problem is not None:
            raise refuse(f"{problem}; expected {expected}")
        descriptor = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC)
        try:
            status = os.fstat(descriptor)
            problem = file_kind_problem(status.st_mode)
            if problem is not None:  # swapped for something else since the stat above
                raise refuse(f"{problem}; expected {expected}")
            if status.st_size > limit:
                raise refuse(_too_big(status.st_size, limit))
            data = _read_at_most(descriptor, limit + 1)
        finally:
            os.close(descriptor)
    except FileNotFoundError:
        raise refuse("no such file") from None
    except PermissionError:
        raise refuse("permission denied") from None
    except OSError as exc:
        if exc.errno == errno.ENOTDIR:
            raise refuse("no such file (a part of the path is not a folder)") from None
        raise refuse(f"cannot read: {exc.strerror or exc}") from None
    if len(data) > limit:
        raise refuse(_too_big(None, limit))
    return data


def _too_big(size: int | None, limit: int) -> str:
    what = f"is {size} bytes" if size is not None else f"holds more than {limit} bytes"
    return f"file {what}; the limit is {limit} bytes"


def _read_at_most(descriptor: int, count: int) -> bytes:
    """Up to ``count`` bytes from ``descriptor``, fewer only at its end."""
    chunks: list[bytes] = []
    remaining = count
    while remaining > 0:
        chunk = os.read(descriptor, min(remaining, 1 << 20))
        if not chunk:
            break
        chunks.append(chunk)
        remaining -= len(chunk)
    return b"".join(chunks)
