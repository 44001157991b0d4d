"""The process's standard streams as a Unix tool treats them: closed or broken, never fatal.

- A stream closed before the command started (``baobab run ... >&-``, ``2>&-``): its file
  descriptor is reopened on ``/dev/null``, so output meant for it is dropped and no file the
  command opens later (a run folder's, a recording) takes descriptor 1 or 2 by accident, where
  a print or a native library's message would corrupt it.
- A stream whose reader went away (``baobab list | head -0``, ``validate ... | head -c1``):
  the first write that meets EPIPE points the descriptor at ``/dev/null`` and the command goes
  on quietly; a run still writes its folder and exits with its own code.

Only the process's own streams are guarded (a caller that replaced ``sys.stdout``, such as a
test capturing output, keeps its stream as it is).
"""

from __future__ import annotations

import contextlib
import io
import os
import sys
from typing import TextIO


class ReaderGoneSafeStream(io.TextIOWrapper):
    """A text stream that switches to ``/dev/null`` when its reader goes away (EPIPE)."""

    def write(self, text: str) -> int:
        """Write ``text``; once the reader has gone, drop it."""
        try:
            return super().write(text)
        except BrokenPipeError:
            self._drop_from_now_on()
            return len(text)

    def flush(self) -> None:
        """Flush; once the reader has gone, what was buffered goes to ``/dev/null``."""
        try:
            super().flush()
        except BrokenPipeError:
            self._drop_from_now_on()

    def _drop_from_now_on(self) -> None:
        with contextlib.suppress(OSError, ValueError):
            _reopen_on_devnull(self.fileno())
            super().flush()  # the buffered text now goes to /dev/null


def guard_standard_streams() -> None:
    """Reopen closed standard descriptors on ``/dev/null``; make stdout and stderr EPIPE-safe."""
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:  # closed: the shell's `>&-`
            _reopen_on_devnull(fd)
    sys.stdout = _guarded(sys.stdout, 1, "__stdout__")
    sys.stderr = _guarded(sys.stderr, 2, "__stderr__")


def _guarded(stream: TextIO | None, fd: int, original: str) -> TextIO:
    if isinstance(stream, ReaderGoneSafeStream):
        return stream
    if stream is not None and stream is not getattr(sys, original):
        return stream  # replaced by the caller (a test capturing output): theirs to handle
    if stream is None:  # the descriptor was closed at start-up: now /dev/null
        guarded = ReaderGoneSafeStream(open(fd, "wb", closefd=False), encoding="utf-8")  # noqa: SIM115
    else:
        stream.flush()
        guarded = ReaderGoneSafeStream(
            stream.detach(),
            encoding=stream.encoding,
            errors=stream.errors,
            line_buffering=stream.line_buffering,
        )
    setattr(sys, original, guarded)
    return guarded


def _reopen_on_devnull(fd: int) -> None:
    devnull = os.open(os.devnull, os.O_RDWR)
    try:
        os.dup2(devnull, fd)
    finally:
        if devnull != fd:
            os.close(devnull)
