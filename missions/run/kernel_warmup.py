"""Compile baobab's kernels into numba's disk cache ahead of time, by running missions once.

A kernel is compiled the first time a run calls it with its argument types, and numba keeps
the machine code in ``__pycache__`` beside the kernel's module (keyed by the module's text,
numba's version and this CPU). Building baobab's wheel (``pip install .``, see ``setup.py``)
runs this module on the modules it is about to package, so the installed package carries its
kernels compiled for this machine and the first run loads them instead of compiling them
(about 20 s of CPU time). The bundled missions reach every kernel with exactly the types a
run passes; a kernel they do not reach is compiled by the first run that needs it, as before.

    python -m baobab.missions.run.kernel_warmup                 # every bundled mission
    python -m baobab.missions.run.kernel_warmup --arm           # the arm's (--mobile: the rest)
    python -m baobab.missions.run.kernel_warmup cafe_delivery   # only these
"""

from __future__ import annotations

import sys
from collections.abc import Sequence

from baobab.missions.language.bundled_missions import bundled_missions, resolve_mission
from baobab.missions.language.loader import load_mission


def missions_by_base() -> tuple[list[str], list[str]]:
    """The bundled missions of mobile robots, and those of arms (their robot's registry entry
    says which): the two share no kernel module, so they warm in two processes."""
    mobile: list[str] = []
    arm: list[str] = []
    for name in bundled_missions():
        robot = load_mission(resolve_mission(name)).robot
        (mobile if robot.mobile else arm).append(name)
    return mobile, arm


def warm_kernels(names: Sequence[str]) -> list[str]:
    """Run each bundled mission ``names`` once (no run folder); return how each ended.

    Raises:
        BaobabError: a name is not a bundled mission, or its run cannot be built.
    """
    from baobab.missions.run.runner import run_mission

    outcomes = []
    for name in names:
        record = run_mission(load_mission(resolve_mission(name)))
        outcomes.append(f"{name}: {record.outcome.result} after {record.outcome.sim_time:.1f} s")
    return outcomes


def main(argv: Sequence[str] | None = None) -> int:
    """Warm the kernels of the named bundled missions (default: all); print how each ended."""
    names = list(sys.argv[1:] if argv is None else argv) or list(bundled_missions())
    mobile, arm = missions_by_base()
    groups = {"--arm": arm, "--mobile": mobile}
    names = [name for given in names for name in groups.get(given, [given])]
    for line in warm_kernels(names):
        print(line, flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
