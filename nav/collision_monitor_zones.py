"""The collision monitor's zones at work: which points lie inside, and when a collision comes.

A :class:`Zone` is one of Nav2's polygons (``polygon``, ``circle``, ``velocity_polygon``, or
the robot's footprint for ``approach``) in ``base_footprint`` (m). Stop, slowdown and limit
zones count the observation points inside (:meth:`Zone.triggered`, with Nav2's
``trigger_consecutive_points`` / ``release_consecutive_points`` debounce); approach zones move
the footprint ahead along the command (:meth:`Zone.collision_time`).
"""

from __future__ import annotations

import math

import numpy as np

from baobab.nav.collision_monitor_params import PolygonParams, VelocityPolygon
from baobab.robots.footprint import Footprint


class Shape:
    """A polygon (``vertices``, ``(K, 2)`` m) or a circle of ``radius`` (m) around the origin."""

    def __init__(self, vertices: np.ndarray | None = None, radius: float = 0.0) -> None:
        self.vertices = vertices
        self.radius = radius

    @classmethod
    def of_footprint(cls, footprint: Footprint) -> Shape:
        """The robot's own outline."""
        if footprint.radius is None:
            return cls(np.asarray(footprint.polygon, dtype=float))
        return cls(radius=footprint.radius)

    def inside(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Which points ``(x, y)`` (m, any shape) lie inside: Nav2's strict tests (a circle's
        ``x^2 + y^2 < r^2``, the polygon's ray crossings)."""
        if self.vertices is None:
            return x * x + y * y < self.radius * self.radius
        inside = np.zeros(np.shape(x), dtype=bool)
        xi, yi = self.vertices[-1]
        for xj, yj in self.vertices:
            crosses = (y <= yi) != (y <= yj)
            with np.errstate(divide="ignore", invalid="ignore"):
                x_at = xi + (y - yi) * (xj - xi) / (yj - yi)
            inside ^= crosses & (x < x_at)
            xi, yi = xj, yj
        return inside


class Zone:
    """One polygon of the monitor, built from its parameters and the robot's footprint."""

    def __init__(self, params: PolygonParams, footprint: Footprint) -> None:
        self.params = params
        self._velocity_shapes = [
            (sub, Shape(np.asarray(sub.points, dtype=float))) for sub in params.velocity_polygons
        ]
        self.shape: Shape | None
        if params.velocity_polygons:
            self.shape = None  # chosen by the command (Nav2 keeps the last match)
        elif params.is_footprint:
            self.shape = Shape.of_footprint(footprint)
        elif params.type == "circle":
            self.shape = Shape(radius=params.radius)
        else:
            self.shape = Shape(np.asarray(params.points, dtype=float))
        self._hits_in_row = 0
        self._misses_in_row = 0
        self.active = False

    def update_shape(self, linear: float, angular: float) -> None:
        """A velocity polygon takes the first sub-polygon whose ranges hold the command
        (m/s, rad/s); with none, the last one chosen stays."""
        for sub, shape in self._velocity_shapes:
            if _in_range(sub, linear, angular, self.params.holonomic):
                self.shape = shape
                return

    def count_inside(self, points: np.ndarray) -> int:
        """How many of ``points`` (``(N, 2)``, m) lie inside the zone (0 without a shape)."""
        if self.shape is None or len(points) == 0:
            return 0
        return int(np.count_nonzero(self.shape.inside(points[:, 0], points[:, 1])))

    def triggered(self, points: np.ndarray) -> bool:
        """Whether the zone acts this cycle: ``min_points`` or more inside for
        ``trigger_consecutive_points`` cycles in a row; it releases after
        ``release_consecutive_points`` cycles in a row with fewer."""
        params = self.params
        if self.count_inside(points) >= params.min_points:
            self._hits_in_row += 1
            self._misses_in_row = 0
            if self._hits_in_row >= params.trigger_consecutive_points:
                self.active = True
        else:
            self._misses_in_row += 1
            self._hits_in_row = 0
            if self._misses_in_row >= params.release_consecutive_points:
                self.active = False
        return self.active

    def collision_time(self, points: np.ndarray, linear: float, angular: float) -> float | None:
        """Nav2's ``Polygon::getCollisionTime``: the time (s) before ``min_points`` of
        ``points`` (``(N, 2)``, m) fall inside the zone as the robot keeps the command
        ``(linear, angular)`` (m/s, rad/s), or None within ``time_before_collision``.

        The footprint is moved ahead in steps of ``simulation_time_step`` as Nav2's
        ``projectState`` moves it (each step along the velocity turned by the yaw so far); as
        in Nav2, the time is the step's start: 0 when the first step collides.
        """
        params = self.params
        if len(points) == 0 or self.shape is None:
            return None
        dt = params.simulation_time_step
        steps = math.floor(params.time_before_collision / dt + 1e-9)
        x, y, yaw = _projected(linear, angular, dt, steps)
        cos, sin = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
        dx, dy = points[:, 0][None, :] - x[:, None], points[:, 1][None, :] - y[:, None]
        local_x, local_y = cos * dx + sin * dy, -sin * dx + cos * dy
        counts = np.count_nonzero(self.shape.inside(local_x, local_y), axis=1)
        hits = np.flatnonzero(counts >= params.min_points)
        return float(hits[0] * dt) if hits.size else None


def _projected(linear: float, angular: float, dt: float, steps: int) -> tuple[np.ndarray, ...]:
    """Poses (m, m, rad) after 1..``steps`` steps of ``dt`` s of Nav2's ``projectState`` from
    the origin: each step moves by the velocity turned through the yaw before it."""
    turned = angular * dt * np.arange(steps)
    x = linear * dt * np.cumsum(np.cos(turned))
    y = linear * dt * np.cumsum(np.sin(turned))
    return x, y, angular * dt * np.arange(1, steps + 1)


def _in_range(sub: VelocityPolygon, linear: float, angular: float, holonomic: bool) -> bool:
    """Nav2's ``VelocityPolygon::isInRange`` for a base without lateral speed."""
    if not sub.theta_min <= angular <= sub.theta_max:
        return False
    if not holonomic:
        return sub.linear_min <= linear <= sub.linear_max
    speed, direction = abs(linear), (0.0 if linear >= 0 else math.pi)
    start, end = sub.direction_start_angle, sub.direction_end_angle
    if start <= end:
        heading_ok = start <= direction <= end
    else:
        heading_ok = direction >= start or direction <= end
    return heading_ok and sub.linear_min <= speed <= sub.linear_max
