"""Node files: how ``baobab ros run NODE.py`` runs a student's or an engineer's rclpy file.

A file that defines ``main`` at top level is loaded under its own module name and its
``main()`` is called, as ``ros2 run`` calls a package's entry point (``pkg.module:main``); any
other file runs as ``__main__``, as ``python3 NODE.py`` would run it. Either way the file's
folder comes first on ``sys.path`` (so its sibling modules import), ``sys.argv`` is the file's
path followed by its arguments (the ``--ros-args`` that ``rclpy.init()`` reads), and the
modules it imported from its folder are forgotten after the run.

A node's exception is the user's own code failing: :func:`failure_report` shows its traceback
from the file's first frame on, and names the file and its nodes.
"""

from __future__ import annotations

import ast
import runpy
import sys
import traceback
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from types import TracebackType

from baobab.nav.ros.script_files import ScriptError, check_script

__all__ = ["ScriptError", "check_script", "failure_report", "node_file_main", "node_file_paths"]


def node_file_main(path: Path) -> Callable[[], None]:
    """What runs the node file at ``path`` (see the module docstring); checked already.

    Raises:
        ScriptError: the file cannot be read or does not compile.
    """
    check_script(path)
    tree = ast.parse(path.read_bytes(), filename=str(path))
    has_main = any(
        isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and node.name == "main"
        for node in tree.body
    )
    shown = str(path)

    def run() -> None:
        if not has_main:
            runpy.run_path(shown, run_name="__main__")
            return
        module = runpy.run_path(shown, run_name=path.stem)
        module["main"]()

    return run


@contextmanager
def node_file_paths(paths: list[Path]) -> Iterator[None]:
    """Put the node files' folders first on ``sys.path`` for the block; forget the modules
    imported from them afterwards."""
    folders = list(dict.fromkeys(str(path.resolve().parent) for path in paths))
    saved_path = list(sys.path)
    modules_before = set(sys.modules)
    sys.path[:0] = folders
    try:
        yield
    finally:
        sys.path[:] = saved_path
        for name in set(sys.modules) - modules_before:
            origin = getattr(sys.modules[name], "__file__", None)
            if origin is not None and str(Path(origin).resolve().parent) in folders:
                del sys.modules[name]


def failure_report(origin: str, node_names: list[str], error: BaseException) -> str:
    """The traceback of ``error`` from the node file's first frame, then one line naming the
    file and its nodes."""
    tb = _from_file_frames(error.__traceback__, origin)
    shown = "".join(traceback.format_exception(type(error), error, tb))
    nodes = ", ".join(f"'{name}'" for name in node_names) or "no node yet"
    return f"{shown}{origin}: node code failed ({nodes}): {type(error).__name__}: {error}"


def _from_file_frames(tb: TracebackType | None, origin: str) -> TracebackType | None:
    start = tb
    while start is not None and start.tb_frame.f_code.co_filename != origin:
        start = start.tb_next
    return tb if start is None else start
