"""Cost of the Panda's 1 kHz control step, and the speed of a whole pick-and-place.

Run: ``python bench/bench_panda.py [--seeds 3] [--steps 20000] [--json]``. Reports:

- microseconds per impedance step (``CartesianImpedanceController.compute_torque``: the chain's
  kinematics and dynamics, the law, saturation and reference filter, one compiled call),
  called back to back from Python on a fixed state: median and best of ``--repeats`` batches;
- the arm's whole 1 kHz loop (the same step plus reading MjData, the set-point, the gripper
  servo and the task checks) where it runs, in MuJoCo's ``mjcb_control`` during ``mj_step``:
  CPU time per physics step with the loop attached minus detached, from the same state
  (``mj_step`` alone is the detached figure);
- for ``--seeds`` seeded picks: sim time, wall and CPU time, their ratios (the real-time
  factor) and the mean ``mj_step`` time (which now includes the control) from MuJoCo's own
  wall-clock step timer.

The machine is shared: wall-clock figures move by +-30 % between runs; CPU time is steadier.
The first call compiles the numba kernels (or loads them from numba's cache); the benchmarks
warm them up before they measure.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from collections.abc import Callable

import mujoco
import numpy as np

from baobab.robots.panda import native_loop
from baobab.robots.panda.impedance import CartesianImpedanceController
from baobab.robots.panda.model import HOME_CONFIGURATION, PandaModel
from baobab.robots.panda.pick import pick_and_place
from baobab.robots.panda.scene import build_panda_sim, place_target


def _time_calls(call: Callable[[], object], steps: int, repeats: int) -> dict[str, float]:
    for _ in range(100):  # compile (or load) the kernels before timing
        call()
    batch = steps // repeats
    timings = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(batch):
            call()
        timings.append((time.perf_counter() - start) / batch * 1e6)
    return {"median_us": statistics.median(timings), "best_us": min(timings)}


def bench_control_step(steps: int = 20000, repeats: int = 5) -> dict[str, float]:
    """Microseconds per ``compute_torque`` on a fixed state, back to back."""
    controller = CartesianImpedanceController(PandaModel())
    q = np.r_[HOME_CONFIGURATION, 0.04, 0.04]
    v = np.r_[np.full(7, 0.1), 0.0, 0.0]
    controller.reset(q)
    position, quaternion = controller.target
    controller.set_target(position + [0.05, -0.02, 0.03], quaternion)
    return _time_calls(lambda: controller.compute_torque(q, v), steps, repeats)


def bench_loop_in_simulation(steps: int = 200, repeats: int = 20) -> dict[str, float]:
    """CPU microseconds per physics step: mj_step with the native arm loop, and without."""
    sim, _arm = build_panda_sim(seed=0)
    model, data = sim.model, sim.data
    sim.step_for(0.1)
    spec = mujoco.mjtState.mjSTATE_INTEGRATION
    state = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, state, spec)

    def cpu_per_step(attached: bool) -> float:
        best = float("inf")
        for _ in range(repeats):
            mujoco.mj_setState(model, data, state, spec)  # userdata too: attached again
            if not attached:
                native_loop.detach(data)
            start = time.process_time()
            mujoco.mj_step(model, data, steps)
            best = min(best, (time.process_time() - start) / steps * 1e6)
        mujoco.mj_setState(model, data, state, spec)
        return best

    physics = min(cpu_per_step(False) for _ in range(2))
    both = min(cpu_per_step(True) for _ in range(2))
    return {"physics_us": physics, "control_in_step_us": both - physics}


def bench_pick(seeds: int = 3) -> list[dict[str, float]]:
    """Sim time, wall time and real-time factor of seeded picks."""
    results = []
    for seed in range(seeds):
        sim, arm = build_panda_sim(seed=seed)
        step_timer = sim.data.timer[mujoco.mjtTimer.mjTIMER_STEP]
        physics = step_timer.duration
        wall, cpu = time.perf_counter(), time.process_time()
        report = pick_and_place(sim, arm, place_target(sim)[:2])
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        physics = step_timer.duration - physics
        results.append(
            {
                "seed": seed,
                "succeeded": report.succeeded,
                "sim_time_s": report.sim_time,
                "wall_time_s": wall,
                "cpu_time_s": cpu,
                "real_time_factor": report.sim_time / wall,
                "cpu_real_time_factor": report.sim_time / cpu,
                "mj_step_us": physics / (report.sim_time / sim.physics_dt) * 1e6,
            }
        )
    return results


def main() -> None:
    """Run the benchmarks and print a table (or JSON)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--steps", type=int, default=20000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    step = bench_control_step(args.steps, args.repeats)
    in_sim = bench_loop_in_simulation()
    picks = bench_pick(args.seeds)
    if args.json:
        figures = {"control_step": step, "in_simulation": in_sim, "picks": picks}
        print(json.dumps(figures, indent=2))
        return
    print(
        f"impedance step (back to back): median {step['median_us']:.1f} us, "
        f"best {step['best_us']:.1f} us"
    )
    print(
        f"in mj_step (CPU): arm loop {in_sim['control_in_step_us']:.1f} us, "
        f"physics {in_sim['physics_us']:.1f} us"
    )
    for pick in picks:
        print(
            f"pick seed {pick['seed']}: {'ok' if pick['succeeded'] else 'FAILED'}, "
            f"sim {pick['sim_time_s']:.2f} s, wall {pick['wall_time_s']:.2f} s, "
            f"cpu {pick['cpu_time_s']:.2f} s, sim/wall {pick['real_time_factor']:.2f}, "
            f"sim/cpu {pick['cpu_real_time_factor']:.2f}, "
            f"mj_step {pick['mj_step_us']:.1f} us (wall, with the arm loop)"
        )


if __name__ == "__main__":
    main()
