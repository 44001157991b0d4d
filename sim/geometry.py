"""Exact planar geometry on a world: clearances, distance rasters and reachability.

Everything works in the map frame, in metres, on the footprint of the obstacles (boxes with yaw,
upright cylinders) seen from above. Distances are signed: positive outside an obstacle,
negative inside it. The floor edge counts as a boundary the robot must keep clear of, like a
wall, so a clearance is the distance to whichever comes first.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from baobab.sim.point_clearance import MAP_WALLS, map_distance_at
from baobab.sim.world import Box, Cylinder, World

FloatArray = NDArray[np.float64]

FLOOR_EDGE = "floor edge"
"""The name :func:`nearest_obstacle` gives the floor boundary."""


def _as_points(points: ArrayLike) -> FloatArray:
    array = np.asarray(points, dtype=np.float64)
    if array.ndim == 1:
        array = array.reshape(1, -1)
    if array.shape[-1] != 2:
        raise ValueError(f"points must have shape (..., 2), got {array.shape}")
    return array


def box_distance(points: ArrayLike, box: Box) -> FloatArray:
    """Signed distance (m) from each point of ``points`` (shape (..., 2)) to the box outline."""
    p = _as_points(points) - np.asarray(box.center)
    cos, sin = np.cos(box.yaw), np.sin(box.yaw)
    # Rotate into the box frame by -yaw.
    local = np.stack((cos * p[..., 0] + sin * p[..., 1], -sin * p[..., 0] + cos * p[..., 1]), -1)
    excess = np.abs(local) - np.asarray(box.size) / 2
    outside = np.linalg.norm(np.maximum(excess, 0.0), axis=-1)
    inside = np.minimum(excess.max(axis=-1), 0.0)
    return outside + inside


def cylinder_distance(points: ArrayLike, cylinder: Cylinder) -> FloatArray:
    """Signed distance (m) from each point of ``points`` (shape (..., 2)) to the circle."""
    p = _as_points(points) - np.asarray(cylinder.center)
    return np.linalg.norm(p, axis=-1) - cylinder.radius


def floor_edge_distance(world: World, points: ArrayLike) -> FloatArray:
    """Distance (m) from each point to the floor edge: positive on the floor, negative off it."""
    p = _as_points(points)
    x_min, y_min, x_max, y_max = world.bounds
    return np.minimum.reduce(
        [p[..., 0] - x_min, x_max - p[..., 0], p[..., 1] - y_min, y_max - p[..., 1]]
    )


def obstacle_names(world: World) -> list[str]:
    """Names of the static obstacles, in the row order of :func:`obstacle_distances`."""
    return [box.name for box in world.boxes] + [cyl.name for cyl in world.cylinders]


def obstacle_distances(world: World, points: ArrayLike) -> FloatArray:
    """Signed distance (m) from every point to every obstacle: shape (obstacles, *points)."""
    p = _as_points(points)
    rows = [box_distance(p, box) for box in world.boxes]
    rows += [cylinder_distance(p, cylinder) for cylinder in world.cylinders]
    if not rows:
        return np.empty((0, *p.shape[:-1]))
    return np.stack(rows)


def clearance(world: World, points: ArrayLike) -> FloatArray:
    """Distance (m) from each point to the nearest obstacle surface or the floor edge.

    Negative inside an obstacle or off the floor. A map's solid cells count as obstacles.
    """
    p = _as_points(points)
    nearest = floor_edge_distance(world, p)
    for box in world.boxes:
        nearest = np.minimum(nearest, box_distance(p, box))
    for cylinder in world.cylinders:
        nearest = np.minimum(nearest, cylinder_distance(p, cylinder))
    if world.grid is not None:
        flat = p.reshape(-1, 2)
        walls = np.array([map_distance_at(world, float(x), float(y)) for x, y in flat])
        nearest = np.minimum(nearest, walls.reshape(p.shape[:-1]))
    return nearest


def nearest_obstacle(world: World, x: float, y: float) -> tuple[str, float]:
    """Name of the obstacle (or ``FLOOR_EDGE``, or the map's walls) nearest to (x, y) and its
    signed distance (m)."""
    names = [*obstacle_names(world), FLOOR_EDGE]
    distances = np.append(
        obstacle_distances(world, (x, y))[:, 0], floor_edge_distance(world, (x, y))
    )
    walls = map_distance_at(world, x, y)
    if walls is not None:
        names.append(MAP_WALLS)
        distances = np.append(distances, walls)
    index = int(np.argmin(distances))
    return names[index], float(distances[index])


@dataclass(frozen=True)
class ClearanceGrid:
    """The clearance of the cell centres of a regular grid laid over the floor.

    ``values[row, col]`` is the clearance (m) at ``origin + ((col + 0.5), (row + 0.5)) *
    resolution``: rows run along y, columns along x.
    """

    origin: tuple[float, float]
    resolution: float
    values: FloatArray

    def cell(self, x: float, y: float) -> tuple[int, int]:
        """(row, col) of the cell holding the map point (x, y) (m); may lie outside the grid."""
        col = int(np.floor((x - self.origin[0]) / self.resolution))
        row = int(np.floor((y - self.origin[1]) / self.resolution))
        return row, col

    def centre(self, row: int, col: int) -> tuple[float, float]:
        """Map coordinates (m) of the centre of cell (row, col)."""
        return (
            self.origin[0] + (col + 0.5) * self.resolution,
            self.origin[1] + (row + 0.5) * self.resolution,
        )

    def free(self, radius: float) -> NDArray[np.bool_]:
        """Cells where a disc of ``radius`` (m) fits without touching anything."""
        return self.values >= radius


def clearance_grid(world: World, resolution: float = 0.05) -> ClearanceGrid:
    """Rasterise the world's clearance at cell centres, exactly, on a grid of ``resolution`` (m)."""
    if not resolution > 0:
        raise ValueError(f"resolution must be positive, got {resolution}")
    x_min, y_min, x_max, y_max = world.bounds
    cols = int(np.ceil((x_max - x_min) / resolution))
    rows = int(np.ceil((y_max - y_min) / resolution))
    xs = x_min + (np.arange(cols) + 0.5) * resolution
    ys = y_min + (np.arange(rows) + 0.5) * resolution
    grid_x, grid_y = np.meshgrid(xs, ys)
    values = clearance(world, np.stack((grid_x, grid_y), axis=-1))
    return ClearanceGrid(origin=(x_min, y_min), resolution=resolution, values=values)


def reachable(free: NDArray[np.bool_], start: tuple[int, int]) -> NDArray[np.bool_]:
    """Flood fill: the cells of ``free`` joined to ``start`` through 4-connected free cells.

    Returns an all-false mask when ``start`` lies outside the grid or on a blocked cell.
    """
    row, col = start
    if not (0 <= row < free.shape[0] and 0 <= col < free.shape[1]) or not free[row, col]:
        return np.zeros_like(free, dtype=bool)
    from scipy import ndimage  # imported here: `baobab validate` needs no raster geometry

    labels, _ = ndimage.label(free)  # the default structure is 4-connected in 2D
    return np.asarray(labels == labels[row, col])
