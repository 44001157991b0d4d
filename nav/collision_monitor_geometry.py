"""Plain-Python geometry of the collision monitor's zones, for checking them as they load.

A zone is a polygon (vertices in ``base_footprint``, m: x forward, y left) or a circle around
the ``base_footprint`` origin. These functions read Nav2's ``points`` parameter, tell whether
a polygon is usable (three vertices or more, an area, no crossing edges) and whether a zone
contains the robot's footprint. They load no numpy: ``baobab validate`` runs them.
"""

from __future__ import annotations

import ast
import itertools
import math
from collections.abc import Sequence
from typing import Any

from baobab.robots.footprint import Footprint

Point = tuple[float, float]
"""A point in ``base_footprint`` (m): x forward, y left."""

MAX_POINTS = 1_000
"""Most vertices of one polygon."""


def parse_points(value: Any) -> tuple[Point, ...]:
    """Nav2's ``points``: the string ``"[[x1, y1], [x2, y2], ...]"``, a list of ``[x, y]``
    pairs, or Humble's flat list ``[x1, y1, x2, y2, ...]`` (m).

    Raises:
        ValueError: anything else, a non-finite number, or more than :data:`MAX_POINTS`.
    """
    expected = 'expected "[[x1, y1], [x2, y2], ...]" (m) or a list of [x, y] pairs'
    if isinstance(value, str):
        try:
            value = ast.literal_eval(value.strip())
        except (ValueError, SyntaxError, MemoryError, RecursionError):
            raise ValueError(f"cannot read {value!r}; {expected}") from None
    if not isinstance(value, list | tuple):
        raise ValueError(f"{expected}")
    if value and all(_is_number(item) for item in value):
        if len(value) % 2:
            raise ValueError(f"an odd count of numbers ({len(value)}); {expected}")
        value = [value[i : i + 2] for i in range(0, len(value), 2)]
    points = []
    for item in value:
        if not (isinstance(item, list | tuple) and len(item) == 2 and all(map(_is_number, item))):
            raise ValueError(f"{item!r} is not an [x, y] pair; {expected}")
        x, y = float(item[0]), float(item[1])
        if not (math.isfinite(x) and math.isfinite(y)):
            raise ValueError(f"[{x}, {y}] is not finite")
        points.append((x, y))
    if len(points) > MAX_POINTS:
        raise ValueError(f"{len(points)} points; the limit is {MAX_POINTS}")
    return tuple(points)


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def polygon_problem(points: Sequence[Point]) -> str | None:
    """Why ``points`` is not a usable zone (fewer than 3 points, no area, crossing edges)."""
    if len(points) < 3:
        return f"a polygon needs at least 3 points, got {len(points)}"
    edges = list(zip(points, [*points[1:], points[0]], strict=True))
    for (i, a), (j, b) in itertools.combinations(enumerate(edges), 2):
        neighbours = j == i + 1 or (i == 0 and j == len(edges) - 1)
        if not neighbours and _segments_cross(*a, *b):
            return f"the polygon's edges {i + 1} and {j + 1} cross; list the points in order"
    if abs(signed_area(points)) < 1e-9:
        return "the polygon has no area (its points lie on one line)"
    return None


def signed_area(points: Sequence[Point]) -> float:
    """The shoelace area (m^2): positive counter-clockwise."""
    pairs = zip(points, [*points[1:], points[0]], strict=True)
    return sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in pairs) / 2


def point_inside(points: Sequence[Point], x: float, y: float) -> bool:
    """Ray crossing (Shimrat's Algorithm 112): True when ``(x, y)`` lies inside."""
    inside = False
    for (xi, yi), (xj, yj) in zip([points[-1], *points[:-1]], points, strict=True):
        if (y <= yi) != (y <= yj) and x < xi + (y - yi) * (xj - xi) / (yj - yi):
            inside = not inside
    return inside


def contains_footprint(points: Sequence[Point] | None, radius: float, footprint: Footprint) -> bool:
    """True when the zone (``points``, or a circle of ``radius`` without them) holds the
    whole ``footprint``."""
    if points is None:
        return radius >= footprint.circumscribed_radius - 1e-9
    if footprint.radius is None:
        outline = footprint.polygon
        return all(point_inside(points, x, y) for x, y in outline) and not any(
            _segments_cross(*a, *b)
            for a in zip(points, [*points[1:], points[0]], strict=True)
            for b in zip(outline, [*outline[1:], outline[0]], strict=True)
        )
    # the zone's inscribed radius: the distance from base_footprint to its nearest edge
    nearest_edge = Footprint(polygon=tuple(points)).inscribed_radius
    return point_inside(points, 0.0, 0.0) and nearest_edge >= footprint.radius - 1e-9


def describe_footprint(footprint: Footprint) -> str:
    """``a circle of radius 0.105 m`` or ``a polygon of 4 points``."""
    if footprint.radius is None:
        return f"a polygon of {len(footprint.polygon)} points"
    return f"a circle of radius {footprint.radius:g} m"


def _segments_cross(a: Point, b: Point, c: Point, d: Point) -> bool:
    """True when segments ``ab`` and ``cd`` properly cross (touching ends do not count)."""

    def side(p: Point, q: Point, r: Point) -> float:
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    d1, d2 = side(c, d, a), side(c, d, b)
    d3, d4 = side(a, b, c), side(a, b, d)
    return d1 * d2 < 0 and d3 * d4 < 0
