"""The arm's 1 kHz step inside MuJoCo's own step: a compiled ``mjcb_control`` callback.

A Python callback at every 1 ms physics step costs more than the physics itself (the
scheduler, the call, and the caches it evicts). MuJoCo calls ``mjcb_control`` inside every
``mj_forward`` (so inside every ``mj_step``), after the positions and velocities are known and
before the actuator forces are computed: exactly where a controller belongs. This module
installs one compiled C callback (a numba ``cfunc``, called without the GIL) that runs
:func:`~baobab.robots.panda.arm_kernel.arm_loop_step` for every MjData an
:class:`~baobab.robots.panda.arm_server.ArmServer` drives, so ``mj_step(model, data, n)``
advances n steps of controlled physics without returning to Python.

How the callback finds its arm: the model reserves :data:`USERDATA_SLOTS` entries of
``mjData.userdata`` (``MjSpec.nuserdata``); :func:`attach` writes a marker, the MjData's own
address and the address of the server's :data:`~baobab.robots.panda.arm_kernel.ARM_LOOP`
record there. The callback reads them with ``mj_getState`` (no knowledge of MuJoCo's struct
layout needed) and acts only on the MjData whose address matches, so a state copied into
another MjData is ignored. :func:`detach` clears the slots; the server detaches when it is
collected, before its records are freed.

The callback runs once per physics time: a ``mj_forward`` at the time of the next step (after
editing the state by hand) takes that step's control, and the step reuses it.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any, cast

import llvmlite.binding
import mujoco
import numba
import numpy as np
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from baobab.robots.panda.arm_kernel import ARM_LOOP, arm_loop_step
from baobab.robots.panda.errors import PandaSceneError
from baobab.robots.panda.impedance_law import CONTROLLER

USERDATA_SLOTS = 3
"""Entries of ``mjData.userdata`` the arm's scene reserves: marker, MjData address, record."""

_MARKER = 2.0**33 + 0.125
"""First userdata entry of an attached MjData: a value no one writes by chance."""
_STATE_TIME = int(mujoco.mjtState.mjSTATE_TIME)
_STATE_USERDATA = int(mujoco.mjtState.mjSTATE_USERDATA)
_LOOP_WORDS = ARM_LOOP.itemsize // 8
_CONTROLLER_WORDS = CONTROLLER.itemsize // 8


def _mujoco_library() -> str:
    folder = Path(mujoco.__file__).parent
    for pattern in ("libmujoco.so*", "libmujoco*.dylib", "mujoco.dll"):
        found = sorted(folder.glob(pattern))
        if found:
            return str(found[0])
    raise ImportError(f"MuJoCo's shared library is not in {folder}")  # pragma: no cover


# The callback calls MuJoCo's C API by symbol name: make libmujoco's symbols visible to the
# JIT linker (the bindings load the library privately).
llvmlite.binding.load_library_permanently(_mujoco_library())
_mj_get_state = cast(
    Callable[[Any, Any, Any, int], None],
    types.ExternalFunction(
        "mj_getState", types.void(types.voidptr, types.voidptr, types.voidptr, types.intc)
    ),
)
_mj_state_size = cast(
    Callable[[Any, int], int],
    types.ExternalFunction("mj_stateSize", types.intc(types.voidptr, types.intc)),
)


@intrinsic
def _pointer_intrinsic(typingctx: Any, address: Any) -> Any:  # pragma: no cover - compiled
    signature = types.voidptr(types.intp)

    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return builder.inttoptr(args[0], cgutils.voidptr_t)

    return signature, codegen


_pointer = cast(Callable[[Any], Any], _pointer_intrinsic)
"""The pointer at an integer address (compiled code only)."""


def _control_callback(model: int, data: int) -> None:  # pragma: no cover - compiled
    """``mjcb_control``: the arm's step, if ``data`` is attached (see the module docstring)."""
    m, d = _pointer(model), _pointer(data)
    if _mj_state_size(m, _STATE_USERDATA) != USERDATA_SLOTS:
        return
    slots = np.empty(USERDATA_SLOTS)
    _mj_get_state(m, d, _pointer(slots.ctypes.data), _STATE_USERDATA)
    if slots[0] != _MARKER or np.int64(slots[1]) != data:
        return
    loop = numba.carray(_pointer(np.int64(slots[2])), (_LOOP_WORDS,), np.float64)
    record = loop.view(ARM_LOOP)[0]
    time = np.empty(1)
    _mj_get_state(m, d, _pointer(time.ctypes.data), _STATE_TIME)
    if time[0] == record.last_time:  # a forward and a step at the same time: one step
        return
    record.last_time = time[0]
    record.physics_steps += 1
    if (record.physics_steps - 1) % record.period_steps != 0:
        return
    controller = numba.carray(_pointer(record.controller_address), (_CONTROLLER_WORDS,), np.float64)
    setpoints = numba.carray(
        _pointer(record.setpoints_address), (record.setpoints_rows, 7), np.float64
    )
    arm_loop_step(
        numba.carray(_pointer(record.qpos_address), (record.nq,), np.float64),
        numba.carray(_pointer(record.qvel_address), (record.nv,), np.float64),
        numba.carray(_pointer(record.ctrl_address), (record.nu,), np.float64),
        numba.carray(_pointer(record.sensordata_address), (record.nsensordata,), np.float64),
        setpoints,
        controller.view(CONTROLLER)[0],
        record,
    )


@functools.cache
def _installed_callback() -> Any:
    """Compile (or load from numba's cache) the callback once per process; return it."""
    compiled = numba.cfunc(types.void(types.intp, types.intp), cache=True, nogil=True)(
        _control_callback
    )
    return compiled.ctypes


def attach(data: mujoco.MjData, model: mujoco.MjModel, loop: np.ndarray) -> None:
    """Drive ``data`` with the arm loop ``loop`` (a one-element :data:`ARM_LOOP` array).

    Fills the record's MjData addresses, writes the userdata slots and installs the callback.
    ``loop`` and the arrays it points to (the controller's record, the set-points) must
    outlive the attachment (:func:`detach`).

    Raises:
        PandaSceneError: if the model does not reserve :data:`USERDATA_SLOTS` userdata
            entries, or integrates with RK4 (which evaluates the model four times a step).
    """
    if model.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4:
        raise PandaSceneError("the arm's control loop needs a one-evaluation integrator, not RK4")
    if model.nuserdata != USERDATA_SLOTS:
        raise PandaSceneError(
            f"the arm's control loop needs a model with nuserdata = {USERDATA_SLOTS} "
            f"(MjSpec.nuserdata), got {model.nuserdata}"
        )
    record = loop[0]
    for name in ("qpos", "qvel", "ctrl", "sensordata"):
        array = getattr(data, name)
        record[f"{name}_address"] = array.ctypes.data
    record["nq"], record["nv"] = model.nq, model.nv
    record["nu"], record["nsensordata"] = model.nu, model.nsensordata
    record["last_time"] = math.nan
    address = data._address
    data.userdata[:] = [_MARKER, float(address), float(loop.ctypes.data)]
    mujoco.set_mjcb_control(_installed_callback())


def detach(data: mujoco.MjData) -> None:
    """Stop driving ``data`` (idempotent)."""
    data.userdata[:] = 0.0
