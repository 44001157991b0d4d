"""A route graph against a world's geometry: nodes on the floor, nodes and edges clear of
obstacles.

A world file's ``route_graph`` (and a mission's) is checked here when it is loaded, so a
graph that a robot could never drive is a located error in the graph file rather than a route
that fails at run time. The world is seen through :class:`Floorplan` (what :class:`~baobab.sim.
world.World` has), so this module does not import the world module that loads graphs.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Protocol

from baobab.sim.errors import WorldError
from baobab.sim.planar_shapes import Circle, Rectangle
from baobab.sim.route_graph_file import RouteGraph

Point = tuple[float, float]


class BoxShape(Rectangle, Protocol):
    """A named box seen from above (a :class:`~baobab.sim.planar_shapes.Rectangle`)."""

    @property
    def name(self) -> str: ...


class CircleShape(Circle, Protocol):
    """A named upright cylinder seen from above (a :class:`~baobab.sim.planar_shapes.Circle`)."""

    @property
    def name(self) -> str: ...


class Floorplan(Protocol):
    """A world as the check sees it: its floor and its static obstacles."""

    @property
    def name(self) -> str: ...
    @property
    def boxes(self) -> Sequence[BoxShape]: ...
    @property
    def cylinders(self) -> Sequence[CircleShape]: ...
    @property
    def bounds(self) -> tuple[float, float, float, float]: ...
    def contains(self, x: float, y: float) -> bool: ...


def check_on_world(graph: RouteGraph, world: Floorplan) -> None:
    """Refuse a graph whose nodes or edges the world's geometry makes impossible.

    Raises:
        WorldError: located at the node or edge in the graph file: a node off the floor or
            inside (or on) an obstacle; an edge crossing or touching an obstacle.
    """
    for node in graph.nodes:
        where = (node.x, node.y)
        if not world.contains(node.x, node.y):
            x_min, y_min, x_max, y_max = world.bounds
            raise WorldError(
                graph.path,
                *graph.node_lines[node.id],
                f"node {node.id} at ({node.x:g}, {node.y:g}) is outside the floor of world "
                f"'{world.name}' (x {x_min:g}..{x_max:g}, y {y_min:g}..{y_max:g})",
            )
        hit = _first_hit(world, where, where)
        if hit is not None:
            raise WorldError(
                graph.path,
                *graph.node_lines[node.id],
                f"node {node.id} at ({node.x:g}, {node.y:g}) is inside obstacle '{hit}'",
            )
    for edge in graph.edges:
        start, end = graph.node(edge.start), graph.node(edge.end)
        hit = _first_hit(world, (start.x, start.y), (end.x, end.y))
        if hit is not None:
            raise WorldError(
                graph.path,
                *graph.edge_lines[edge.id],
                f"edge {edge.id} from node {edge.start} to node {edge.end} passes through "
                f"obstacle '{hit}'",
            )


def _first_hit(world: Floorplan, start: Point, end: Point) -> str | None:
    """The name of the first obstacle the segment from ``start`` to ``end`` (m) touches."""
    for box in world.boxes:
        if segment_hits_box(box, start, end):
            return box.name
    for cylinder in world.cylinders:
        if segment_hits_circle(cylinder, start, end):
            return cylinder.name
    return None


def segment_hits_circle(circle: CircleShape, start: Point, end: Point) -> bool:
    """True when the segment from ``start`` to ``end`` (m) touches the disc of ``circle``."""
    cx, cy = circle.center
    ax, ay, dx, dy = start[0] - cx, start[1] - cy, end[0] - start[0], end[1] - start[1]
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 == 0 else max(0.0, min(1.0, -(ax * dx + ay * dy) / length2))
    return math.hypot(ax + t * dx, ay + t * dy) <= circle.radius


def segment_hits_box(box: BoxShape, start: Point, end: Point) -> bool:
    """True when the segment from ``start`` to ``end`` (m) touches the rectangle of ``box``."""
    cx, cy = box.center
    cos, sin = math.cos(box.yaw), math.sin(box.yaw)

    def local(point: Point) -> Point:  # into the box frame: translate, then rotate by -yaw
        px, py = point[0] - cx, point[1] - cy
        return cos * px + sin * py, -sin * px + cos * py

    (ax, ay), (bx, by) = local(start), local(end)
    # Liang-Barsky: clip the segment's parameter range to the box's two slabs.
    low, high = 0.0, 1.0
    for origin, delta, half in ((ax, bx - ax, box.size[0] / 2), (ay, by - ay, box.size[1] / 2)):
        if delta == 0:
            if abs(origin) > half:
                return False
            continue
        t1, t2 = (-half - origin) / delta, (half - origin) / delta
        low, high = max(low, min(t1, t2)), min(high, max(t1, t2))
        if low > high:
            return False
    return True
