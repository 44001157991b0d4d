"""Where the time of one ``baobab run`` goes: each phase of both processes, wall and CPU.

    T0=$(date +%s.%N) python bench/bench_run_phases.py run walls_go_to_goal --json --out /tmp/r

Runs the ``baobab`` command line like the console script (which leaves with ``os._exit``) with
its phases wrapped: each line on stderr is ``[pid] wall <s since T0> cpu <this process's CPU
s> > or < phase``. The run's process is the pid that prepares and simulates. On a loaded
machine the wall column stretches; the CPU column is what each phase costs.
"""

from __future__ import annotations

import builtins
import functools
import importlib
import os
import sys
import time
from collections.abc import Callable
from typing import Any

T0 = float(os.environ.get("T0", time.time()))

WRAPPED = {
    "baobab.missions.cli.run_process": ["prepare_run_process", "start_run_process"],
    "baobab.missions.cli.run_command": ["load_mission", "_load_plotting", "save_run", "_report"],
    "baobab.missions.cli.run_job": ["simulate"],
}
"""The phases: module, then its functions, wrapped once the module is imported."""


def mark(what: str) -> None:
    """One line: pid, wall seconds since T0, this process's CPU seconds, what."""
    wall, cpu = time.time() - T0, time.process_time()
    sys.stderr.write(f"[{os.getpid()}] wall {wall:6.3f} cpu {cpu:6.3f} {what}\n")
    sys.stderr.flush()


def wrap(module: Any, name: str) -> None:
    """Mark the start and end of ``module.name`` each time it runs."""
    function: Callable[..., Any] = getattr(module, name)

    @functools.wraps(function)
    def marked(*args: Any, **kwargs: Any) -> Any:
        mark(f"> {name}")
        try:
            return function(*args, **kwargs)
        finally:
            mark(f"< {name}")

    setattr(module, name, marked)


def main() -> None:
    """Run the command line given on ours, marking its phases."""
    mark("interpreter started")
    from baobab.missions.cli import command_line

    mark("command line imported")
    original_import = builtins.__import__
    done: set[str] = set()

    def importing(name: str, *args: Any, **kwargs: Any) -> Any:
        module = original_import(name, *args, **kwargs)
        if name in WRAPPED and name not in done:  # a whole module: its functions exist
            done.add(name)
            for function in WRAPPED[name]:
                wrap(importlib.import_module(name), function)
        return module

    builtins.__import__ = importing
    for name in WRAPPED:
        if name in sys.modules:
            importing(name)
    code = command_line.main(sys.argv[1:])
    mark(f"done, exit {code}")
    sys.stdout.flush()
    os._exit(code)


if __name__ == "__main__":
    main()
