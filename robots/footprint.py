"""A robot's footprint the way Nav2 configures one: a radius, or a polygon in ``base_link``.

Nav2's costmaps take either ``robot_radius`` or ``footprint`` (a polygon, x forward, y left,
around ``base_link``). From the footprint come the two radii the stack works with
(``nav2_costmap_2d::calculateMinAndMaxDistances``): the *inscribed* radius, the distance from
``base_link`` to the nearest edge (what the inflation layer marks
``INSCRIBED_INFLATED_OBSTACLE``), and the *circumscribed* radius, the farthest vertex (what a
turn in place sweeps). ``footprint_padding`` (Nav2's 0.01 m) moves each polygon vertex outward
along x and along y (``padFootprint``).

:meth:`Footprint.clearance_in` measures the footprint at a pose against a world's obstacles
and floor edge, exactly, in plain floating-point math: the mission loader checks every pose
with it before numpy or any physics is loaded.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from baobab.sim.planar_shapes import circle_distance_at, rectangle_distance_at
from baobab.sim.point_clearance import (
    MAP_WALLS,
    map_distance_at,
    obstacle_distances_at,
)
from baobab.sim.world import Box, Cylinder, Pose2D, World

NAV2_FOOTPRINT_PADDING = 0.01
"""Nav2's ``footprint_padding`` default (m)."""
FLOOR_EDGE = "floor edge"
"""The floor boundary's name in clearance reports (as :mod:`baobab.sim.geometry` names it)."""
CIRCLE_POINTS = 16
"""Points of the outline Nav2 makes of a radius (``makeFootprintFromRadius``)."""

Point = tuple[float, float]
"""A point (m): x forward, y left in ``base_link``; or a map-frame point."""


@dataclass(frozen=True)
class Footprint:
    """A circle of ``radius`` around ``base_link``, or a simple ``polygon`` (vertices in order
    around the robot, either way, m). Exactly one of the two is given; :meth:`problem` says
    what is wrong with a footprint that is not usable."""

    radius: float | None = None
    polygon: tuple[Point, ...] = ()

    @classmethod
    def circle(cls, radius: float) -> Footprint:
        """A circular footprint of ``radius`` (m)."""
        return cls(radius=float(radius))

    @classmethod
    def rectangle(cls, x_min: float, x_max: float, y_min: float, y_max: float) -> Footprint:
        """An axis-aligned rectangle in ``base_link`` (m), counter-clockwise from rear right."""
        return cls(polygon=((x_min, y_min), (x_max, y_min), (x_max, y_max), (x_min, y_max)))

    @property
    def is_circle(self) -> bool:
        """True for a radius, False for a polygon."""
        return self.radius is not None

    @property
    def outline(self) -> tuple[Point, ...]:
        """The polygon's vertices (m); a circle gives Nav2's 16-point outline of it."""
        if self.radius is None:
            return self.polygon
        step = 2 * math.pi / CIRCLE_POINTS
        return tuple(
            (self.radius * math.cos(i * step), self.radius * math.sin(i * step))
            for i in range(CIRCLE_POINTS)
        )

    @property
    def inscribed_radius(self) -> float:
        """Distance (m) from ``base_link`` to the nearest edge (a circle's radius)."""
        if self.radius is not None:
            return self.radius
        return min(_segment_distance((0.0, 0.0), a, b) for a, b in _edges(self.polygon))

    @property
    def circumscribed_radius(self) -> float:
        """Distance (m) from ``base_link`` to the farthest vertex (a circle's radius)."""
        if self.radius is not None:
            return self.radius
        return max(math.hypot(x, y) for x, y in self.polygon)

    def padded(self, padding: float) -> Footprint:
        """Nav2's ``padFootprint``: each polygon vertex moved ``padding`` (m) outward along x
        and along y (by the signs of its coordinates); a circle is returned as it is."""
        if self.radius is not None or padding == 0.0:
            return self
        return Footprint(
            polygon=tuple((x + _sign(x) * padding, y + _sign(y) * padding) for x, y in self.polygon)
        )

    def at(self, pose: Pose2D) -> list[Point]:
        """The outline's vertices at ``pose`` in the map frame (m)."""
        cos, sin = math.cos(pose.yaw), math.sin(pose.yaw)
        return [(pose.x + cos * x - sin * y, pose.y + sin * x + cos * y) for x, y in self.outline]

    def contains(self, point: Point, *, tolerance: float = 0.0) -> bool:
        """True when ``point`` (m, ``base_link``) lies in the footprint or within ``tolerance``
        (m) of its outline."""
        if self.radius is not None:
            return math.hypot(*point) <= self.radius + tolerance
        if _contains(self.polygon, point):
            return True
        return min(_segment_distance(point, a, b) for a, b in _edges(self.polygon)) <= tolerance

    def problem(self) -> str | None:
        """Why this is not a usable footprint, or None: a radius that is not a positive
        number; a polygon of fewer than 3 vertices, with a repeated vertex, crossing edges or
        no area, or one that does not hold ``base_link``."""
        if self.radius is not None:
            if self.polygon:
                return "give a radius or a polygon, not both"
            if not (math.isfinite(self.radius) and self.radius > 0):
                return f"the radius must be a positive number of metres, got {self.radius:g}"
            return None
        points = self.polygon
        if len(points) < 3:
            return f"a footprint polygon needs at least 3 vertices, got {len(points)}"
        if not all(math.isfinite(v) for point in points for v in point):
            return "every footprint vertex must be finite"
        return _simple_polygon_problem(points)

    def clearance_in(self, world: World, pose: Pose2D) -> tuple[str, float]:
        """The obstacle (or ``floor edge``) nearest to the footprint at ``pose`` and the
        distance (m) between them: zero or negative when the footprint touches or overlaps it.

        A circle is measured from its centre (signed distance less the radius); a polygon
        exactly, edge against edge (negative when the two overlap).
        """
        if self.radius is not None:
            point = (pose.x, pose.y)
            distances = obstacle_distances_at(world, *point)
            distances.append((FLOOR_EDGE, _floor_edge_distance(world, point)))
            name, distance = min(distances, key=lambda item: item[1])
            return name, distance - self.radius
        return _polygon_nearest(world, self.at(pose))


def _sign(value: float) -> float:
    return 0.0 if value == 0.0 else math.copysign(1.0, value)


def _edges(points: Sequence[Point]) -> list[tuple[Point, Point]]:
    return [(points[i], points[(i + 1) % len(points)]) for i in range(len(points))]


def _segment_distance(point: Point, a: Point, b: Point) -> float:
    """Distance (m) from ``point`` to the segment ``a``-``b``."""
    ex, ey = b[0] - a[0], b[1] - a[1]
    length2 = ex * ex + ey * ey
    t = 0.0 if length2 == 0.0 else ((point[0] - a[0]) * ex + (point[1] - a[1]) * ey) / length2
    t = min(max(t, 0.0), 1.0)
    return math.hypot(a[0] + t * ex - point[0], a[1] + t * ey - point[1])


def _cross(o: Point, a: Point, b: Point) -> float:
    """z of (a - o) x (b - o)."""
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _segments_meet(a: Point, b: Point, c: Point, d: Point) -> bool:
    """True when the segments ab and cd share a point."""
    d1, d2, d3, d4 = _cross(c, d, a), _cross(c, d, b), _cross(a, b, c), _cross(a, b, d)
    if ((d1 > 0 > d2) or (d1 < 0 < d2)) and ((d3 > 0 > d4) or (d3 < 0 < d4)):
        return True
    return any(
        side == 0.0 and _segment_distance(point, p, q) < 1e-12
        for side, point, p, q in ((d1, a, c, d), (d2, b, c, d), (d3, c, a, b), (d4, d, a, b))
    )


def _contains(polygon: Sequence[Point], point: Point) -> bool:
    """True when ``point`` lies inside ``polygon`` (even-odd rule)."""
    x, y = point
    inside = False
    for (x0, y0), (x1, y1) in _edges(polygon):
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


def _simple_polygon_problem(points: Sequence[Point]) -> str | None:
    """Why ``points`` is not a simple polygon holding the origin, or None."""
    edges = _edges(points)
    if any(math.dist(a, b) < 1e-9 for a, b in edges):
        return "two consecutive footprint vertices are the same point"
    count = len(edges)
    for i in range(count):
        for j in range(i + 2, count):
            if i == 0 and j == count - 1:
                continue  # the first and last edges share a vertex
            if _segments_meet(*edges[i], *edges[j]):
                return (
                    f"footprint edges {i + 1} and {j + 1} cross: the polygon is not simple "
                    "(list the vertices in order around the robot)"
                )
    area = 0.5 * sum(_cross((0.0, 0.0), a, b) for a, b in edges)
    if abs(area) < 1e-9:
        return "the footprint polygon has no area"
    if not _contains(points, (0.0, 0.0)):
        return "the footprint polygon must hold base_link (0, 0), the point the robot turns about"
    return None


def _obstacle_outline(obstacle: Box | Cylinder) -> list[Point]:
    """A box's corners (map frame, m); a cylinder has none."""
    if isinstance(obstacle, Cylinder):
        return []
    cx, cy = obstacle.center
    cos, sin = math.cos(obstacle.yaw), math.sin(obstacle.yaw)
    a, b = obstacle.size[0] / 2, obstacle.size[1] / 2
    return [
        (cx + cos * x - sin * y, cy + sin * x + cos * y)
        for x, y in ((-a, -b), (a, -b), (a, b), (-a, b))
    ]


def _polygon_distance(polygon: Sequence[Point], obstacle: Box | Cylinder) -> float:
    """Distance (m) between a polygon and an obstacle's outline; negative when they overlap
    (as deep as the polygon's deepest vertex inside it, at least 1e-9)."""
    signed = rectangle_distance_at if isinstance(obstacle, Box) else circle_distance_at
    deepest = min(signed(x, y, obstacle) for x, y in polygon)  # type: ignore[arg-type]
    if deepest <= 0.0:
        return min(deepest, -1e-9)
    if isinstance(obstacle, Cylinder):
        if _contains(polygon, obstacle.center):
            return -1e-9
        gap = min(_segment_distance(obstacle.center, a, b) for a, b in _edges(polygon))
        return gap - obstacle.radius
    corners = _obstacle_outline(obstacle)
    if any(_contains(polygon, corner) for corner in corners):
        return -1e-9
    sides, edges = _edges(corners), _edges(polygon)
    if any(_segments_meet(*side, *edge) for side in sides for edge in edges):
        return -1e-9
    return min(deepest, *(_segment_distance(corner, *edge) for corner in corners for edge in edges))


def _polygon_nearest(world: World, polygon: Sequence[Point]) -> tuple[str, float]:
    """The nearest obstacle or floor edge to ``polygon`` and the distance (m) to it."""
    obstacles: list[Box | Cylinder] = [*world.boxes, *world.cylinders]
    distances = [(obstacle.name, _polygon_distance(polygon, obstacle)) for obstacle in obstacles]
    distances.append((FLOOR_EDGE, min(_floor_edge_distance(world, point) for point in polygon)))
    walls = _polygon_map_distance(world, polygon)
    if walls is not None:
        distances.append((MAP_WALLS, walls))
    return min(distances, key=lambda item: item[1])


def _polygon_map_distance(world: World, polygon: Sequence[Point]) -> float | None:
    """Distance (m) between a polygon and the map's solid cells (None without a map): exact
    (cell squares as boxes) where a cell lies within the polygon's circumcircle, else the
    centre's distance less the circumradius, a lower bound that is positive."""
    cx = sum(x for x, _ in polygon) / len(polygon)
    cy = sum(y for _, y in polygon) / len(polygon)
    centre = map_distance_at(world, cx, cy)
    grid, solid = world.grid, world.map_solid()
    if centre is None or grid is None or solid is None:
        return None
    reach = max(math.hypot(x - cx, y - cy) for x, y in polygon)
    if centre >= reach:
        return centre - reach
    (x0, y0), step = grid.origin, grid.resolution
    low_x, low_y = (
        max(math.floor((cx - reach - x0) / step), 0),
        max(math.floor((cy - reach - y0) / step), 0),
    )
    rows, cols = solid[
        low_y : math.ceil((cy + reach - y0) / step) + 1,
        low_x : math.ceil((cx + reach - x0) / step) + 1,
    ].nonzero()
    cells = [
        Box(
            name=MAP_WALLS,
            center=(x0 + (low_x + col + 0.5) * step, y0 + (low_y + row + 0.5) * step),
            size=(step, step),
        )
        for row, col in zip(rows.tolist(), cols.tolist(), strict=True)
    ]
    return min(_polygon_distance(polygon, cell) for cell in cells) if cells else centre - reach


def _floor_edge_distance(world: World, point: Point) -> float:
    x_min, y_min, x_max, y_max = world.bounds
    return min(point[0] - x_min, x_max - point[0], point[1] - y_min, y_max - point[1])
