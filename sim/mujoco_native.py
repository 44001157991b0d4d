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
import numba
import numpy as np
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from baobab.sim.records import record


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

    Compiled code gets them from a :data:`GEOM_ARRAYS` record (:func:`geom_views`), which
    costs a kernel call far less than a tuple of fourteen arrays would.
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


_GEOM_LAYOUT = {
    # field: (MjData or MjModel, dtype, count of rows, columns); 0 columns for a vector
    "geom_xpos": ("data", np.float64, "ngeom", 3),
    "geom_xmat": ("data", np.float64, "ngeom", 9),
    "geom_size": ("model", np.float64, "ngeom", 3),
    "geom_rbound": ("model", np.float64, "ngeom", 0),
    "geom_type": ("model", np.int32, "ngeom", 0),
    "geom_group": ("model", np.int32, "ngeom", 0),
    "geom_matid": ("model", np.int32, "ngeom", 0),
    "geom_rgba": ("model", np.float32, "ngeom", 4),
    "mat_rgba": ("model", np.float32, "nmat", 4),
    "geom_aabb": ("model", np.float64, "ngeom", 6),
    "geom_bodyid": ("model", np.int32, "ngeom", 0),
    "body_bvhadr": ("model", np.int32, "nbody", 0),
    "bvh_aabb": ("model", np.float64, "nbvh", 6),
    "xipos": ("data", np.float64, "nbody", 3),
}

GEOM_ARRAYS = np.dtype(
    [(name, np.int64) for name in GeomArrays._fields]
    + [(count, np.int64) for count in ("ngeom", "nmat", "nbody", "nbvh")]
)
"""Where each of :class:`GeomArrays` lives (its address in MjModel or MjData, valid while they
live), and the counts that shape them (:func:`geom_arrays`)."""


def geom_arrays(model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """The :data:`GEOM_ARRAYS` record of ``model`` and ``data``; keep both alive while it is used.

    Raises:
        TypeError: if MuJoCo stores one of the arrays with another type or layout than the
            kernels read it with.
    """
    counts = {count: int(getattr(model, count)) for count in ("ngeom", "nmat", "nbody", "nbvh")}
    addresses = {}
    for name, (owner, dtype, rows, columns) in _GEOM_LAYOUT.items():
        array = getattr(data if owner == "data" else model, name)
        shape = (counts[rows], columns) if columns else (counts[rows],)
        if array.dtype != dtype or array.shape != shape or not array.flags.c_contiguous:
            raise TypeError(
                f"MuJoCo's {name} is {array.dtype} {array.shape}, expected contiguous "
                f"{np.dtype(dtype)} {shape}"
            )
        addresses[name] = array.ctypes.data
    return record(GEOM_ARRAYS, **addresses, **counts)


@numba.njit(cache=True, nogil=True, inline="always")
def geom_views(geom: np.ndarray) -> GeomArrays:  # pragma: no cover - compiled
    """The :class:`GeomArrays` a :data:`GEOM_ARRAYS` record points to (compiled code only)."""
    g = geom[0]
    ngeom, nbody = g.ngeom, g.nbody
    return GeomArrays(
        geom_xpos=numba.carray(pointer(g.geom_xpos), (ngeom, 3), np.float64),
        geom_xmat=numba.carray(pointer(g.geom_xmat), (ngeom, 9), np.float64),
        geom_size=numba.carray(pointer(g.geom_size), (ngeom, 3), np.float64),
        geom_rbound=numba.carray(pointer(g.geom_rbound), (ngeom,), np.float64),
        geom_type=numba.carray(pointer(g.geom_type), (ngeom,), np.int32),
        geom_group=numba.carray(pointer(g.geom_group), (ngeom,), np.int32),
        geom_matid=numba.carray(pointer(g.geom_matid), (ngeom,), np.int32),
        geom_rgba=numba.carray(pointer(g.geom_rgba), (ngeom, 4), np.float32),
        mat_rgba=numba.carray(pointer(g.mat_rgba), (g.nmat, 4), np.float32),
        geom_aabb=numba.carray(pointer(g.geom_aabb), (ngeom, 6), np.float64),
        geom_bodyid=numba.carray(pointer(g.geom_bodyid), (ngeom,), np.int32),
        body_bvhadr=numba.carray(pointer(g.body_bvhadr), (nbody,), np.int32),
        bvh_aabb=numba.carray(pointer(g.bvh_aabb), (g.nbvh, 6), np.float64),
        xipos=numba.carray(pointer(g.xipos), (nbody, 3), np.float64),
    )
