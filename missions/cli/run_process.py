"""``baobab run``'s run process, forked as soon as the command line says ``run``.

Loading the simulation stack (MuJoCo, numba and its compiler, py_trees, the robots and the
compiled control dispatcher) is most of a short run's wall time, and none of it depends on the
mission. So :func:`start_run_process` forks the run's process before this process even builds
its parser or imports the run command (pydantic, the mission language): the child loads the
stack (:func:`prepare_run_process`) on one core while this one parses the arguments, loads and
checks the mission and then loads the plotting stack on the other. A refused input, ``--help``
or a usage error ends the child unused
(:meth:`~baobab.missions.run.child_process.StartedChild.discard`).

This module imports only the standard library and :mod:`~baobab.missions.run.child_process`,
so the fork comes a few milliseconds after the interpreter's start.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from baobab.missions.run.child_process import StartedChild


def start_run_process() -> StartedChild | None:
    """Fork the run's process now; None where forking is not safe (the run then happens in the
    calling process, :func:`~baobab.missions.run.child_process.fork_is_safe`)."""
    from baobab.missions.run.child_process import fork_is_safe, start_child

    return start_child(prepare_run_process) if fork_is_safe() else None


def prepare_run_process() -> None:
    """What a run's process loads before it knows its mission: the run's modules (MuJoCo,
    py_trees, numba), the modules its request arrives in (the mission language, the run job)
    and the compiled control dispatcher every robot uses.

    With the cyclic garbage collector paused, then the loaded objects frozen
    (:func:`~baobab.missions.cli.startup.loading_modules`): the collector would otherwise walk
    them again and again while they are made, a tenth of this work.
    """
    from baobab.missions.cli.startup import loading_modules

    with loading_modules():
        import baobab.missions.cli.run_job
        import baobab.missions.run.runner  # noqa: F401  (both imported for their cost, now)
        from baobab.sim.native_control import load_dispatcher

        load_dispatcher()
