"""The arm's 1 kHz step inside MuJoCo's own step: a compiled kernel for ``mjcb_control``.

:mod:`baobab.sim.native_control` runs a compiled kernel inside every ``mj_forward`` of an
attached MjData (so inside every ``mj_step``), after the positions and velocities are known
and before the actuator forces are computed: exactly where a controller belongs. The arm's
kernel runs :func:`~baobab.robots.panda.arm_kernel.arm_loop_step` for the MjData an
:class:`~baobab.robots.panda.arm_server.ArmServer` drives, so ``mj_step(model, data, n)``
advances n steps of controlled physics without returning to Python. Its record is the
server's :data:`~baobab.robots.panda.arm_kernel.ARM_LOOP`.

The kernel runs once per physics time: a ``mj_forward`` at the time of the next step (after
editing the state by hand) takes that step's control, and the step reuses it.
"""

from __future__ import annotations

import functools
import math

import mujoco
import numba
import numpy as np

from baobab.robots.panda.arm_kernel import ARM_LOOP, arm_loop_step
from baobab.robots.panda.errors import PandaSceneError
from baobab.robots.panda.impedance_law import CONTROLLER
from baobab.sim import native_control
from baobab.sim.errors import SimulationError
from baobab.sim.mujoco_native import mj_get_state, pointer
from baobab.sim.native_control import STATE_TIME

USERDATA_SLOTS = native_control.USERDATA_SLOTS
"""Entries of ``mjData.userdata`` the arm's scene reserves (:mod:`baobab.sim.native_control`)."""

_LOOP_WORDS = ARM_LOOP.itemsize // 8
_CONTROLLER_WORDS = CONTROLLER.itemsize // 8


def _arm_kernel(model: int, data: int, loop_address: int) -> None:  # pragma: no cover - compiled
    """The arm's step for ``data``, whose :data:`ARM_LOOP` record is at ``loop_address``."""
    m, d = pointer(model), pointer(data)
    loop = numba.carray(pointer(loop_address), (_LOOP_WORDS,), np.float64)
    record = loop.view(ARM_LOOP)[0]
    time = np.empty(1)
    mj_get_state(m, d, pointer(time.ctypes.data), STATE_TIME)
    if time[0] == record.last_time:  # a forward and a step at the same time: one step
        return
    record.last_time = time[0]
    record.physics_steps += 1
    if (record.physics_steps - 1) % record.period_steps != 0:
        return
    controller = numba.carray(pointer(record.controller_address), (_CONTROLLER_WORDS,), np.float64)
    setpoints = numba.carray(
        pointer(record.setpoints_address), (record.setpoints_rows, 7), np.float64
    )
    arm_loop_step(
        numba.carray(pointer(record.qpos_address), (record.nq,), np.float64),
        numba.carray(pointer(record.qvel_address), (record.nv,), np.float64),
        numba.carray(pointer(record.ctrl_address), (record.nu,), np.float64),
        numba.carray(pointer(record.sensordata_address), (record.nsensordata,), np.float64),
        setpoints,
        controller.view(CONTROLLER)[0],
        record,
    )


@functools.cache
def _kernel_address() -> int:
    """Compile (or load from numba's cache) the arm's kernel once per process."""
    return native_control.compile_kernel(_arm_kernel)


def attach(data: mujoco.MjData, model: mujoco.MjModel, loop: np.ndarray) -> None:
    """Drive ``data`` with the arm loop ``loop`` (a one-element :data:`ARM_LOOP` array).

    Fills the record's MjData addresses, writes the userdata slots and installs the callback.
    ``loop`` and the arrays it points to (the controller's record, the set-points) must
    outlive the attachment (:func:`detach`).

    Raises:
        PandaSceneError: if the model does not reserve :data:`USERDATA_SLOTS` userdata
            entries, or integrates with RK4 (which evaluates the model four times a step).
    """
    record = loop[0]
    for name in ("qpos", "qvel", "ctrl", "sensordata"):
        record[f"{name}_address"] = getattr(data, name).ctypes.data
    record["nq"], record["nv"] = model.nq, model.nv
    record["nu"], record["nsensordata"] = model.nu, model.nsensordata
    record["last_time"] = math.nan
    try:
        native_control.attach(data, model, _kernel_address(), loop)
    except SimulationError as error:
        raise PandaSceneError(f"the arm's control loop: {error}") from None


def detach(data: mujoco.MjData) -> None:
    """Stop driving ``data`` (idempotent)."""
    native_control.detach(data)
