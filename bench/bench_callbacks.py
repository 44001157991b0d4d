"""Where a mission's time goes: CPU time per sim second of each periodic callback and of physics.

Run: ``python bench/bench_callbacks.py [MISSION ...]`` (default ``cafe_delivery``). Each mission
runs once to warm the compiled kernels' caches, then once measured: every callback registered
with :meth:`Simulation.every` is timed (process CPU time), and so is every ``mj_step`` batch.
What is left is the run loop itself: the mission tree, the trace, events and fault monitors.
The timers add about a microsecond per call, so the parts sum to a little more than a plain
run takes.
"""

from __future__ import annotations

import argparse
import collections
import time
from collections.abc import Callable
from typing import Any

import mujoco

from baobab.missions.language.bundled_missions import resolve_mission
from baobab.missions.language.loader import load_mission
from baobab.missions.run.runner import run_mission
from baobab.sim import simulation

_costs: collections.defaultdict[str, float] = collections.defaultdict(float)
_calls: collections.Counter[str] = collections.Counter()


def _timed(name: str, work: Callable[..., object]) -> Callable[..., object]:
    def run(*args: object) -> object:
        began = time.process_time()
        try:
            return work(*args)
        finally:
            _costs[name] += time.process_time() - began
            _calls[name] += 1

    return run


def wrap_callbacks(wrap: Callable[[str, Callable[..., Any]], Callable[..., Any]]) -> None:
    """From now on, pass every periodic callback a simulation schedules
    (:meth:`Simulation.every`, by its name) and every ``mj_step`` batch through
    ``wrap(name, work)``."""
    every = simulation.Simulation.every

    def wrapped_every(
        self: simulation.Simulation,
        period: float,
        callback: simulation.Callback,
        *,
        name: str,
        first_call: float | None = None,
    ) -> simulation.PeriodicHandle:
        return every(self, period, wrap(name, callback), name=name, first_call=first_call)

    simulation.Simulation.every = wrapped_every  # type: ignore[method-assign]
    simulation.mujoco.mj_step = wrap("physics (mj_step)", mujoco.mj_step)  # type: ignore[attr-defined]


def measure(name: str) -> None:
    """Run ``name`` twice and print the second run's split per sim second."""
    mission = load_mission(resolve_mission(name))
    run_mission(mission)
    _costs.clear()
    _calls.clear()
    began = time.process_time()
    record = run_mission(mission)
    total = time.process_time() - began
    sim_time = float(record.outcome.sim_time)
    print(f"{name}: {sim_time:.1f} s of sim, {1000 * total / sim_time:.2f} ms CPU per sim s")
    for part, cost in sorted(_costs.items(), key=lambda item: -item[1]):
        per_call = 1e6 * cost / _calls[part]
        rate = _calls[part] / sim_time
        share = 1000 * cost / sim_time
        print(f"  {part:28s} {share:6.2f} ms/sim s  {per_call:7.1f} us x {rate:6.1f}/s")
    rest = total - sum(_costs.values())
    print(f"  {'run loop (the rest)':28s} {1000 * rest / sim_time:6.2f} ms/sim s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("missions", nargs="*", default=["cafe_delivery"])
    args = parser.parse_args()
    wrap_callbacks(_timed)
    for name in args.missions:
        measure(name)


if __name__ == "__main__":
    main()
