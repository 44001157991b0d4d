"""Real small, full and read-only file systems for tests: tmpfs mounts (needs root).

A test that needs one asks :func:`tmpfs`; where this machine cannot mount (not root, a
container without the capability), the test is skipped with the reason, never faked.
"""

from __future__ import annotations

import subprocess
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest


def _mount(*arguments: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(["mount", *arguments], capture_output=True, text=True, check=False)


@contextmanager
def tmpfs(where: Path, size_kib: int) -> Iterator[Path]:
    """A tmpfs of ``size_kib`` KiB mounted at ``where`` (created) while inside."""
    where.mkdir(parents=True, exist_ok=True)
    try:
        done = _mount("-t", "tmpfs", "-o", f"size={size_kib}k", "tmpfs", str(where))
    except FileNotFoundError:
        pytest.skip("no mount command on this machine: cannot test a real small file system")
    if done.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here (needs root): {done.stderr.strip()}")
    try:
        yield where
    finally:
        subprocess.run(["umount", "-l", str(where)], check=False, capture_output=True)


def make_read_only(where: Path) -> None:
    """Remount the tmpfs at ``where`` read-only (as a failing disk or a full quota does)."""
    done = _mount("-o", "remount,ro", str(where))
    assert done.returncode == 0, done.stderr


def fill(where: Path) -> None:
    """Fill the file system of ``where`` to the last byte."""
    for name, chunk in (("filler", 65536), ("filler-tail", 1)):
        with open(where / name, "wb", buffering=0) as filler:
            try:
                while filler.write(b"\0" * chunk):
                    pass
            except OSError:  # ENOSPC: full
                pass
