"""How a ``baobab`` command ends: its exit codes, by name.

A signal that ends a command gives ``128 + signal`` (:mod:`baobab.missions.cli.interrupts`):
130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP.
"""

from __future__ import annotations

EXIT_OK = 0
"""The command did what it was asked; a run turned out as intended."""
EXIT_NOT_INTENDED = 1
"""A run (or a campaign's run) ran but did not turn out as intended."""
EXIT_INVALID = 2
"""Invalid input: a located message on standard error, nothing run, nothing written."""
EXIT_NOT_SAVED = 3
"""The run ran, but neither its run folder nor the fallback folder could be written."""
EXIT_INTERRUPTED = 130
"""SIGINT (Ctrl-C) ended it: ``128 + 2``."""
