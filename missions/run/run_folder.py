"""The run folder: ``result.json``, ``trace.jsonl`` and ``plot.png``; claimed, then written.

A run first claims its folder (:func:`claimed_run_folder`): the folder is created if needed
(or taken if it exists and is empty, such as a container's mount point) and locked, so a
second run given the same ``--out`` is refused before it simulates anything. The files are
then written into a hidden temporary folder inside it and moved into place with
``result.json`` last: a folder with a ``result.json`` is complete. On any error, the
temporary folder and whatever had been moved are removed, so a failed write leaves the folder
as it was (empty).
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import shutil
from collections.abc import Iterator, Mapping
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

from baobab.missions.run.output_checks import OutputError, check_output_folder

if TYPE_CHECKING:
    from baobab.missions.run.plot_data import PlotData

RESULT_FILE = "result.json"
TRACE_FILE = "trace.jsonl"
PLOT_FILE = "plot.png"
DEFAULT_ROOT = Path("runs")


class RunFolderError(OutputError):
    """The run folder cannot be used (a file, a non-empty folder, in use by another run)."""


def default_run_folder(
    mission: str, root: Path = DEFAULT_ROOT, now: datetime | None = None
) -> Path:
    """``runs/<mission>-<UTC timestamp>``, with ``-2``, ``-3``... if that name is taken."""
    stamp = (now or datetime.now(UTC)).strftime("%Y%m%dT%H%M%SZ")
    folder = root / f"{mission}-{stamp}"
    suffix = 2
    while folder.exists():
        folder = root / f"{mission}-{stamp}-{suffix}"
        suffix += 1
    return folder


def check_run_folder(folder: Path, flag: str = "--out") -> None:
    """Refuse a target that is a file, a non-empty folder, or on a file system that cannot
    take it (read-only, not writable, full); before the run.

    Raises:
        RunFolderError: with the reason.
    """
    try:
        check_output_folder(flag, folder)
    except OutputError as error:
        raise RunFolderError(str(error)) from None


@contextlib.contextmanager
def claimed_run_folder(folder: Path, flag: str = "--out") -> Iterator[Path]:
    """Create (or take, when empty) ``folder`` and lock it against other runs while inside.

    On the way out, the folder is removed again if nothing was written into it (with the
    parent folders this made). The lock is the kernel's (``flock``): it goes with the
    process, whatever ends it.

    Raises:
        RunFolderError: the folder is locked by another run, not empty, or cannot be made.
    """
    check_run_folder(folder, flag)
    made = _make_folders(folder, flag)
    try:
        descriptor = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    except OSError as error:
        _remove_if_empty(made)
        raise RunFolderError(f"{flag} {folder}: cannot open the folder: {error.strerror}") from None
    try:
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise RunFolderError(
                f"{flag} {folder}: in use by another baobab run; wait for it to end or give "
                "another folder"
            ) from None
        try:
            check_run_folder(folder, flag)  # a run that held the lock may just have written it
            yield folder
        finally:
            _remove_if_empty(made)
    finally:
        os.close(descriptor)


def _make_folders(folder: Path, flag: str) -> list[Path]:
    """Create ``folder`` and its missing parents; the ones made, outermost first."""
    missing = [folder, *folder.parents]
    missing = list(reversed([path for path in missing if not path.exists()]))
    made: list[Path] = []
    for path in missing:
        try:
            path.mkdir()
        except FileExistsError:
            continue  # made meanwhile, by another run: the lock decides
        except OSError as error:
            _remove_if_empty(made)
            reason = error.strerror or str(error)
            raise RunFolderError(f"{flag} {folder}: cannot create {path}: {reason}") from None
        made.append(path)
    return made


def _remove_if_empty(made: list[Path]) -> None:
    for path in reversed(made):
        try:
            path.rmdir()
        except OSError:
            return  # not empty (the run was written) or gone


def write_run_folder(
    folder: Path, result: Mapping[str, Any], trace_text: str, plot: PlotData | None
) -> Path:
    """Write the run folder and return its path.

    Args:
        folder: the target (created if missing; must be empty).
        result: the result object (``result.json``).
        trace_text: the trace as JSON Lines (``trace.jsonl``).
        plot: what ``plot.png`` shows; no plot when None.

    Raises:
        RunFolderError: when the target is taken.
        OSError: when the file system refuses; the folder is left as it was.
    """
    folder.mkdir(parents=True, exist_ok=True)
    if any(folder.iterdir()):
        raise RunFolderError(f"{folder}: folder is not empty; give a new or empty folder")
    temporary = folder / f".writing-{os.getpid()}"
    moved: list[Path] = []
    try:
        temporary.mkdir()
        (temporary / TRACE_FILE).write_text(trace_text, encoding="utf-8")
        if plot is not None:
            # Imported here: `baobab run` checks the run folder before the run's process is
            # forked, and that process must start single-threaded (NumPy's BLAS starts threads).
            from baobab.missions.run.plotting import save_plot

            save_plot(plot, temporary / PLOT_FILE)
        (temporary / RESULT_FILE).write_text(
            json.dumps(result, indent=2, ensure_ascii=False) + "\n", encoding="utf-8"
        )
        for name in (TRACE_FILE, PLOT_FILE, RESULT_FILE):  # result.json last: "complete"
            if (temporary / name).exists():
                os.replace(temporary / name, folder / name)
                moved.append(folder / name)
        temporary.rmdir()
    except BaseException:
        shutil.rmtree(temporary, ignore_errors=True)
        for path in moved:
            path.unlink(missing_ok=True)
        raise
    return folder
