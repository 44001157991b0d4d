"""MuJoCo's C functions callable from numba-compiled code, by symbol name.

Compiled kernels that loop over many geoms or beams call MuJoCo itself for the exact
geometry (so their results are bit for bit those of the Python bindings) and do their own
culling around it. Pointers travel as integer addresses (``intp``): on every platform MuJoCo
supports, a pointer argument and a pointer-sized integer are passed alike. An address comes
from ``MjModel._address`` / ``MjData._address`` or from ``array.ctypes.data`` (also inside
compiled code).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any, cast

import llvmlite.binding
import mujoco
from numba import types


def _mujoco_library() -> str:
    folder = Path(mujoco.__file__).parent
    for pattern in ("libmujoco.so*", "libmujoco*.dylib", "mujoco.dll"):
        found = sorted(folder.glob(pattern))
        if found:
            return str(found[0])
    raise ImportError(f"MuJoCo's shared library is not in {folder}")  # pragma: no cover


# The bindings load libmujoco privately: make its symbols visible to the JIT linker.
llvmlite.binding.load_library_permanently(_mujoco_library())

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


def address(struct: Any) -> int:
    """The C address of an ``MjModel`` or ``MjData``."""
    return int(struct._address)
