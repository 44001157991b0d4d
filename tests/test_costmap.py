"""Costmap grid, layers and layered costmaps: exact values against independent computations."""

from __future__ import annotations

import math

import numpy as np
import pytest

from baobab.nav.costmap import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    Costmap2D,
)
from baobab.nav.footprint import collision_mask, in_collision, project_motion, time_to_collision
from baobab.nav.layered_costmap import CostmapParams, LayeredCostmap
from baobab.nav.layers import InflationLayer, StaticLayer
from baobab.sim.lidar import LaserScan
from baobab.sim.world import Box, Cylinder, Floor, Pose2D, World

RES = 0.05


def make_world(
    size: tuple[float, float] = (4.0, 4.0),
    boxes: tuple[Box, ...] = (),
    cylinders: tuple[Cylinder, ...] = (),
) -> World:
    return World(
        name="test",
        floor=Floor(size=size),
        boxes=list(boxes),
        cylinders=list(cylinders),
        spawns={"default": Pose2D(x=0.0, y=0.0)},
    )


def ray_box_range(x: float, y: float, heading: float, box: tuple[float, ...]) -> float:
    """Distance along a ray to an axis-aligned box (x0, y0, x1, y1), inf if missed (slabs)."""
    x0, y0, x1, y1 = box
    dx, dy = math.cos(heading), math.sin(heading)
    t_near, t_far = -math.inf, math.inf
    for origin, direction, lo, hi in ((x, dx, x0, x1), (y, dy, y0, y1)):
        if abs(direction) < 1e-12:
            if not lo <= origin <= hi:
                return math.inf
            continue
        t0, t1 = sorted(((lo - origin) / direction, (hi - origin) / direction))
        t_near, t_far = max(t_near, t0), min(t_far, t1)
    return t_near if t_near <= t_far and t_near > 0 else math.inf


def synthetic_scan(
    pose: Pose2D, boxes: list[tuple[float, ...]], range_max: float = 3.5
) -> LaserScan:
    """A 360-beam scan of axis-aligned boxes, like the LDS-01 (0.12-3.5 m)."""
    n = 360
    increment = 2 * math.pi / n
    ranges = np.full(n, np.inf)
    for i in range(n):
        heading = pose.yaw + i * increment
        hit = min((ray_box_range(pose.x, pose.y, heading, b) for b in boxes), default=math.inf)
        if hit <= range_max:
            ranges[i] = hit
    return LaserScan(
        stamp=0.0,
        frame_id="base_scan",
        angle_min=0.0,
        angle_max=(n - 1) * increment,
        angle_increment=increment,
        range_min=0.12,
        range_max=range_max,
        ranges=ranges,
        sensor_pose=pose,
    )


def test_world_to_map_and_back() -> None:
    grid = Costmap2D(40, 20, RES, origin=(-1.0, -0.5))
    assert grid.world_to_map(-1.0, -0.5) == (0, 0)
    assert grid.world_to_map(0.999, 0.499) == (39, 19)
    assert grid.world_to_map(1.0, 0.0) is None
    assert grid.world_to_map(-1.001, 0.0) is None
    assert grid.map_to_world(3, 4) == pytest.approx((-0.825, -0.275))
    xs, ys = np.array([-0.88, 0.21, 5.0]), np.array([-0.38, 0.31, 0.0])
    ix, iy, inside = grid.world_to_map_array(xs, ys)
    assert inside.tolist() == [True, True, False]
    assert (ix[:2].tolist(), iy[:2].tolist()) == ([2, 24], [2, 16])
    grid.data[16, 24] = LETHAL_OBSTACLE
    assert grid.cost(0.21, 0.31) == LETHAL_OBSTACLE
    assert grid.costs(xs, ys, outside=7).tolist() == [0, 254, 7]


def test_inflation_formula_values() -> None:
    layer = InflationLayer()
    distances = np.array([0.0, 0.05, 0.105, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.55, 0.56, 1.0])
    expected = [254, 253, 253, 220, 189, 163, 140, 104, 77, 66, 0, 0]
    assert layer.cost_of_distance(distances).tolist() == expected


def test_inflation_around_one_lethal_cell() -> None:
    # A 1 cm post at a cell centre makes exactly one lethal cell.
    world = make_world(cylinders=(Cylinder(name="post", center=(0.025, 0.025), radius=0.01),))
    costmap = LayeredCostmap.global_costmap(world).costmap
    ix, iy = costmap.world_to_map(0.025, 0.025) or (-1, -1)

    def at(dx: int, dy: int) -> int:
        return int(costmap.data[iy + dy, ix + dx])

    assert at(0, 0) == LETHAL_OBSTACLE
    assert (at(1, 0), at(2, 0), at(0, -2), at(1, 1)) == (253, 253, 253, 253)
    assert at(3, 0) == 220  # 0.15 m
    assert at(2, 2) == 225  # 0.1414 m
    assert at(3, 1) == 214  # 0.1581 m
    assert at(3, 4) == 163  # 0.25 m
    assert at(0, 6) == 140  # 0.30 m
    assert at(-11, 0) == 66  # 0.55 m, the inflation radius
    assert at(-12, 0) == FREE_SPACE
    assert at(8, 8) == FREE_SPACE  # 0.566 m
    lethal = costmap.data == LETHAL_OBSTACLE
    assert lethal[5:-5, 5:-5].sum() == 1


def _clipped_area(
    polygon: list[tuple[float, float]], x0: float, y0: float, x1: float, y1: float
) -> float:
    """Area of a convex polygon clipped to a rectangle (Sutherland-Hodgman), for the test."""
    edges = [(0, x0, 1), (0, x1, -1), (1, y0, 1), (1, y1, -1)]
    points = polygon
    for axis, bound, side in edges:
        clipped: list[tuple[float, float]] = []
        for i, current in enumerate(points):
            previous = points[i - 1]
            inside_c = side * (current[axis] - bound) >= 0
            inside_p = side * (previous[axis] - bound) >= 0
            if inside_c != inside_p:
                t = (bound - previous[axis]) / (current[axis] - previous[axis])
                clipped.append(
                    (
                        previous[0] + t * (current[0] - previous[0]),
                        previous[1] + t * (current[1] - previous[1]),
                    )
                )
            if inside_c:
                clipped.append(current)
        points = clipped
        if not points:
            return 0.0
    return 0.5 * abs(
        sum(points[i - 1][0] * p[1] - p[0] * points[i - 1][1] for i, p in enumerate(points))
    )


def test_static_layer_matches_analytic_geometry() -> None:
    aligned = Box(name="aligned", center=(-1.0, 1.0), size=(0.5, 0.2))  # faces on cell edges
    rotated = Box(name="rotated", center=(0.6, -0.7), size=(0.9, 0.23), yaw=0.5)
    table = Cylinder(name="table", center=(-0.9, -0.8), radius=0.33)
    world = make_world(size=(4.0, 3.6), boxes=(aligned, rotated), cylinders=(table,))
    static = StaticLayer(world, RES)
    assert (static.size_x, static.size_y) == (82, 74)  # floor plus one border cell each side
    half = RES / 2
    expected = np.zeros_like(static.raster, dtype=bool)
    for iy in range(static.size_y):
        for ix in range(static.size_x):
            cx = static.origin_x + (ix + 0.5) * RES
            cy = static.origin_y + (iy + 0.5) * RES
            x0, y0, x1, y1 = cx - half, cy - half, cx + half, cy + half
            off_floor = x0 < -2.0 - 1e-9 or x1 > 2.0 + 1e-9 or y0 < -1.8 - 1e-9 or y1 > 1.8 + 1e-9
            boxes_hit = False
            for box in (aligned, rotated):
                c, s = math.cos(box.yaw), math.sin(box.yaw)
                a, b = box.size[0] / 2, box.size[1] / 2
                corners = [
                    (box.center[0] + c * u - s * v, box.center[1] + s * u + c * v)
                    for u, v in ((-a, -b), (a, -b), (a, b), (-a, b))
                ]
                boxes_hit |= _clipped_area(corners, x0, y0, x1, y1) > 1e-12
            nearest_x = min(max(table.center[0], x0), x1)
            nearest_y = min(max(table.center[1], y0), y1)
            cylinder_hit = math.dist((nearest_x, nearest_y), table.center) < table.radius
            expected[iy, ix] = off_floor or boxes_hit or cylinder_hit
    assert np.array_equal(static.raster == LETHAL_OBSTACLE, expected)
    # The aligned box covers exactly 10 x 4 cells: touching a cell edge is not overlapping.
    ix0, iy0 = static.lattice_index(-1.25, 0.9)
    assert static.raster[iy0 : iy0 + 4, ix0 : ix0 + 10].min() == LETHAL_OBSTACLE
    assert static.raster[iy0 - 1, ix0 : ix0 + 10].max() == FREE_SPACE
    assert static.raster[iy0 : iy0 + 4, ix0 + 10].max() == FREE_SPACE


def test_obstacle_layer_marks_a_box_and_clears_it_when_it_leaves() -> None:
    world = make_world(size=(8.0, 8.0))
    costmap = LayeredCostmap.global_costmap(world)
    robot = Pose2D(x=0.0, y=0.0, yaw=0.3)
    crate = (1.01, -0.21, 1.31, 0.21)  # faces off cell edges, so each hit has one cell
    costmap.update(robot, [synthetic_scan(robot, [crate])])
    grid = costmap.costmap
    face = [(1.02, y) for y in np.linspace(-0.15, 0.15, 7)]
    assert all(grid.cost(x, y) == LETHAL_OBSTACLE for x, y in face)
    assert grid.cost(0.93, 0.0) == INSCRIBED_INFLATED_OBSTACLE  # 0.10 m from the marks
    assert grid.cost(0.7, 0.0) == 140  # 0.30 m
    assert grid.cost(0.3, 0.0) == FREE_SPACE
    # The inside of the crate is hidden from the sensor: not marked.
    assert costmap.obstacle_layer.grid.cost(1.2, 0.0) == FREE_SPACE
    revision = costmap.revision
    # Seeing the same scene again changes no cell, so nothing is recomputed.
    costmap.update(robot, [synthetic_scan(robot, [crate])])
    _ = costmap.costmap
    assert costmap.revision == revision
    # The crate is taken away: the next scan sees through and clears every marked cell.
    costmap.update(robot, [synthetic_scan(robot, [])])
    assert not costmap.obstacle_layer.grid.data.any()
    assert all(costmap.costmap.cost(x, y) == FREE_SPACE for x, y in face)
    assert costmap.revision == revision + 1


def test_obstacle_layer_ranges() -> None:
    world = make_world(size=(10.0, 10.0))
    costmap = LayeredCostmap.global_costmap(world)
    robot = Pose2D(x=-4.0, y=0.0)
    near, far = (-1.99, 0.91, -1.89, 1.11), (-1.29, -0.11, -1.19, 0.11)  # 2.2 m, 2.7 m away
    costmap.update(robot, [synthetic_scan(robot, [near, far])])
    obstacles = costmap.obstacle_layer.grid
    assert obstacles.cost(-1.98, 1.0) == LETHAL_OBSTACLE  # within obstacle_max_range
    hit_cell = obstacles.world_to_map(-1.28, 0.0) or (0, 0)
    assert obstacles.data[:, hit_cell[0]].max() == FREE_SPACE  # beyond it: not marked
    # A stale mark in front of the far box is cleared (raytrace 3.0 m), the box's own cell kept.
    stale = obstacles.world_to_map(-1.5, 0.0) or (0, 0)
    obstacles.data[stale[1], stale[0]] = LETHAL_OBSTACLE
    obstacles.data[hit_cell[1], hit_cell[0]] = LETHAL_OBSTACLE
    costmap.update(robot, [synthetic_scan(robot, [near, far])])
    assert obstacles.data[stale[1], stale[0]] == FREE_SPACE
    assert obstacles.data[hit_cell[1], hit_cell[0]] == LETHAL_OBSTACLE
    # Beyond the raytrace range nothing is cleared.
    beyond = obstacles.world_to_map(-0.8, 0.0) or (0, 0)
    obstacles.data[beyond[1], beyond[0]] = LETHAL_OBSTACLE
    costmap.update(robot, [synthetic_scan(robot, [])])
    assert obstacles.data[beyond[1], beyond[0]] == LETHAL_OBSTACLE


def test_rolling_window_follows_the_robot() -> None:
    wall = Box(name="wall", center=(1.5, 0.0), size=(0.2, 2.0))
    world = make_world(size=(8.0, 8.0), boxes=(wall,))
    static = StaticLayer(world, RES)
    whole = LayeredCostmap.global_costmap(world, static=static).costmap
    local = LayeredCostmap.local_costmap(world, Pose2D(x=0.0, y=0.0), static=static)
    grid = local.costmap
    assert (grid.size_x, grid.size_y) == (60, 60)
    assert grid.bounds == pytest.approx((-1.5, -1.5, 1.5, 1.5))
    for x, y in [(0.43, 0.27), (-0.3, 0.9), (2.2, -1.1), (-3.6, 3.9)]:
        local.update(Pose2D(x=x, y=y))
        grid = local.costmap
        x0, y0, x1, y1 = grid.bounds
        assert abs((x0 + x1) / 2 - x) <= RES / 2 + 1e-9
        assert abs((y0 + y1) / 2 - y) <= RES / 2 + 1e-9
        # The window is a slice of the global map (static cells beyond it inflate into it).
        ix, iy = static.lattice_index(x0, y0)
        padded = np.pad(whole.data, 60, constant_values=LETHAL_OBSTACLE)
        assert np.array_equal(grid.data, padded[iy + 60 : iy + 120, ix + 60 : ix + 120])


def test_rolling_window_keeps_obstacles_in_place_while_they_stay_inside() -> None:
    world = make_world(size=(8.0, 8.0))
    local = LayeredCostmap.local_costmap(world, Pose2D(x=0.0, y=0.0))
    crate = (-1.01, -0.11, -0.81, 0.11)
    robot = Pose2D(x=0.0, y=0.0, yaw=math.pi)
    local.update(robot, [synthetic_scan(robot, [crate])])
    assert local.costmap.cost(-0.82, 0.0) == LETHAL_OBSTACLE
    for x, y in [(0.43, 0.27), (-0.3, 0.9)]:
        local.update(Pose2D(x=x, y=y))
        assert local.costmap.cost(-0.82, 0.0) == LETHAL_OBSTACLE
        assert local.costmap.cost(-0.82, 0.3) != LETHAL_OBSTACLE
    local.update(Pose2D(x=2.2, y=-1.1))  # the crate leaves the window and is dropped
    assert local.costmap.cost(-0.82, 0.0) == 255
    local.update(Pose2D(x=0.0, y=0.0))
    assert local.costmap.cost(-0.82, 0.0) == FREE_SPACE


def test_clear_resets_only_the_obstacle_layer() -> None:
    world = make_world(boxes=(Box(name="wall", center=(0.0, 1.2), size=(2.0, 0.2)),))
    costmap = LayeredCostmap.global_costmap(world)
    before = costmap.costmap.data.copy()
    robot = Pose2D(x=0.0, y=-0.5)
    costmap.update(robot, [synthetic_scan(robot, [(0.51, -0.61, 0.71, -0.41)])])
    assert costmap.costmap.cost(0.52, -0.5) == LETHAL_OBSTACLE
    costmap.clear()
    assert not costmap.obstacle_layer.grid.data.any()
    assert np.array_equal(costmap.costmap.data, before)
    assert costmap.costmap.cost(0.0, 1.2) == LETHAL_OBSTACLE


def test_incremental_update_equals_full_recompute() -> None:
    world = make_world(
        size=(6.0, 6.0),
        boxes=(Box(name="b", center=(1.0, 1.0), size=(0.6, 0.3), yaw=0.4),),
        cylinders=(Cylinder(name="t", center=(-1.2, 0.5), radius=0.3),),
    )
    rng = np.random.default_rng(7)
    costmap = LayeredCostmap.global_costmap(world)
    for _ in range(6):
        robot = Pose2D(x=float(rng.uniform(-2, 2)), y=float(rng.uniform(-2, 2)), yaw=0.0)
        lo = rng.uniform(-2.5, 2.0, size=2)
        crate = (lo[0], lo[1], lo[0] + 0.3, lo[1] + 0.2)
        costmap.update(robot, [synthetic_scan(robot, [crate])])
        fresh = LayeredCostmap.global_costmap(world, static=costmap.static_layer)
        fresh.obstacle_layer.grid.data[:] = costmap.obstacle_layer.grid.data
        assert np.array_equal(costmap.costmap.data, fresh.costmap.data)


def test_local_costmap_without_static_layer_sees_only_obstacles() -> None:
    world = make_world(boxes=(Box(name="wall", center=(0.0, 1.0), size=(2.0, 0.2)),))
    params = CostmapParams(use_static_layer=False)
    local = LayeredCostmap.local_costmap(world, Pose2D(x=0.0, y=0.0), params=params)
    assert not local.costmap.data.any()


def test_footprint_collision_and_projection() -> None:
    world = make_world(boxes=(Box(name="wall", center=(1.0, 0.0), size=(0.2, 2.0)),))
    grid = LayeredCostmap.global_costmap(world).costmap
    assert in_collision(grid, 0.85, 0.0)  # 0.05 m from the wall: inside the inscribed radius
    assert not in_collision(grid, 0.6, 0.0)
    assert not in_collision(grid, 9.0, 0.0)  # off the map: unknown
    assert in_collision(grid, 9.0, 0.0, unknown_is_collision=True)
    assert collision_mask(grid, np.array([0.85, 0.6]), np.array([0.0, 0.0])).tolist() == [
        True,
        False,
    ]
    start = Pose2D(x=0.0, y=0.0, yaw=0.0)
    arc = project_motion(start, 0.2, 0.5, 2.0, 0.1)
    assert arc.shape == (20, 3)
    assert arc[-1] == pytest.approx([0.4 * math.sin(1.0), 0.4 * (1 - math.cos(1.0)), 1.0])
    # Towards the wall face at 0.9 m at 0.15 m/s: inscribed cells start at x = 0.8 m.
    hit = time_to_collision(grid, start, 0.15, 0.0, 8.0, 0.1)
    assert hit == pytest.approx(5.4)
    assert time_to_collision(grid, start, -0.2, 0.0, 5.0, 0.1) is None
    assert time_to_collision(grid, start, 0.0, 1.0, 3.0, 0.1) is None
