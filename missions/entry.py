"""The ``baobab`` console script: signals and streams are set up before anything else loads.

This module's first statements make SIGINT, SIGTERM and SIGHUP end the process at once and
quietly with ``128 + signal`` (:mod:`baobab.missions.interrupts`), so a Ctrl-C while the
command is still starting gives exit 130 and no traceback. Then the standard streams are made
safe (:mod:`baobab.missions.streams`), and only then the command line
(:mod:`baobab.missions.cli`) is imported and run; a command that must tidy up on the way out
(or ``baobab run``, once its run starts) handles the signals its own way.
"""

from __future__ import annotations

import signal

from baobab.missions.interrupts import exit_code_for, exit_on_signals

exit_on_signals()


def main() -> int:
    """Run the ``baobab`` command line on ``sys.argv``; returns the exit code."""
    from baobab.missions.streams import guard_standard_streams

    guard_standard_streams()
    from baobab.missions.cli import main as command_line

    try:
        return command_line()
    except KeyboardInterrupt:
        return exit_code_for(signal.SIGINT)
    finally:
        exit_on_signals()
