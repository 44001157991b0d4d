"""A user's Python file (a node file, a launch file, a Nav2 script), read and compiled before it
runs, so that a file that cannot run is refused with a located one-line error."""

from __future__ import annotations

from pathlib import Path
from types import CodeType

from baobab.sim.errors import SourceError
from baobab.sim.input_files import read_input_file


class ScriptError(SourceError):
    """A script that cannot be read or compiled, located as ``path:line:col: message``."""


def check_script(path: Path) -> CodeType:
    """Read and compile the script at ``path`` without running it.

    Raises:
        ScriptError: the file cannot be read (or is not a regular file, or is over
            :data:`~baobab.sim.input_files.MAX_INPUT_BYTES`), or holds a syntax error (located
            where Python locates it).
    """
    shown = str(path)
    source = read_input_file(path, ScriptError, expected="a Python script")
    try:
        return compile(source, shown, "exec", dont_inherit=True)
    except SyntaxError as exc:
        line, column = exc.lineno or 1, exc.offset or 1
        raise ScriptError(shown, line, max(column, 1), f"{type(exc).__name__}: {exc.msg}") from None
    except ValueError as exc:  # NUL bytes in the source
        raise ScriptError(shown, 1, 1, str(exc)) from None
