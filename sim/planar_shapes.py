"""Plain-math planar geometry of rectangles and circles seen from above, without numpy.

The world file's checks (``baobab validate``) use these, so they cost no numpy import. A
rectangle is anything with a ``center`` (m), full side lengths ``size`` (m) and a ``yaw`` (rad),
a circle anything with a ``center`` and a ``radius`` (m): the world's boxes and cylinders, a
dock's parts. Distances are signed: positive outside, negative inside.
"""

from __future__ import annotations

import math
from typing import Protocol


class Rectangle(Protocol):
    """A rectangle in the plane."""

    @property
    def center(self) -> tuple[float, float]:
        """Centre (m)."""
        ...

    @property
    def size(self) -> tuple[float, float]:
        """Full side lengths along its own x and y (m)."""
        ...

    @property
    def yaw(self) -> float:
        """Heading of its own x axis (rad)."""
        ...


class Circle(Protocol):
    """A circle in the plane."""

    @property
    def center(self) -> tuple[float, float]:
        """Centre (m)."""
        ...

    @property
    def radius(self) -> float:
        """Radius (m)."""
        ...


def rectangle_distance_at(x: float, y: float, box: Rectangle) -> float:
    """Signed distance (m) from (x, y) (m) to the outline of ``box``."""
    px, py = x - box.center[0], y - box.center[1]
    cos, sin = math.cos(box.yaw), math.sin(box.yaw)
    # Rotate into the box frame by -yaw.
    local_x, local_y = cos * px + sin * py, -sin * px + cos * py
    excess_x = abs(local_x) - box.size[0] / 2
    excess_y = abs(local_y) - box.size[1] / 2
    outside = math.sqrt(max(excess_x, 0.0) ** 2 + max(excess_y, 0.0) ** 2)
    inside = min(max(excess_x, excess_y), 0.0)
    return outside + inside


def circle_distance_at(x: float, y: float, circle: Circle) -> float:
    """Signed distance (m) from (x, y) (m) to ``circle``."""
    return math.hypot(x - circle.center[0], y - circle.center[1]) - circle.radius


def rectangle_corners(box: Rectangle) -> list[tuple[float, float]]:
    """The four corners (m), counter-clockwise from the one at the box's -x, -y."""
    cos, sin = math.cos(box.yaw), math.sin(box.yaw)
    half_x, half_y = box.size[0] / 2, box.size[1] / 2
    return [
        (box.center[0] + cos * dx - sin * dy, box.center[1] + sin * dx + cos * dy)
        for dx, dy in ((-half_x, -half_y), (half_x, -half_y), (half_x, half_y), (-half_x, half_y))
    ]


def rectangles_overlap(a: Rectangle, b: Rectangle) -> bool:
    """True when the two rectangles share area (separating axis test; touching is not)."""
    corners_a, corners_b = rectangle_corners(a), rectangle_corners(b)
    for yaw in (a.yaw, a.yaw + math.pi / 2, b.yaw, b.yaw + math.pi / 2):
        axis = (math.cos(yaw), math.sin(yaw))
        span_a = [axis[0] * x + axis[1] * y for x, y in corners_a]
        span_b = [axis[0] * x + axis[1] * y for x, y in corners_b]
        if max(span_a) <= min(span_b) + 1e-9 or max(span_b) <= min(span_a) + 1e-9:
            return False
    return True


def rectangle_meets_circle(box: Rectangle, circle: Circle) -> bool:
    """True when the rectangle and the circle share area."""
    return rectangle_distance_at(circle.center[0], circle.center[1], box) < circle.radius - 1e-9
