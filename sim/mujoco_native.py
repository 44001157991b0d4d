"""MuJoCo's C functions callable from numba-compiled code, by symbol name.

Compiled kernels that loop over many geoms or beams call MuJoCo itself for the exact
geometry (so their results are bit for bit those of the Python bindings) and do their own
culling around it. Pointers travel as integer addresses (``intp``): on every platform MuJoCo
supports, a pointer argument and a pointer-sized integer are passed alike. An address comes
from ``MjModel._address`` / ``MjData._address`` or from ``array.ctypes.data`` (also inside
compiled code).
"""

from __future__ import annotations

import ctypes.util
from collections.abc import Callable
from pathlib import Path
from typing import Any, cast

import llvmlite.binding
import mujoco
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


def _mujoco_library() -> str:
    folder = Path(mujoco.__file__).parent
    for pattern in ("libmujoco.so*", "libmujoco*.dylib", "mujoco.dll"):
        found = sorted(folder.glob(pattern))
        if found:
            return str(found[0])
    raise ImportError(f"MuJoCo's shared library is not in {folder}")  # pragma: no cover


# The bindings load libmujoco privately: make its symbols visible to the JIT linker; and libm's,
# for C functions numba does not provide.
llvmlite.binding.load_library_permanently(_mujoco_library())
_libm = ctypes.util.find_library("m")
if _libm is not None:  # pragma: no branch - every Unix has one
    llvmlite.binding.load_library_permanently(_libm)

ray_geom = cast(
    Callable[[int, int, int, int, int, int, int], float],
    types.ExternalFunction(
        "mju_rayGeom",
        types.float64(
            types.intp, types.intp, types.intp, types.intp, types.intp, types.intc, types.intp
        ),
    ),
)
"""``mju_rayGeom(pos, mat, size, pnt, vec, geomtype, normal)``: distance along ``vec`` to a
primitive geom, or -1 if the ray misses it (addresses of float64 arrays; ``normal`` may be 0)."""

geom_distance = cast(
    Callable[[int, int, int, int, float, int], float],
    types.ExternalFunction(
        "mj_geomDistance",
        types.float64(types.intp, types.intp, types.intc, types.intc, types.float64, types.intp),
    ),
)
"""``mj_geomDistance(model, data, geom1, geom2, distmax, fromto)``: signed distance (m) between
two geoms, ``distmax`` if it is larger (``fromto`` may be 0)."""


mj_get_state = cast(
    Callable[[Any, Any, Any, int], None],
    types.ExternalFunction(
        "mj_getState", types.void(types.voidptr, types.voidptr, types.voidptr, types.intc)
    ),
)
"""``mj_getState(m, d, state, spec)``: copy the parts ``spec`` of the state into ``state``."""

mj_state_size = cast(
    Callable[[Any, int], int],
    types.ExternalFunction("mj_stateSize", types.intc(types.voidptr, types.intc)),
)
"""``mj_stateSize(m, spec)``: the number of float64 values in the state parts ``spec``."""

remainder = cast(
    Callable[[float, float], float],
    types.ExternalFunction("remainder", types.float64(types.float64, types.float64)),
)
"""C's ``remainder``: the same function as Python's ``math.remainder``."""


@intrinsic
def _pointer_intrinsic(typingctx: Any, address: Any) -> Any:  # pragma: no cover - compiled
    signature = types.voidptr(types.intp)

    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return builder.inttoptr(args[0], cgutils.voidptr_t)

    return signature, codegen


pointer = cast(Callable[[Any], Any], _pointer_intrinsic)
"""The pointer at an integer address (compiled code only)."""


def address(struct: Any) -> int:
    """The C address of an ``MjModel`` or ``MjData``."""
    return int(struct._address)
