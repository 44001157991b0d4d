"""Run an unmodified Nav2 Simple Commander script against baobab (``baobab nav2 SCRIPT.py``).

The script runs as ``__main__``, as ``python3 SCRIPT.py`` would run it: its folder first on
``sys.path``, ``sys.argv[0]`` its path, its output going straight to standard output. Its
imports of ``rclpy``, ``geometry_msgs.msg``, ``robot_navigator`` and the rest resolve to
:mod:`baobab.nav.ros`, and a ``BasicNavigator()`` it builds without arguments uses the world,
start, seed and pacing given here (:mod:`baobab.nav.defaults`).

Exit status, as Python's own for a script:

* 0 when it falls off its end or calls ``exit()`` / ``sys.exit()`` with nothing or ``None``;
* ``n`` for ``exit(n)``; 1 for ``exit("message")``, the message printed on standard error;
* 1 for an exception: the script's traceback (from its own first frame) on standard error;
* 130 when interrupted (``KeyboardInterrupt``);
* 2 for a script that cannot be read or does not compile, and for a located input error
  (:class:`~baobab.sim.errors.SourceError`, such as an unknown world) raised while it runs:
  one ``path:line:col: message`` line, no traceback.

Each run happens in a copy of the caller's ``contextvars`` context and inside
:func:`~baobab.nav.ros.ros_shims`, so defaults, sim-time sources, rclpy state and the modules
the script loaded from its own folder do not leak into the next run. The script's
``time.sleep`` advances sim time once it has a navigator, and, unless ``realtime`` is set,
``time.time`` and ``time.monotonic`` read sim time (:mod:`baobab.nav.script_time`);
``rclpy.spin_once(timeout_sec=...)``, ``Rate.sleep`` and a clock's ``sleep_for`` advance sim
time in any case (:mod:`baobab.nav.navigator_time`).
"""

from __future__ import annotations

import contextvars
import runpy
import sys
import traceback
from collections.abc import Callable, Mapping, Sequence
from contextlib import ExitStack
from pathlib import Path
from types import TracebackType
from typing import Any

from baobab.nav.defaults import use_navigator_defaults
from baobab.nav.ros import ros_shims
from baobab.nav.ros.script_files import ScriptError, check_script
from baobab.nav.script_time import script_time
from baobab.sim.errors import SourceError

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_INVALID = 2
EXIT_INTERRUPTED = 130

__all__ = ["ScriptError", "check_script", "run_nav2_script"]


def run_nav2_script(
    path: Path | str,
    *,
    navigator_defaults: Mapping[str, Any] | None = None,
    argv: Sequence[str] = (),
) -> int:
    """Run the Python script at ``path`` as ``__main__`` with the ROS shims installed.

    Args:
        path: the script file.
        navigator_defaults: keyword arguments for
            :func:`~baobab.nav.defaults.use_navigator_defaults` (``world``, ``start``,
            ``seed``, ``realtime``); unknown keys raise ``TypeError``.
        argv: the script's command-line arguments after its own path.

    Returns:
        The exit status (see the module docstring). Errors are reported on standard error,
        never raised, except ``TypeError`` for bad ``navigator_defaults``.
    """
    script = Path(path)
    try:
        check_script(script)
    except ScriptError as exc:
        print(exc, file=sys.stderr)
        return EXIT_INVALID
    return contextvars.copy_context().run(
        _run_isolated, script, dict(navigator_defaults or {}), [str(script), *argv]
    )


def _run_isolated(script: Path, defaults: dict[str, Any], argv: list[str]) -> int:
    folder = script.resolve().parent
    saved_argv, saved_path = sys.argv, list(sys.path)
    modules_before = set(sys.modules)
    sys.argv = argv
    sys.path.insert(0, str(folder))
    try:
        with ExitStack() as stack:
            stack.enter_context(ros_shims())
            stack.enter_context(use_navigator_defaults(**defaults))
            stack.enter_context(script_time(wall_clock=bool(defaults.get("realtime", False))))
            status = _guarded(script, lambda: runpy.run_path(str(script), run_name="__main__"))
            cleanup = _guarded(script, _shut_down_ros)
    finally:
        sys.argv = saved_argv
        sys.path[:] = saved_path
        _forget_script_modules(folder, modules_before)
    return status if status != EXIT_OK else cleanup


def _shut_down_ros() -> None:
    """Shut rclpy down if the script left it up, destroying its nodes (and navigators)."""
    from baobab.nav.ros import rclpy

    rclpy.try_shutdown()


def _guarded(script: Path, action: Callable[[], object]) -> int:
    """Run ``action`` and turn its ending into an exit status, reporting as Python does."""
    try:
        action()
    except SystemExit as exc:
        return _exit_status(exc.code)
    except SourceError as exc:  # a located user-input mistake, such as an unknown world
        sys.stdout.flush()
        print(exc, file=sys.stderr)
        return EXIT_INVALID
    except KeyboardInterrupt:
        sys.stdout.flush()
        print(f"{script}: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:
        sys.stdout.flush()
        traceback.print_exception(
            type(exc), exc, _from_script_frames(exc.__traceback__, script), file=sys.stderr
        )
        return EXIT_FAILED
    return EXIT_OK


def _exit_status(code: object) -> int:
    if code is None:
        return EXIT_OK
    if isinstance(code, int):
        return int(code)
    sys.stdout.flush()
    print(code, file=sys.stderr)
    return EXIT_FAILED


def _from_script_frames(tb: TracebackType | None, script: Path) -> TracebackType | None:
    """The traceback from the script's first frame on, without the runner's and runpy's."""
    start = tb
    while start is not None and start.tb_frame.f_code.co_filename != str(script):
        start = start.tb_next
    return tb if start is None else start


def _forget_script_modules(folder: Path, modules_before: set[str]) -> None:
    """Drop modules the script imported from its own folder, so the next run loads its own."""
    for name in set(sys.modules) - modules_before:
        origin = getattr(sys.modules[name], "__file__", None)
        if origin is None:
            continue
        top = name.partition(".")[0]
        origin_path = Path(origin).resolve()
        if origin_path == folder / f"{top}.py" or folder / top in origin_path.parents:
            del sys.modules[name]
