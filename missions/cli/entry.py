"""The ``baobab`` console script: signals and streams are set up before anything else loads.

This module's first statements make SIGINT, SIGTERM and SIGHUP end the process at once and
quietly with ``128 + signal`` (:mod:`baobab.missions.cli.interrupts`), so a Ctrl-C while the
command is still starting gives exit 130 and no traceback. Then the standard streams are made
safe (:mod:`baobab.missions.cli.streams`), and only then the command line
(:mod:`baobab.missions.cli.command_line`) is imported and run; a command that must tidy up on
the way out
(or ``baobab run``, once its run starts) handles the signals its own way.

When the command is done, the process leaves at once (:func:`_leave`): the interpreter's own
teardown resets the signal handlers to the system's defaults, and a SIGTERM in that last
fraction of a second would kill the process instead of ending it with exit 143.
"""

from __future__ import annotations

import os
import signal


def _exit_during_start_up(signum: int, _frame: object) -> None:
    os._exit(128 + signum)  # nothing written yet: nothing to flush


# The process's first statements, before any other import (those take a few milliseconds).
for _signum in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
    signal.signal(_signum, _exit_during_start_up)

import contextlib  # noqa: E402
import sys  # noqa: E402
from typing import NoReturn  # noqa: E402

from baobab.missions.cli.interrupts import (  # noqa: E402
    HANDLED,
    exit_code_for,
    exit_on_signals,
    exits_at_once,
)
from baobab.missions.run.exit_codes import EXIT_NOT_INTENDED, EXIT_OK  # noqa: E402

exit_on_signals()


def main() -> int:
    """Run the ``baobab`` command line on ``sys.argv``; returns (or exits with) the exit code."""
    from baobab.missions.cli.streams import guard_standard_streams

    guard_standard_streams()
    arguments = sys.argv[1:]
    running = _command(arguments) == "run"
    served = _run_in_server(arguments) if running else None
    if served is not None:
        _leave(served)
    from baobab.missions.cli.command_line import main as command_line

    try:
        code = command_line()
    except KeyboardInterrupt:
        code = exit_code_for(signal.SIGINT)
    if running and code in (EXIT_OK, EXIT_NOT_INTENDED):
        from baobab.missions.cli.run_client import start_server

        start_server()  # for the next run
    if not exits_at_once():  # a command that unwinds: the interpreter's teardown runs its
        exit_on_signals()  # clean-ups (atexit), and a signal meanwhile ends it at once
        return code
    _leave(code)


def _command(arguments: list[str]) -> str | None:
    """The subcommand: the first argument that is not an option."""
    return next((argument for argument in arguments if not argument.startswith("-")), None)


def _run_in_server(arguments: list[str]) -> int | None:
    """``baobab run`` in the run server (:mod:`baobab.missions.cli.run_client`), if one serves."""
    from baobab.missions.cli.run_client import run_in_server

    return run_in_server(arguments)


def _leave(code: int) -> NoReturn:
    """Flush the streams and exit with ``code``, or ``128 + signal`` if one came meanwhile."""
    signal.pthread_sigmask(signal.SIG_BLOCK, HANDLED)
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    pending = sorted(signal.sigpending() & set(HANDLED))
    os._exit(exit_code_for(pending[0]) if pending else code)
