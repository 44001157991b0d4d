"""Checks of what a command will write, made before it simulates anything.

A run that cannot keep what it makes is refused at once (exit 2, one line naming the flag and
the path), instead of failing after the simulation: the run folder's file system must be
writable and have room (:data:`MIN_FREE_BYTES`), ``--record``/``--video``/``--btlog``/
``--baseline`` must name a regular file (or a new one) in a writable folder (``--live``'s
address is checked by :meth:`~baobab.sim.recording_sinks.LiveSink.check_address`). Each check
uses the file system's own answers (``statvfs``, ``access``), so nothing is written by a
refusal.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from baobab.sim.errors import BaobabError

MIN_FREE_BYTES = 1 << 20
"""Free space a command needs before it starts (bytes): room for a short run's folder."""


class OutputError(BaobabError):
    """A place a command would write to cannot be written."""


def nearest_existing(path: Path) -> Path:
    """``path`` itself if it exists, else its nearest ancestor that does."""
    path = Path(os.path.abspath(path))
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def filesystem_problem(folder: Path) -> str | None:
    """Why files cannot be created in the existing folder ``folder``, or None."""
    try:
        facts = os.statvfs(folder)
    except OSError as error:
        return error.strerror or str(error)
    if facts.f_flag & os.ST_RDONLY:
        return "it is on a read-only file system"
    if not os.access(folder, os.W_OK | os.X_OK):
        return "it is not writable"
    free = facts.f_bavail * facts.f_frsize
    if free < MIN_FREE_BYTES:
        needed = MIN_FREE_BYTES >> 20
        return f"its file system is full ({free // 1024} KiB free, at least {needed} MiB needed)"
    return None


def check_output_folder(flag: str, folder: Path) -> None:
    """Refuse a folder target (``--out``) that is a file, not empty, or cannot be written.

    A folder that does not exist yet is checked where it will be created.

    Raises:
        OutputError: with the reason, naming ``flag`` and ``folder``.
    """
    existing = nearest_existing(folder)
    if existing == Path(os.path.abspath(folder)):
        if not existing.is_dir():
            raise OutputError(f"{flag} {folder}: is a file; give a folder that does not exist yet")
        if any(existing.iterdir()):
            raise OutputError(f"{flag} {folder}: folder is not empty; give a new or empty folder")
    elif not existing.is_dir():
        raise OutputError(f"{flag} {folder}: {existing} is a file, not a folder")
    problem = filesystem_problem(existing)
    if problem is not None:
        where = "" if existing == Path(os.path.abspath(folder)) else f" ({existing})"
        raise OutputError(f"{flag} {folder}: cannot write there{where}: {problem}")


def check_output_file(flag: str, path: Path, *, create_folders: bool = False) -> None:
    """Refuse a file target that is a folder or a special file, or whose folder cannot take it.

    Args:
        flag: the command-line flag, for the message.
        path: the file to be written (replaced if it exists).
        create_folders: the command creates missing folders (else they must exist).

    Raises:
        OutputError: with the reason, naming ``flag`` and ``path``.
    """
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        mode = None
    except OSError as error:
        raise OutputError(f"{flag} {path}: {error.strerror}") from None
    if mode is not None and stat.S_ISDIR(mode):
        raise OutputError(f"{flag} {path}: is a folder; give a file name")
    if mode is not None and not stat.S_ISREG(mode):
        raise OutputError(f"{flag} {path}: is not a regular file (a device, FIFO or socket)")
    folder = Path(os.path.abspath(path)).parent
    if not folder.is_dir() and not create_folders:
        raise OutputError(f"{flag} {path}: the folder {path.parent} does not exist")
    existing = nearest_existing(folder)
    if not existing.is_dir():
        raise OutputError(f"{flag} {path}: {existing} is a file, not a folder")
    problem = filesystem_problem(existing)
    if problem is None and mode is not None and not os.access(path, os.W_OK):
        problem = "the file is not writable"
    if problem is not None:
        raise OutputError(f"{flag} {path}: cannot write there: {problem}")
