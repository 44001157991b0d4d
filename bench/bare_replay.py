"""Bare ``mj_step`` of a mission's model, stepping the mission's own motion.

The baseline of "loop / bare ``mj_step``" (``bench/run.py --only missions``) must step what the
loop steps. A fresh MjData of the model is a robot at rest: its contacts settle and MuJoCo's
solver converges in under one iteration a step, while a driving robot's rolling contacts take
more (``mj_step`` of the cafe's Burger costs about 1.3x at rest). So the honest baseline
replays the run: :func:`record_controls` runs the mission once with the physics stepped one
step at a time, keeping the initial physics state and every step's actuator controls
(``data.ctrl`` after a step is the control that step applied; the robot's compiled base
controller sets it inside the step); :func:`replay` sets that initial state on a fresh MjData
and steps the same number of steps open loop, the controls fed inside MuJoCo's control
callback by a compiled kernel (as the robot's own controller is fed), so no Python runs
between steps. The replay is checked against the run: the final positions must agree
(:attr:`Controls.final_qpos`).
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass

import mujoco
import numba
import numpy as np

from baobab.sim import native_control, simulation
from baobab.sim.mujoco_native import mj_get_state, pointer
from baobab.sim.native_control import STATE_TIME
from baobab.sim.records import Record, record

REPLAY = np.dtype(
    [
        ("ctrl_address", np.int64),  # the MjData's ctrl (float64[nu])
        ("nu", np.int64),
        ("table_address", np.int64),  # float64[rows, nu]: row k is the control of step first + k
        ("rows", np.int64),
        ("first_step", np.int64),  # physics step of the first row
        ("physics_dt", np.float64),  # s
    ]
)
"""The replay kernel's record (all 8-byte)."""

_FULL = int(mujoco.mjtState.mjSTATE_FULLPHYSICS)


@dataclass
class Controls:
    """One run's motion: its initial physics state and the control of each step.

    Attributes:
        initial_state: ``mj_getState(FULLPHYSICS)`` before the first step.
        table: float64[steps, nu], the control each step applied.
        final_qpos: the positions after the last step (the replay must reach them).
    """

    initial_state: np.ndarray
    table: np.ndarray
    final_qpos: np.ndarray


@numba.njit(cache=True, nogil=True)
def _feed(replay: Record, step: int) -> None:
    row = step - replay.first_step
    if 0 <= row < replay.rows:
        ctrl = numba.carray(pointer(replay.ctrl_address), (replay.nu,), np.float64)
        table = numba.carray(pointer(replay.table_address), (replay.rows, replay.nu), np.float64)
        ctrl[:] = table[row]


def replay_kernel(model: int, data: int, address: int) -> None:  # pragma: no cover - compiled
    """``mjcb_control`` of the replayed MjData: the recorded control of the current step."""
    replay = numba.carray(pointer(address), (1,), REPLAY)
    now = np.empty(1)
    mj_get_state(pointer(model), pointer(data), pointer(now.ctypes.data), STATE_TIME)
    _feed(replay[0], int(np.rint(now[0] / replay[0].physics_dt)))


@functools.cache
def _kernel_address() -> int:
    return native_control.compile_kernel(replay_kernel)


def record_controls(run: object) -> Controls:
    """Call ``run()`` (a mission run in this process) with the physics stepped one step at a
    time, keeping the first simulation's initial state and each step's control."""
    real_step = simulation.mujoco.mj_step
    steps: list[np.ndarray] = []
    captured: dict[str, np.ndarray] = {}
    first_data: list[mujoco.MjData] = []

    def stepping(model: mujoco.MjModel, data: mujoco.MjData, nstep: int = 1) -> None:
        if not first_data:
            first_data.append(data)
            state = np.empty(mujoco.mj_stateSize(model, _FULL))
            mujoco.mj_getState(model, data, state, _FULL)
            captured["initial"] = state
        for _ in range(nstep):
            real_step(model, data)
            if data is first_data[0]:
                steps.append(data.ctrl.copy())
        if data is first_data[0]:
            captured["final"] = data.qpos.copy()

    simulation.mujoco.mj_step = stepping  # type: ignore[attr-defined]
    try:
        run()  # type: ignore[operator]
    finally:
        simulation.mujoco.mj_step = real_step  # type: ignore[attr-defined]
    return Controls(captured["initial"], np.array(steps), captured["final"])


def replay(model: mujoco.MjModel, controls: Controls) -> tuple[float, float]:
    """Step a fresh MjData of ``model`` through ``controls``: (wall s, largest final position
    difference against the run)."""
    data = mujoco.MjData(model)
    mujoco.mj_setState(model, data, controls.initial_state, _FULL)
    mujoco.mj_forward(model, data)
    table = np.ascontiguousarray(controls.table)
    dt = model.opt.timestep
    feeder = record(
        REPLAY,
        ctrl_address=data.ctrl.ctypes.data,
        nu=model.nu,
        table_address=table.ctypes.data,
        rows=len(table),
        first_step=round(data.time / dt),
        physics_dt=dt,
    )
    native_control.attach(data, model, _kernel_address(), feeder)
    try:
        began = time.perf_counter()
        mujoco.mj_step(model, data, len(table))
        wall = time.perf_counter() - began
    finally:
        native_control.detach(data)
    return wall, float(np.max(np.abs(data.qpos - controls.final_qpos)))


def resting(model: mujoco.MjModel, steps: int) -> float:
    """Wall seconds of ``steps`` steps of a fresh MjData of ``model``: the robot at rest."""
    data = mujoco.MjData(model)
    began = time.perf_counter()
    mujoco.mj_step(model, data, steps)
    return time.perf_counter() - began
