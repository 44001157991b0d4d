"""The compiled costmap kernels against straightforward computations, cell by cell.

The obstacle layer's ray tracing is compared with the plain formula it replaced (every beam
sampled every half cell, each sample's cell by division), written here with numpy; the layered
costmap's incremental master with a full recompute by ``scipy.ndimage.distance_transform_edt``
after every update of random rolling and fixed windows.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.ndimage import distance_transform_edt

from baobab.nav.costmap import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
    Costmap2D,
)
from baobab.nav.layered_costmap import CostmapParams, LayeredCostmap
from baobab.nav.layers import InflationLayer, ObstacleLayer, ObstacleParams, StaticLayer
from baobab.nav.raytrace_kernels import cell_thresholds
from baobab.sim.lidar import LaserScan
from baobab.sim.world import Box, Cylinder, Floor, Pose2D, World


def reference_trace(
    data: np.ndarray,
    origin: tuple[float, float],
    resolution: float,
    scan: LaserScan,
    params: ObstacleParams,
) -> tuple[np.ndarray, tuple[int, int, int, int] | None]:
    """The obstacle layer update as first written: sample, divide, clear, then mark."""
    out = data.copy()
    height, width = out.shape
    ranges = np.asarray(scan.ranges, dtype=float)
    pose = scan.sensor_pose
    headings = (pose.yaw + scan.angles).tolist()
    cos_h = np.array([math.cos(heading) for heading in headings])  # the C library's, as compiled
    sin_h = np.array([math.sin(heading) for heading in headings])
    valid = ~np.isnan(ranges) & (ranges >= max(scan.range_min, 0.0))
    hit = valid & np.isfinite(ranges)
    clear_to = np.where(
        hit, np.minimum(ranges, params.raytrace_max_range), params.raytrace_max_range
    )
    clear_to = np.where(valid, clear_to, 0.0)
    mark = hit & (ranges < params.obstacle_max_range) & (ranges >= params.obstacle_min_range)
    t = np.arange(
        max(params.raytrace_min_range, 0.0), float(clear_to.max(initial=0.0)), resolution / 2
    )
    hit_range = np.where(hit, ranges, 0.0)
    end_x = np.floor((pose.x + cos_h * hit_range - origin[0]) / resolution)
    end_y = np.floor((pose.y + sin_h * hit_range - origin[1]) / resolution)
    ix = np.floor((pose.x + cos_h[:, None] * t[None, :] - origin[0]) / resolution)
    iy = np.floor((pose.y + sin_h[:, None] * t[None, :] - origin[1]) / resolution)
    inside = (ix >= 0) & (ix < width) & (iy >= 0) & (iy < height)
    # A beam stops at its first sample not below its clearing length, and when it leaves the
    # grid after having entered it.
    before_end = np.logical_and.accumulate(t[None, :] < clear_to[:, None], axis=1)
    entered = np.logical_or.accumulate(inside, axis=1)
    left = np.logical_or.accumulate(entered & ~inside, axis=1)
    own_hit = hit[:, None] & (ix == end_x[:, None]) & (iy == end_y[:, None])
    cleared = before_end & inside & ~left & ~own_hit
    out[iy[cleared].astype(int), ix[cleared].astype(int)] = FREE_SPACE
    marked = mark & (end_x >= 0) & (end_x < width) & (end_y >= 0) & (end_y < height)
    out[end_y[marked].astype(int), end_x[marked].astype(int)] = LETHAL_OBSTACLE
    ys, xs = np.nonzero(out != data)
    if xs.size == 0:
        return out, None
    return out, (int(xs.min()), int(ys.min()), int(xs.max()) + 1, int(ys.max()) + 1)


def random_scan(
    rng: np.random.Generator, pose: Pose2D, beams: int = 360, wall_range: float | None = None
) -> LaserScan:
    """A scan with every kind of return: misses, NaN, blind spots, near and far hits."""
    increment = float(rng.choice([2 * math.pi / beams, 1.5 * math.pi / beams]))
    ranges = rng.uniform(0.0, 3.4, beams)
    kind = rng.random(beams)
    ranges[kind < 0.25] = np.inf
    ranges[(kind >= 0.25) & (kind < 0.28)] = np.nan
    if wall_range is not None:
        ranges[kind > 0.7] = wall_range
    return LaserScan(
        stamp=0.0,
        frame_id="base_scan",
        angle_min=float(rng.uniform(-math.pi, math.pi)),
        angle_max=0.0,
        angle_increment=increment,
        range_min=0.12,
        range_max=3.5,
        ranges=ranges,
        sensor_pose=pose,
    )


@pytest.mark.parametrize("seed", range(6))
def test_obstacle_layer_matches_the_sampled_formula(seed: int) -> None:
    rng = np.random.default_rng(seed)
    params = ObstacleParams(raytrace_min_range=float(rng.choice([0.0, 0.31])))
    size_x, size_y = int(rng.integers(20, 90)), int(rng.integers(20, 90))
    origin = (float(rng.uniform(-3, 0)), float(rng.uniform(-3, 0)))
    grid = Costmap2D(size_x, size_y, 0.05, origin)
    layer = ObstacleLayer(grid, params)
    # Old marks, including values the lidar never writes.
    grid.data[:] = rng.choice(
        np.array([FREE_SPACE, LETHAL_OBSTACLE, 77, NO_INFORMATION], dtype=np.uint8),
        size=grid.data.shape,
        p=[0.8, 0.14, 0.03, 0.03],
    )
    x_max, y_max = origin[0] + size_x * 0.05, origin[1] + size_y * 0.05
    for step in range(8):
        # Mostly inside the grid, sometimes outside it, sometimes on a cell corner.
        x = float(rng.uniform(origin[0] - 1.0, x_max + 1.0))
        y = float(rng.uniform(origin[1] - 1.0, y_max + 1.0))
        if step == 0:
            x, y = origin[0] + 10 * 0.05, origin[1] + 7 * 0.05
        pose = Pose2D(x=x, y=y, yaw=float(rng.uniform(-10, 10)))
        scan = random_scan(rng, pose, beams=int(rng.choice([360, 90])), wall_range=0.85)
        expected, expected_bounds = reference_trace(grid.data, origin, 0.05, scan, params)
        bounds = layer.add_scan(scan)
        assert np.array_equal(grid.data, expected)
        assert bounds == expected_bounds
        index, old = layer.last_changes
        assert index.size == np.count_nonzero(grid.data.ravel()[index] != old)


def test_cell_thresholds_agree_with_division() -> None:
    rng = np.random.default_rng(3)
    for resolution in (0.05, 0.1, 0.03):
        thresholds = cell_thresholds(80, resolution)
        near = thresholds[:, None] + rng.integers(-3, 4, (81, 6)) * np.spacing(thresholds)[:, None]
        u = np.concatenate([near.ravel(), rng.uniform(-0.5, 80 * resolution + 0.5, 2000)])
        by_division = np.floor(u / resolution)
        by_threshold = np.searchsorted(thresholds, u, side="right") - 1
        inside = (by_division >= 0) & (by_division < 80)
        assert np.array_equal(by_division[inside], by_threshold[inside])
        assert np.all(by_threshold[~inside & (by_division < 0)] == -1)
        assert np.all(by_threshold[~inside & (by_division >= 80)] == 80)


def reference_master(layers: LayeredCostmap) -> np.ndarray:
    """The master costmap computed from scratch with scipy's exact distance transform."""
    params = layers.params
    grid = layers.obstacle_layer.grid
    res = grid.resolution
    pad = math.ceil(params.inflation_radius / res) + 2
    ix0, iy0 = layers.static_layer.lattice_index(grid.origin_x, grid.origin_y)
    shape = (grid.size_y + 2 * pad, grid.size_x + 2 * pad)
    if params.use_static_layer:
        base = layers.static_layer.window(ix0 - pad, iy0 - pad, shape[1], shape[0])
    else:
        base = np.zeros(shape, dtype=np.uint8)
    if params.use_obstacle_layer:  # Nav2's updateWithMax; a free obstacle cell adds nothing
        inner = base[pad:-pad, pad:-pad]
        obstacle = grid.data
        known = (obstacle != NO_INFORMATION) & (obstacle != FREE_SPACE)
        raised = np.where(inner == NO_INFORMATION, obstacle, np.maximum(inner, obstacle))
        inner[known] = raised[known]
    lethal = base == LETHAL_OBSTACLE
    distance = distance_transform_edt(~lethal) if lethal.any() else np.full(shape, np.inf)
    inflated = InflationLayer(params.inflation).cost_of_distance(distance * res)
    master = np.where(
        base == NO_INFORMATION,
        np.where(inflated >= INSCRIBED_INFLATED_OBSTACLE, inflated, NO_INFORMATION),
        np.maximum(base, inflated),
    )
    return master[pad:-pad, pad:-pad].astype(np.uint8)


def cluttered_world() -> World:
    return World(
        name="clutter",
        floor=Floor(size=(6.0, 5.0)),
        boxes=[
            Box(name="wall", center=(0.0, 1.6), size=(3.0, 0.1)),
            Box(name="crate", center=(1.7, -1.1), size=(0.5, 0.3), yaw=0.6),
        ],
        cylinders=[Cylinder(name="table", center=(-1.4, -0.6), radius=0.35)],
        spawns={"default": Pose2D(x=0.0, y=0.0)},
    )


@pytest.mark.parametrize("use_static", [True, False])
def test_rolling_window_matches_a_full_recompute(use_static: bool) -> None:
    rng = np.random.default_rng(11)
    world = cluttered_world()
    static = StaticLayer(world)
    params = CostmapParams(use_static_layer=use_static)
    local = LayeredCostmap.local_costmap(world, Pose2D(x=0, y=0), params, (2.0, 1.5), static)
    whole = LayeredCostmap.global_costmap(world, params, static)
    x, y = 0.0, 0.0
    for step in range(40):
        # Mostly a cell or two per update, sometimes a jump, off the floor now and then.
        jump = 2.5 if step % 9 == 8 else 0.08
        x = float(np.clip(x + rng.uniform(-jump, jump), -3.8, 3.8))
        y = float(np.clip(y + rng.uniform(-jump, jump), -3.3, 3.3))
        pose = Pose2D(x=x, y=y, yaw=float(rng.uniform(-math.pi, math.pi)))
        scans = [random_scan(rng, pose)] if step % 4 != 3 else []
        local.update(pose, scans)
        whole.update(pose, scans)
        if step % 13 == 12:
            local.clear()
        if step % 3 != 1:  # some updates pile up before a read
            assert np.array_equal(local.costmap.data, reference_master(local)), step
            assert np.array_equal(whole.costmap.data, reference_master(whole)), step


def test_a_moving_window_keeps_its_records_in_step_with_its_placement() -> None:
    # The window's and the obstacle grid's records follow the window when it moves.
    world = cluttered_world()
    local = LayeredCostmap.local_costmap(world, Pose2D(x=0, y=0), size=(2.0, 1.5))
    rng = np.random.default_rng(4)
    for step in range(6):
        pose = Pose2D(x=0.3 * step - 0.9, y=-0.2 * step, yaw=0.0)
        local.update(pose, [random_scan(rng, pose)])
        grid = local.obstacle_layer.grid
        ix0, iy0 = local.static_layer.lattice_index(grid.origin_x, grid.origin_y)
        placement = local._window()[0]
        assert (placement["raster_x0"], placement["raster_y0"]) == (ix0, iy0)
        geometry = grid.pack()[0]
        assert (geometry["origin_x"], geometry["origin_y"]) == (grid.origin_x, grid.origin_y)
        assert np.array_equal(local.costmap.data, reference_master(local)), step


def test_unknown_obstacle_cells_next_to_static_walls() -> None:
    # Nav2's updateWithMax: an unknown obstacle cell adds nothing, so a static wall under it
    # stays lethal and keeps its inflation.
    world = cluttered_world()
    static = StaticLayer(world)
    layers = LayeredCostmap.local_costmap(world, Pose2D(x=0.0, y=1.2), static=static)
    wall_cells = static.window(*static.lattice_index(-1.5, -0.3), 60, 60) == LETHAL_OBSTACLE
    obstacles = layers.obstacle_layer.grid.data
    obstacles[wall_cells] = NO_INFORMATION
    obstacles[5, 7] = LETHAL_OBSTACLE
    expected = reference_master(layers)
    assert np.array_equal(layers.costmap.data, expected)
    assert (expected[wall_cells] == LETHAL_OBSTACLE).all()


def test_obstacle_cells_over_unknown_static_cells() -> None:
    # A lethal obstacle cell on an unknown static cell is lethal (and inflates); a free one
    # leaves it unknown.
    world = cluttered_world()
    static = StaticLayer(world)
    static.raster[40:60, 40:80] = NO_INFORMATION
    layers = LayeredCostmap.local_costmap(world, Pose2D(x=0.0, y=0.0), static=static)
    grid = layers.obstacle_layer.grid
    ix0, iy0 = static.lattice_index(grid.origin_x, grid.origin_y)
    grid.data[50 - iy0, 60 - ix0] = LETHAL_OBSTACLE
    expected = reference_master(layers)
    assert np.array_equal(layers.costmap.data, expected)
    assert expected[50 - iy0, 60 - ix0] == LETHAL_OBSTACLE
    assert expected[50 - iy0, 70 - ix0] == NO_INFORMATION


def test_inflate_matches_the_distance_transform() -> None:
    rng = np.random.default_rng(5)
    layer = InflationLayer()
    for density in (0.002, 0.02, 0.2):
        lethal = rng.random((57, 83)) < density
        distance = distance_transform_edt(~lethal) if lethal.any() else np.full((57, 83), np.inf)
        expected = layer.cost_of_distance(distance * 0.05)
        assert np.array_equal(layer.inflate(lethal, 0.05), expected)
