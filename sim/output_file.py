"""A file written beside its final name and moved there once complete; a write error ends it.

Recordings (MCAP) are written while the run goes on. When the disk fills or the file system
turns read-only meanwhile, an :class:`OutputFile` says so once (``on_failure``), removes what
it had written and accepts every later write without writing it, so the run goes on and the
writer that feeds it (foxglove-sdk's, in native code) sees no error per message. Nothing is
ever left under the final name unless it is complete: the data goes to a hidden
``.<name>.tmp-<pid>`` beside it, renamed into place by :meth:`OutputFile.close`.
"""

from __future__ import annotations

import contextlib
import io
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from _typeshed import ReadableBuffer


class OutputFile(io.RawIOBase):
    """A seekable binary file for writing ``path``; see the module text.

    Args:
        path: the final file (replaced, if it exists, when this one is complete).
        on_failure: told once, in words, why writing stopped (e.g. "No space left on device");
            without it, the owner reads :attr:`failure` after :meth:`close`.

    Raises:
        OSError: the temporary file cannot be created.
    """

    def __init__(self, path: str | Path, on_failure: Callable[[str], None] | None = None) -> None:
        super().__init__()
        self.path = Path(path)
        self.temporary = self.path.with_name(f".{self.path.name}.tmp-{os.getpid()}")
        self.failure: str | None = None
        self._on_failure = on_failure
        self._file: io.BufferedWriter | None = open(self.temporary, "wb")  # noqa: SIM115
        self._position = 0  # where writes go once they are dropped

    def writable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def write(self, data: ReadableBuffer, /) -> int:
        """Write ``data`` (or drop it, once writing has failed); returns its length."""
        size = len(memoryview(data).cast("B"))
        if self._file is not None:
            try:
                self._file.write(data)
            except OSError as error:
                self._fail(error)
        self._position += size
        return size

    def seek(self, offset: int, whence: int = io.SEEK_SET) -> int:
        """Move to ``offset`` (from the start, the current position or the end)."""
        if self._file is not None:
            try:
                self._position = self._file.seek(offset, whence)
                return self._position
            except OSError as error:
                self._fail(error)
        base = {io.SEEK_SET: 0, io.SEEK_CUR: self._position, io.SEEK_END: self._position}
        self._position = base[whence] + offset
        return self._position

    def tell(self) -> int:
        return self._position if self._file is None else self._file.tell()

    def flush(self) -> None:
        if self._file is not None:
            try:
                self._file.flush()
            except OSError as error:
                self._fail(error)

    def close(self) -> None:
        """Finish: move the complete file to its final name (or drop it after a failure)."""
        if self.closed:
            return
        try:
            if self._file is not None:
                self._file.flush()
                os.fsync(self._file.fileno())
                self._file.close()
                self._file = None
                os.replace(self.temporary, self.path)
        except OSError as error:
            self._fail(error)
        finally:
            super().close()

    def discard(self) -> None:
        """Drop what was written (nothing reaches the final name)."""
        if self._file is not None:
            with contextlib.suppress(OSError):
                self._file.close()
            self._file = None
        self.temporary.unlink(missing_ok=True)
        super().close()

    def __del__(self) -> None:
        # Never finished by close(): incomplete, so it must not reach the final name.
        if not self.closed:
            self.discard()

    def _fail(self, error: OSError) -> None:
        """Stop writing: remove the temporary file and say why, once."""
        if self._file is not None:
            with contextlib.suppress(OSError):
                self._file.close()
            self._file = None
        self.temporary.unlink(missing_ok=True)
        if self.failure is None:
            self.failure = error.strerror or str(error)
            if self._on_failure is not None:
                self._on_failure(self.failure)
