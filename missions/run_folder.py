"""The run folder: ``result.json``, ``trace.jsonl`` and ``plot.png``, written atomically.

Everything is written into a hidden temporary folder beside the target, which is renamed into
place only once complete; on any error the temporary folder is removed. So a run folder is
either complete or absent, whatever interrupts the writing.
"""

from __future__ import annotations

import json
import os
import shutil
from collections.abc import Mapping
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

from baobab.sim.errors import BaobabError

if TYPE_CHECKING:
    from baobab.missions.plotting import PlotData

RESULT_FILE = "result.json"
TRACE_FILE = "trace.jsonl"
PLOT_FILE = "plot.png"
DEFAULT_ROOT = Path("runs")


class RunFolderError(BaobabError):
    """The run folder cannot be used (it exists and is not empty, or is a file)."""


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


def check_run_folder(folder: Path) -> None:
    """Refuse a target that exists and is a file or a non-empty folder (before the run).

    Raises:
        RunFolderError: with the reason.
    """
    if folder.is_file():
        raise RunFolderError(f"--out {folder}: is a file; give a folder that does not exist yet")
    if folder.is_dir() and any(folder.iterdir()):
        raise RunFolderError(f"--out {folder}: folder is not empty; give a new or empty folder")


def write_run_folder(
    folder: Path, result: Mapping[str, Any], trace_text: str, plot: PlotData | None
) -> Path:
    """Write the run folder atomically and return its path.

    Args:
        folder: the target (must not exist, or be an empty folder).
        result: the result object (``result.json``).
        trace_text: the trace as JSON Lines (``trace.jsonl``).
        plot: what ``plot.png`` shows; no plot when None.

    Raises:
        RunFolderError: when the target is taken.
        OSError: when the file system refuses; nothing is left behind.
    """
    check_run_folder(folder)
    folder.parent.mkdir(parents=True, exist_ok=True)
    temporary = folder.parent / f".{folder.name}.tmp-{os.getpid()}"
    if temporary.exists():
        shutil.rmtree(temporary)
    try:
        temporary.mkdir()
        (temporary / RESULT_FILE).write_text(
            json.dumps(result, indent=2, ensure_ascii=False) + "\n", encoding="utf-8"
        )
        (temporary / TRACE_FILE).write_text(trace_text, encoding="utf-8")
        if plot is not None:
            # Imported here: `baobab run` checks the run folder before the run's process is
            # forked, and that process must start single-threaded (NumPy's BLAS starts threads).
            from baobab.missions.plotting import save_plot

            save_plot(plot, temporary / PLOT_FILE)
        if folder.is_dir():
            folder.rmdir()  # empty, checked above
        temporary.rename(folder)
    except BaseException:
        shutil.rmtree(temporary, ignore_errors=True)
        raise
    return folder
