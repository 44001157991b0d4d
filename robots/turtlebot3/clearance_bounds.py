"""Lower bounds of the distance from the footprint to obstacle geoms, to cull exact queries.

``DiffDriveBase.min_clearance`` asks MuJoCo (``mj_geomDistance``) for exact distances, but
only for the obstacles that could be the nearest: the others are ruled out by a bound.

A bound for any geom is the centre gap less both bounding radii. For an upright box it is the
gap in the floor plane between the footprint's centre and the box's rectangle, less the
footprint radius (the box and the upright footprint cylinder project onto these), less
:data:`BOUND_MARGIN`. The bounds of geoms that never move (the static obstacles) are reused
while the footprint stays within :data:`REUSE_DISTANCE` of where they were computed, lowered by
the distance moved since: every bound is 1-Lipschitz in the footprint's position, so it stays a
lower bound. The few movable geoms are bounded afresh each time.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

BOX = int(mujoco.mjtGeom.mjGEOM_BOX)

BOUND_MARGIN = 1e-4
"""Slack (m) under the planar bound, far above the distance solver's tolerance."""

REUSE_DISTANCE = 0.1
"""How far (m) the footprint may move before the static bounds are computed again."""


_Row = tuple[int, np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]
"""A geom's id, and views of its position, rotation, size and bounding radius; its type."""


class ClearanceBounds:
    """Lower bounds of the distances from ``footprint`` to the obstacle geoms.

    Args:
        model, data: the simulation's model and data (``data`` kinematics up to date).
        footprint: id of the footprint cylinder geom.
        static_geoms: ids of geoms that never move or change size.
        movable_geoms: ids of geoms that move or are resized at run time.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        footprint: int,
        static_geoms: np.ndarray,
        movable_geoms: np.ndarray,
    ) -> None:
        self._data, self._footprint = data, footprint
        self._own_radius = float(model.geom_rbound[footprint])
        self._footprint_radius = float(model.geom_size[footprint, 0])

        # Row views into the model and data, made once: they follow every change, and
        # reading them costs less than indexing the whole arrays at each call.
        def rows(geoms: np.ndarray) -> list[_Row]:
            return [
                (
                    geom,
                    data.geom_xpos[geom],
                    data.geom_xmat[geom],
                    model.geom_size[geom],
                    model.geom_rbound[geom : geom + 1],
                    int(model.geom_type[geom]),
                )
                for geom in geoms.tolist()
            ]

        self._static_rows = rows(static_geoms)
        self._movable_rows = rows(movable_geoms)
        self._static_at = (math.inf, math.inf)
        self._static_bounds: list[tuple[float, int]] = []

    def sorted_bounds(self) -> list[tuple[float, int]]:
        """``(lower bound (m), geom id)`` of every obstacle geom, nearest bound first."""
        cx, cy = self._data.geom_xpos[self._footprint, :2].tolist()
        moved = math.hypot(cx - self._static_at[0], cy - self._static_at[1])
        if moved > REUSE_DISTANCE:
            self._static_bounds = self._bounds(self._static_rows, cx, cy)
            self._static_bounds.sort(key=lambda pair: pair[0])
            self._static_at, moved = (cx, cy), 0.0
        pairs = [(bound - moved, geom) for bound, geom in self._static_bounds]
        if self._movable_rows:
            pairs.extend(self._bounds(self._movable_rows, cx, cy))
            pairs.sort(key=lambda pair: pair[0])
        return pairs

    def _bounds(self, rows: list[_Row], cx: float, cy: float) -> list[tuple[float, int]]:
        """``(lower bound (m), geom id)`` of each geom of ``rows`` from ``(cx, cy)`` (m)."""
        pairs = []
        for geom, xpos, xmat, size, rbound, kind in rows:
            x, y, _ = xpos.tolist()
            gx, gy = cx - x, cy - y
            bound = math.hypot(gx, gy) - (float(rbound[0]) + self._own_radius)
            r = xmat.tolist()
            if kind == BOX and r[8] > 1.0 - 1e-9:  # an upright box
                sx, sy, _ = size.tolist()
                # The offset in the box frame, R^T (p - c), in the plane.
                along_x = max(abs(r[0] * gx + r[3] * gy) - sx, 0.0)
                along_y = max(abs(r[1] * gx + r[4] * gy) - sy, 0.0)
                planar = math.hypot(along_x, along_y) - self._footprint_radius - BOUND_MARGIN
                bound = max(bound, planar)
            pairs.append((bound, geom))
        return pairs
