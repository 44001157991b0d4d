"""The floor under "loop / bare ``mj_step``": what the compiled work and the tree ticks alone cost.

Run: ``python bench/bench_loop_floor.py [MISSION]`` (default ``cafe_delivery``).

Issue 28 asks for the loop at most 1.5x bare ``mj_step`` of the same model replaying the run's
motion (``bench/run.py --only missions``). This bench asks what that leaves room for. It runs
the mission once to warm the kernels, then once under :mod:`cProfile` and reports per physics
step (us):

- the bare replay of the same motion (``bare_replay.py``), in the same process;
- the self time of each compiled kernel the navigation stack calls from Python (A*, the
  smoother's rounds, the costmap's ray tracing and window refresh, the lidar's caster, the
  pure-pursuit step, the clearance metric ...): the work Nav2's default rates ask for (1 Hz
  replanning, 5 Hz scans and local costmap, a 20 Hz controller), already compiled;
- ``mj_step`` as the loop calls it: in 20 Hz batches, between which Python and the kernels
  evict its caches, with the base's compiled controller inside.

The floor is what the loop would cost if no line of Python outside the kernels cost anything:
(bare + kernels) / bare, and (``mj_step`` in the loop + kernels) / bare. cProfile's own cost
per call is small for these (tens of calls per sim second) but included; treat the figures as
about +-5 %. The Python parts, the behaviour trees' ticks among them, are in
``bench/bench_loop_parts.py``.
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import sys

import bare_replay  # beside this script
from numba.core.dispatcher import Dispatcher

from baobab.missions.language.bundled_missions import resolve_mission
from baobab.missions.language.loader import load_mission
from baobab.missions.run.rig import build_rig
from baobab.missions.run.runner import run_mission


def _dispatcher(file: str, line: int, function: str) -> bool:
    """Whether the profiled function at ``file:line`` is a compiled numba dispatcher (numba
    reports a dispatcher's calls under its Python function's code)."""
    for module in list(sys.modules.values()):
        if getattr(module, "__file__", None) == file:
            found = getattr(module, function, None)
            if not isinstance(found, Dispatcher):
                return False
            code = found.py_func.__code__
            return code.co_filename == file and code.co_firstlineno == line
    return False


def measure(name: str) -> None:
    mission = load_mission(resolve_mission(name))
    run_mission(mission)
    profile = cProfile.Profile()
    profile.enable()
    record = run_mission(mission)
    profile.disable()
    controls = bare_replay.record_controls(lambda: run_mission(mission))
    model = build_rig(mission, mission.seed).sim.model
    bare, _ = bare_replay.replay(model, controls)
    steps = len(controls.table)
    per_step = 1e6 / steps
    stats = pstats.Stats(profile).stats  # type: ignore[attr-defined]
    kernels: list[tuple[float, str, int]] = []
    physics = 0.0
    for (file, line, function), (_cc, calls, own, _total, _callers) in stats.items():
        if function == "<built-in method mujoco._functions.mj_step>":
            physics += own
        elif _dispatcher(file, line, function):
            kernels.append((own, f"{os.path.basename(file)}:{function}", calls))
    kernels.sort(reverse=True)
    kernel_total = sum(own for own, _, _ in kernels if own * per_step >= 0.01)
    print(f"{name}: {record.outcome.sim_time:.1f} s of sim, {steps} physics steps")
    print(f"  loop (under cProfile)            {record.wall_time * per_step:6.2f} us/step")
    print(f"  bare mj_step replaying the run   {bare * per_step:6.2f} us/step")
    print("  compiled kernels called from Python (self time):")
    for own, label, calls in kernels:
        if own * per_step >= 0.01:
            print(f"    {label:44s} {own * per_step:5.2f} us/step  ({calls} calls)")
    print(f"    {'all':44s} {kernel_total * per_step:5.2f} us/step")
    print(f"  mj_step in the loop              {physics * per_step:6.2f} us/step")
    print(f"  floor: kernels / bare                        {1 + kernel_total / bare:5.2f}")
    print(f"  floor: (mj_step in the loop + kernels) / bare {(physics + kernel_total) / bare:5.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mission", nargs="?", default="cafe_delivery")
    measure(parser.parse_args().mission)


if __name__ == "__main__":
    main()
