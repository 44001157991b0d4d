"""Lower bounds of the distance from the footprint to obstacle geoms, to cull exact queries.

``DiffDriveBase.min_clearance`` asks MuJoCo (``mj_geomDistance``) for exact distances, but
only for the obstacles that could be the nearest: the others are ruled out by a bound.

A bound for any geom is the centre gap less both bounding radii. For an upright box it is the
gap in the floor plane between the footprint's centre and the box's rectangle, less the
footprint radius (the box and the upright footprint cylinder project onto these), less
:data:`BOUND_MARGIN`. Geoms that never move (the static obstacles) have their part of the
computation prepared once, and their bounds are reused while the footprint stays within
:data:`REUSE_DISTANCE` of where they were computed, lowered by the distance moved since: every
bound is 1-Lipschitz in the footprint's position, so it stays a lower bound. The few movable
geoms are read afresh each time.
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


def _upright_box(kind: int, rotation: list[float]) -> bool:
    return kind == BOX and rotation[8] > 1.0 - 1e-9


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
        self._model, self._data = model, data
        self._footprint = footprint
        self._static_ids = static_geoms.tolist()
        self._movable_ids = movable_geoms.tolist()
        # Row views into the model and data, made once: fancy indexing costs more per call.
        self._movable_rows = [
            (
                geom,
                data.geom_xpos[geom],
                data.geom_xmat[geom],
                model.geom_size[geom],
                model.geom_rbound[geom : geom + 1],
                int(model.geom_type[geom]),
            )
            for geom in self._movable_ids
        ]
        rotations = data.geom_xmat[static_geoms]
        self._centres = data.geom_xpos[static_geoms, :2].copy()
        self._rbound = model.geom_rbound[static_geoms].copy()
        self._box = np.array(
            [
                _upright_box(kind, rotation)
                for kind, rotation in zip(
                    model.geom_type[static_geoms].tolist(), rotations.tolist(), strict=True
                )
            ],
            dtype=bool,
        )
        # Box axes in the plane (first two rows of the first two columns) and half sizes.
        self._axes = rotations[:, [0, 3, 1, 4]].copy()
        self._half = model.geom_size[static_geoms, :2].copy()
        self._static_at = (math.inf, math.inf)
        self._static_bounds: list[tuple[float, int]] = []

    def sorted_bounds(self) -> list[tuple[float, int]]:
        """``(lower bound (m), geom id)`` of every obstacle geom, nearest bound first."""
        model, data, footprint = self._model, self._data, self._footprint
        cx, cy = data.geom_xpos[footprint, :2].tolist()
        own_radius = float(model.geom_rbound[footprint])
        footprint_radius = float(model.geom_size[footprint, 0])
        moved = math.hypot(cx - self._static_at[0], cy - self._static_at[1])
        if moved > REUSE_DISTANCE:
            self._static_bounds = self._static(cx, cy, own_radius, footprint_radius)
            self._static_at, moved = (cx, cy), 0.0
        pairs = [(bound - moved, geom) for bound, geom in self._static_bounds]
        if self._movable_rows:
            pairs.extend(self._movable_bounds(cx, cy, own_radius, footprint_radius))
            pairs.sort(key=lambda pair: pair[0])
        return pairs

    def _static(
        self, cx: float, cy: float, own_radius: float, footprint_radius: float
    ) -> list[tuple[float, int]]:
        """The static geoms' bounds from ``(cx, cy)`` (m), nearest first."""
        dx = cx - self._centres[:, 0]
        dy = cy - self._centres[:, 1]
        bounds = np.hypot(dx, dy) - (self._rbound + own_radius)
        axes = self._axes
        outside_x = np.maximum(np.abs(axes[:, 0] * dx + axes[:, 1] * dy) - self._half[:, 0], 0.0)
        outside_y = np.maximum(np.abs(axes[:, 2] * dx + axes[:, 3] * dy) - self._half[:, 1], 0.0)
        planar = np.hypot(outside_x, outside_y) - (footprint_radius + BOUND_MARGIN)
        bounds = np.where(self._box, np.maximum(bounds, planar), bounds)
        pairs = list(zip(bounds.tolist(), self._static_ids, strict=True))
        pairs.sort(key=lambda pair: pair[0])
        return pairs

    def _movable_bounds(
        self, cx: float, cy: float, own_radius: float, footprint_radius: float
    ) -> list[tuple[float, int]]:
        """The movable geoms' bounds from ``(cx, cy)`` (m), read from the current state."""
        pairs = []
        for geom, xpos, xmat, size, rbound, kind in self._movable_rows:
            x, y, _ = xpos.tolist()
            r = xmat.tolist()
            gx, gy = cx - x, cy - y
            bound = math.hypot(gx, gy) - (float(rbound[0]) + own_radius)
            if _upright_box(kind, r):
                sx, sy, _ = size.tolist()
                along_x = max(abs(r[0] * gx + r[3] * gy) - sx, 0.0)
                along_y = max(abs(r[1] * gx + r[4] * gy) - sy, 0.0)
                bound = max(bound, math.hypot(along_x, along_y) - footprint_radius - BOUND_MARGIN)
            pairs.append((bound, geom))
        return pairs
