"""Signed distances from one point to a world's obstacles, in plain floating-point math.

The same formulas as :mod:`baobab.sim.geometry` (boxes with yaw, upright cylinders, seen from
above; positive outside, negative inside), for a single point and without numpy, so that
checking the poses of a mission (``baobab validate``) does not pay numpy's import.
"""

from __future__ import annotations

from baobab.sim.planar_shapes import circle_distance_at, rectangle_distance_at
from baobab.sim.world import World


def obstacle_distances_at(world: World, x: float, y: float) -> list[tuple[str, float]]:
    """(name, signed distance (m)) to every static obstacle: boxes (the docks' parts last),
    cylinders, then the map's solid cells (named :data:`MAP_WALLS`) on a world that stands on a
    map."""
    boxes = [*world.boxes, *world.dock_boxes]
    distances = [(box.name, rectangle_distance_at(x, y, box)) for box in boxes]
    distances += [(cyl.name, circle_distance_at(x, y, cyl)) for cyl in world.cylinders]
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
