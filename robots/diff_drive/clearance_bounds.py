"""The footprint's clearance to the obstacle geoms: exact distances, few of them, compiled.

:meth:`ClearanceBounds.min_clearance` asks MuJoCo (``mj_geomDistance``) for exact distances,
but only for the obstacles that could be the nearest: the others are ruled out by a lower
bound of their distance. Candidates go nearest bound first, and the search ends at the first
bound that is not below the best distance so far, so the answer is the one an exhaustive
search gives, bit for bit. The whole search runs compiled, calling MuJoCo by symbol.

A bound for any geom is the planar centre gap less both bounding radii. Upright boxes and
cylinders, the usual obstacles, get a tighter one: the planar gap between their outline (a
rectangle or a disc) and the disc that holds the footprint's shadow on the floor (a
cylinder's radius and tilt, a polygon prism's bounding sphere), less :data:`BOUND_MARGIN`.
Both shapes project inside those outlines, so the bound holds; when the outlines overlap the
gap is negative, as deep as the shift that would part them (a penetration is never deeper than
that).

Compiled because the metrics ask for the clearance 20 times a simulated second: from Python
the bounds would be a dozen numpy passes and each exact distance a call through the bindings;
compiled, the whole search is one call. The tests compare its answer with the exhaustive
search over ``mj_geomDistance`` (``tests/test_clearance_bounds.py``). MuJoCo's arrays travel
in one :data:`~baobab.sim.mujoco_native.GEOM_ARRAYS` record.
"""

from __future__ import annotations

import math

import mujoco
import numba
import numpy as np

from baobab.sim.mujoco_native import address, geom_arrays, geom_distance, geom_views

_BOX = int(mujoco.mjtGeom.mjGEOM_BOX)
_CYLINDER = int(mujoco.mjtGeom.mjGEOM_CYLINDER)

BOUND_MARGIN = 1e-4
"""Slack (m) under the planar bounds, far above the distance solver's tolerance."""

UPRIGHT = 1.0 - 1e-9
"""A geom whose z axis has at least this vertical component counts as upright."""


@numba.njit(cache=True, nogil=True)
def clearance_bounds(
    footprint: int, geoms: np.ndarray, geom: np.ndarray, bounds: np.ndarray
) -> None:  # pragma: no cover - compiled
    """Lower bounds (m) of the distances from the ``footprint`` cylinder to ``geoms``.

    Args:
        footprint: the footprint geom's id (a cylinder, or a polygon's prism).
        geoms: obstacle geom ids (n,).
        geom: the model's and data's :data:`~baobab.sim.mujoco_native.GEOM_ARRAYS` record.
        bounds: out (n,).
    """
    geometry = geom_views(geom)
    geom_xpos, geom_xmat, geom_size = geometry.geom_xpos, geometry.geom_xmat, geometry.geom_size
    geom_rbound, geom_type = geometry.geom_rbound, geometry.geom_type
    cx, cy = geom_xpos[footprint, 0], geom_xpos[footprint, 1]
    axis = geom_xmat[footprint]
    own_radius = geom_rbound[footprint]
    if geom_type[footprint] == _CYLINDER:
        # The footprint's shadow on the floor lies in a disc: radius plus the tilted axis' reach.
        shadow = geom_size[footprint, 0] + geom_size[footprint, 1] * math.hypot(axis[2], axis[5])
    else:  # a polygon's prism: its bounding sphere's shadow
        shadow = own_radius
    for k in range(geoms.shape[0]):
        geom = geoms[k]
        gx, gy = cx - geom_xpos[geom, 0], cy - geom_xpos[geom, 1]
        bound = math.hypot(gx, gy) - (geom_rbound[geom] + own_radius)
        r = geom_xmat[geom]
        kind = geom_type[geom]
        if r[8] > UPRIGHT and kind in (_BOX, _CYLINDER):
            # A tilt within UPRIGHT moves the top and bottom outlines by this much at most.
            lean = geom_size[geom, 2 if kind == _BOX else 1] * math.hypot(r[2], r[5])
            if kind == _BOX:
                # The offset in the box frame, R^T (p - c), in the plane, against the rectangle.
                along_x = abs(r[0] * gx + r[3] * gy) - geom_size[geom, 0]
                along_y = abs(r[1] * gx + r[4] * gy) - geom_size[geom, 1]
                if along_x > 0.0 or along_y > 0.0:
                    planar = math.hypot(max(along_x, 0.0), max(along_y, 0.0))
                else:  # inside: a negative gap, as deep as the nearest side
                    planar = max(along_x, along_y)
            else:
                planar = math.hypot(gx, gy) - geom_size[geom, 0]
            bound = max(bound, planar - shadow - lean - BOUND_MARGIN)
        bounds[k] = bound


@numba.njit(cache=True, nogil=True)
def _min_clearance(
    model: int,
    data: int,
    footprint: int,
    geoms: np.ndarray,
    geom: np.ndarray,
    max_distance: float,
    below: float,
    bounds: np.ndarray,
) -> float:  # pragma: no cover - compiled
    """See :meth:`ClearanceBounds.min_clearance`; ``model``/``data`` are C addresses, ``geom``
    the :data:`~baobab.sim.mujoco_native.GEOM_ARRAYS` record."""
    clearance_bounds(footprint, geoms, geom, bounds)
    nearest = math.inf
    for _ in range(geoms.shape[0]):
        # The nearest bound not yet tried: usually one or two rounds.
        pick, lower = -1, math.inf
        for k in range(geoms.shape[0]):
            if bounds[k] < lower:
                pick, lower = k, bounds[k]
        if pick < 0 or lower >= max_distance or lower >= nearest or lower >= below:
            break
        bounds[pick] = math.inf
        distance = geom_distance(model, data, footprint, geoms[pick], max_distance, 0)
        nearest = min(nearest, distance)
    return nearest if nearest < max_distance and nearest < below else math.inf


class ClearanceBounds:
    """Distance from ``footprint`` to the nearest obstacle geom, and its culling bounds.

    Args:
        model, data: the simulation's model and data (``data`` kinematics up to date).
        footprint: id of the footprint cylinder geom.
        obstacles: ids of the obstacle geoms (static and movable: every bound is computed
            from the current state).
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        footprint: int,
        obstacles: np.ndarray,
    ) -> None:
        self._footprint = int(footprint)
        self._geoms = np.asarray(obstacles, dtype=np.int64)
        self._bounds = np.empty(self._geoms.shape[0])
        # The struct addresses and array views, read once: each attribute read makes a view.
        self._addresses = (address(model), address(data))
        self._geom = geom_arrays(model, data)  # valid while model and data live
        # The views must outlive nothing: keep the structs they point into alive.
        self._model, self._data = model, data

    def min_clearance(self, max_distance: float = 2.0, *, below: float = math.inf) -> float:
        """Distance (m) from the footprint to the nearest obstacle geom, as
        ``min(mj_geomDistance(footprint, g, max_distance))`` over them all gives it.

        Negative when an obstacle reaches inside the footprint; ``inf`` when nothing is
        within ``max_distance`` (m), or nothing nearer than ``below`` (m): a caller that only
        wants a clearance below the least so far skips the obstacles that cannot give one.
        """
        model, data = self._addresses
        return float(
            _min_clearance(
                model,
                data,
                self._footprint,
                self._geoms,
                self._geom,
                float(max_distance),
                float(below),
                self._bounds,
            )
        )

    def sorted_bounds(self) -> list[tuple[float, int]]:
        """``(lower bound (m), geom id)`` of every obstacle geom, nearest bound first."""
        bounds = np.empty(self._geoms.shape[0])
        clearance_bounds(self._footprint, self._geoms, self._geom, bounds)
        return sorted(zip(bounds.tolist(), self._geoms.tolist(), strict=True))
