"""Imported by the campaign's forkserver: numba's compiler and the control dispatcher, once.

A local campaign runs each run in a fresh process forked from a forkserver that imported the
run's modules first (:func:`~baobab.missions.campaigns.executors.preload_modules`). Importing
modules is all a forkserver can be asked to do, so this module's import does the rest of what
every run would otherwise do on its own: numba loads its compiler's registries (and with them
SciPy's linear algebra) the first time a process loads a compiled kernel, about half a second,
and :func:`~baobab.sim.native_control.load_dispatcher` is that first time.
"""

from __future__ import annotations

from baobab.sim.native_control import load_dispatcher

load_dispatcher()
