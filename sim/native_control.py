"""Compiled controllers inside MuJoCo's own step: one process-wide ``mjcb_control``.

A Python callback at every physics step (or every other one) costs more than the physics: the
scheduler, the call, and the caches it evicts. MuJoCo calls ``mjcb_control`` inside every
``mj_forward`` (so inside every ``mj_step``), after positions, velocities and position-stage
sensors are known and before actuator forces are computed: where a controller belongs. This
module installs one compiled C callback (a numba ``cfunc``, called without the GIL) that hands
each MjData to the compiled *kernel* attached to it, so ``mj_step(model, data, n)`` advances n
steps of controlled physics without returning to Python.

How the callback finds a kernel: the model reserves :data:`USERDATA_SLOTS` entries of
``mjData.userdata`` (``MjSpec.nuserdata``); :func:`attach` writes a marker, the MjData's own
address, the kernel's address and the address of the kernel's record there. The callback
reads them with ``mj_getState`` (no knowledge of MuJoCo's struct layout needed) and acts only
on the MjData whose address matches, so a state copied into another MjData is ignored. It
calls the kernel as ``kernel(model, data, record)``, three addresses. A kernel is a numba
``cfunc`` of signature :data:`KERNEL_SIGNATURE`; it reads MjData through the addresses its
record holds. :func:`detach` clears the slots.

Kernels import no robot code here: this module only dispatches, so a mobile robot's process
never loads the arm's dynamics and the other way round.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, cast

import mujoco
import numba
import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from baobab.sim.errors import SimulationError
from baobab.sim.mujoco_native import mj_get_state, mj_state_size, pointer

USERDATA_SLOTS = 4
"""Entries of ``mjData.userdata`` a model with compiled control reserves: marker, MjData
address, kernel address, record address."""

KERNEL_SIGNATURE = types.void(types.intp, types.intp, types.intp)
"""``kernel(model, data, record)``: the addresses of the mjModel, the mjData and the record."""

_MARKER = 2.0**33 + 0.125
"""First userdata entry of an attached MjData: a value no one writes by chance."""
STATE_TIME = int(mujoco.mjtState.mjSTATE_TIME)
_STATE_USERDATA = int(mujoco.mjtState.mjSTATE_USERDATA)


@intrinsic
def _call_kernel_intrinsic(
    typingctx: Any, kernel: Any, model: Any, data: Any, record: Any
) -> Any:  # pragma: no cover - compiled
    signature = types.void(types.intp, types.intp, types.intp, types.intp)

    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        word = ir.IntType(64)
        function_type = ir.FunctionType(ir.VoidType(), [word, word, word])
        function = builder.inttoptr(args[0], function_type.as_pointer())
        builder.call(function, args[1:])
        return context.get_dummy_value()

    return signature, codegen


_call_kernel = cast(Callable[[Any, Any, Any, Any], None], _call_kernel_intrinsic)


def _control_callback(model: int, data: int) -> None:  # pragma: no cover - compiled
    """``mjcb_control``: run the kernel attached to ``data``, if any (module docstring)."""
    m = pointer(model)
    if mj_state_size(m, _STATE_USERDATA) != USERDATA_SLOTS:
        return
    slots = np.empty(USERDATA_SLOTS)
    mj_get_state(m, pointer(data), pointer(slots.ctypes.data), _STATE_USERDATA)
    if slots[0] != _MARKER or np.int64(slots[1]) != data:
        return
    _call_kernel(np.int64(slots[2]), model, data, np.int64(slots[3]))


@functools.cache
def _installed_callback() -> Any:
    """Compile (or load from numba's cache) the dispatcher once per process; return it."""
    compiled = numba.cfunc(types.void(types.intp, types.intp), cache=True, nogil=True)(
        _control_callback
    )
    return compiled.ctypes


def load_dispatcher() -> None:
    """Compile (or load from numba's cache) the process-wide control callback now, and with it
    numba's compiler itself: a process that will run compiled control does this while it
    waits for other work (``baobab run``'s run process)."""
    _installed_callback()


def compile_kernel(kernel: Callable[[int, int, int], None]) -> int:
    """Compile ``kernel`` (a function of :data:`KERNEL_SIGNATURE`) as a C callback, cached on
    disk; return its address for :func:`attach`. Keep the result: compile once per process."""
    return cast(int, numba.cfunc(KERNEL_SIGNATURE, cache=True, nogil=True)(kernel).address)


def attach(data: mujoco.MjData, model: mujoco.MjModel, kernel: int, record: np.ndarray) -> None:
    """Run the compiled ``kernel`` inside every ``mj_forward`` of ``data``.

    ``record`` (any NumPy array; the kernel knows its layout) and what it points to must
    outlive the attachment (:func:`detach`).

    Raises:
        SimulationError: if the model does not reserve :data:`USERDATA_SLOTS` userdata
            entries, or integrates with RK4 (which evaluates the model four times a step).
    """
    if model.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4:
        raise SimulationError("compiled control needs a one-evaluation integrator, not RK4")
    if model.nuserdata != USERDATA_SLOTS:
        raise SimulationError(
            f"compiled control needs a model with nuserdata = {USERDATA_SLOTS} "
            f"(MjSpec.nuserdata), got {model.nuserdata}"
        )
    data.userdata[:] = [_MARKER, float(data._address), float(kernel), float(record.ctypes.data)]
    mujoco.set_mjcb_control(_installed_callback())


def detach(data: mujoco.MjData) -> None:
    """Stop running compiled control on ``data`` (idempotent)."""
    data.userdata[:] = 0.0
