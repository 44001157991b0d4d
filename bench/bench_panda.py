"""Cost of the Panda's 1 kHz control step, and the speed of a whole pick-and-place.

Run: ``python bench/bench_panda.py [--seeds 3] [--steps 20000] [--json]``. Reports:

- microseconds per control step (Pinocchio kinematics and dynamics + the impedance law +
  saturation + reference filter), called back to back on a fixed state: median and best of
  ``--repeats`` batches;
- the same step inside the simulation loop (the arm server's 1 kHz callback between physics
  steps, whose caches it shares): CPU time of (callback + mj_step) minus mj_step alone;
- for ``--seeds`` seeded picks: sim time, wall and CPU time, their ratios (the real-time
  factor) and the mean ``mj_step`` time from MuJoCo's own (wall-clock) step timer.

The machine is shared: wall-clock figures move by +-30 % between runs; CPU time is steadier.
The first call compiles the numba kernels (or loads them from numba's cache); the step
benchmark warms them up before it measures.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

import mujoco
import numpy as np

from baobab.robots.panda.impedance import CartesianImpedanceController
from baobab.robots.panda.model import HOME_CONFIGURATION, PandaModel
from baobab.robots.panda.pick import pick_and_place
from baobab.robots.panda.scene import build_panda_sim, place_target


def bench_control_step(steps: int = 20000, repeats: int = 5) -> dict[str, float]:
    """Microseconds per ``compute_torque`` on a fixed state, back to back."""
    controller = CartesianImpedanceController(PandaModel())
    q = np.r_[HOME_CONFIGURATION, 0.04, 0.04]
    v = np.r_[np.full(7, 0.1), 0.0, 0.0]
    controller.reset(q)
    position, quaternion = controller.target
    controller.set_target(position + [0.05, -0.02, 0.03], quaternion)
    for _ in range(100):  # compile (or load) the kernels before timing
        controller.compute_torque(q, v)
    batch = steps // repeats
    timings = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(batch):
            controller.compute_torque(q, v)
        timings.append((time.perf_counter() - start) / batch * 1e6)
    return {"median_us": statistics.median(timings), "best_us": min(timings)}


def bench_control_in_loop(steps: int = 5000) -> dict[str, float]:
    """CPU microseconds of the arm server's control callback inside the physics loop."""
    sim, arm = build_panda_sim(seed=0)
    model, data = sim.model, sim.data

    def cpu_per_step(control: bool) -> float:
        start = time.process_time()
        for _ in range(steps):
            if control:
                arm._control(sim.time)  # the callback exactly as Simulation calls it
            mujoco.mj_step(model, data)
        return (time.process_time() - start) / steps * 1e6

    physics = min(cpu_per_step(False) for _ in range(2))
    both = min(cpu_per_step(True) for _ in range(2))
    return {"physics_us": physics, "control_callback_us": both - physics}


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
    loop = bench_control_in_loop()
    picks = bench_pick(args.seeds)
    if args.json:
        print(json.dumps({"control_step": step, "control_in_loop": loop, "picks": picks}, indent=2))
        return
    print(
        f"control step (back to back): median {step['median_us']:.1f} us, "
        f"best {step['best_us']:.1f} us"
    )
    print(
        f"in the sim loop (CPU): control callback {loop['control_callback_us']:.1f} us, "
        f"mj_step {loop['physics_us']:.1f} us"
    )
    for pick in picks:
        print(
            f"pick seed {pick['seed']}: {'ok' if pick['succeeded'] else 'FAILED'}, "
            f"sim {pick['sim_time_s']:.2f} s, wall {pick['wall_time_s']:.2f} s, "
            f"cpu {pick['cpu_time_s']:.2f} s, sim/wall {pick['real_time_factor']:.2f}, "
            f"sim/cpu {pick['cpu_real_time_factor']:.2f}, "
            f"mj_step {pick['mj_step_us']:.1f} us (wall)"
        )


if __name__ == "__main__":
    main()
