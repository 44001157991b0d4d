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
from typing import Any, NamedTuple, cast

import llvmlite.binding
import mujoco
import numpy as np
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


class GeomArrays(NamedTuple):
    """MuJoCo's arrays the compiled geometry kernels read, by their MuJoCo names.

    Views into the model and data (:func:`geom_arrays`): they follow the state as it changes.
    """

    geom_xpos: np.ndarray
    """``data.geom_xpos`` (ngeom, 3): geom centres, world frame (m)."""
    geom_xmat: np.ndarray
    """``data.geom_xmat`` (ngeom, 9): geom orientations, row-major."""
    geom_size: np.ndarray
    """``model.geom_size`` (ngeom, 3) (m)."""
    geom_rbound: np.ndarray
    """``model.geom_rbound`` (ngeom,): bounding sphere radius (m)."""
    geom_type: np.ndarray
    """``model.geom_type`` (ngeom,): ``mjtGeom``."""
    geom_group: np.ndarray
    """``model.geom_group`` (ngeom,)."""
    geom_matid: np.ndarray
    """``model.geom_matid`` (ngeom,): material, -1 for none."""
    geom_rgba: np.ndarray
    """``model.geom_rgba`` (ngeom, 4)."""
    mat_rgba: np.ndarray
    """``model.mat_rgba`` (nmat, 4)."""
    geom_aabb: np.ndarray
    """``model.geom_aabb`` (ngeom, 6): bounding box, geom frame: centre, half sizes (m)."""
    geom_bodyid: np.ndarray
    """``model.geom_bodyid`` (ngeom,)."""
    body_bvhadr: np.ndarray
    """``model.body_bvhadr`` (nbody,): the body's bounding-volume root, -1 for none."""
    bvh_aabb: np.ndarray
    """``model.bvh_aabb`` (nbvh, 6): bounding boxes, body inertial frame (m)."""
    xipos: np.ndarray
    """``data.xipos`` (nbody, 3): body inertial frames' origins, world frame (m)."""


def geom_arrays(model: mujoco.MjModel, data: mujoco.MjData) -> GeomArrays:
    """The :class:`GeomArrays` of ``model`` and ``data``, views made once (reading a MuJoCo
    array attribute builds a new view each time)."""
    return GeomArrays(
        **{name: getattr(data if name in _DATA else model, name) for name in GeomArrays._fields}
    )


_DATA = {"geom_xpos", "geom_xmat", "xipos"}
"""The :class:`GeomArrays` fields that live in MjData."""
