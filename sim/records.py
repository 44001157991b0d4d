"""Named records: how Python hands values to the compiled (numba) kernels.

A kernel takes a few named records, never a long positional list:

- scalars (settings, a pose, a grid's geometry, results) travel in a *record*: a NumPy
  structured array of one element whose dtype the kernel's module defines, field by field
  with units. numba reads its fields by name (``settings[0].lookahead_dist``) at the cost of
  an array index. A record is built by one ``pack()`` beside the Python dataclass it mirrors,
  with :func:`record`, which takes every field by name;
- arrays of run-time size travel in a :class:`typing.NamedTuple` of arrays, read by name too.
  numba types such an argument element by element, about 1 us plus 0.2 us per array a call:
  where a kernel is called often with many arrays that live in MuJoCo (as long as their
  MjModel or MjData), a record of their addresses travels instead and the kernel views them
  by name (:data:`~baobab.sim.mujoco_native.GEOM_ARRAYS`).

Not jitclasses: numba cannot cache code that takes one, so every process would compile those
kernels anew (seconds of start-up).
"""

from __future__ import annotations

from typing import Any, TypeAlias

import numpy as np

Record: TypeAlias = Any
"""One record as compiled code sees it (numba's record type: fields as attributes)."""


def record(dtype: np.dtype, source: object = None, /, **fields: object) -> np.ndarray:
    """A one-element array of ``dtype``, every field set by name.

    A field takes the keyword argument of its name, else ``source``'s attribute of its name.

    Raises:
        AttributeError: if a field is neither given nor an attribute of ``source``.
        TypeError: for a keyword that names no field (a misspelt field).
    """
    names = dtype.names or ()
    unknown = set(fields) - set(names)
    if unknown:
        raise TypeError(f"{dtype} has no field {sorted(unknown)[0]!r}")
    values = tuple(fields[name] if name in fields else getattr(source, name) for name in names)
    return np.array([values], dtype=dtype)
