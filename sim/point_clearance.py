"""Signed distances from one point to a world's obstacles, in plain floating-point math.

The same formulas as :mod:`baobab.sim.geometry` (boxes with yaw, upright cylinders, seen from
above; positive outside, negative inside), for a single point and without numpy, so that
checking the poses of a mission (``baobab validate``) does not pay numpy's import.
"""

from __future__ import annotations

import math

from baobab.sim.world import Box, Cylinder, World


def box_distance_at(x: float, y: float, box: Box) -> float:
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


def cylinder_distance_at(x: float, y: float, cylinder: Cylinder) -> float:
    """Signed distance (m) from (x, y) (m) to the circle of ``cylinder``."""
    px, py = x - cylinder.center[0], y - cylinder.center[1]
    return math.sqrt(px * px + py * py) - cylinder.radius


def obstacle_distances_at(world: World, x: float, y: float) -> list[tuple[str, float]]:
    """(name, signed distance (m)) to every static obstacle: boxes, cylinders, then the map's
    solid cells (named :data:`MAP_WALLS`) on a world that stands on a map."""
    distances = [(box.name, box_distance_at(x, y, box)) for box in world.boxes]
    distances += [(cyl.name, cylinder_distance_at(x, y, cyl)) for cyl in world.cylinders]
    distance = map_distance_at(world, x, y)
    if distance is not None:
        distances.append((MAP_WALLS, distance))
    return distances


MAP_WALLS = "the map's walls"
"""The name a map's solid cells go by in clearance reports."""


def map_distance_at(world: World, x: float, y: float) -> float | None:
    """Signed distance (m) from (x, y) to the map's nearest solid cell; None without a map."""
    grid, solid = world.grid, world.map_solid()
    if grid is None or solid is None:
        return None
    from baobab.sim.map_geometry import signed_distance_to_cells  # numpy: maps only

    return signed_distance_to_cells(solid, grid.origin, grid.resolution, x, y)
