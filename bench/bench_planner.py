"""Benchmark: global planning time per query, and the cost of costmap updates.

Usage: ``python bench/bench_planner.py [--queries 200] [--seed 0] [--worlds cafe farm]``

For each world: build the global costmap (static raster + full inflation), then plan between
seeded random start/goal pairs drawn from the free space the spawn can reach, timing the A*
search alone and the whole plan (search + Simple Smoother + orientations). Then the costmap
updates: one obstacle-layer update from a random 360-beam scan, the incremental inflation
that follows it, the same scan again (no cell changes, no inflation), a full inflation, and
one local (3 m x 3 m rolling) costmap cycle. Wall-clock
medians and 95th percentiles in milliseconds.
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable

import numpy as np
from scipy import ndimage

from baobab.nav.costmap import MAX_NON_OBSTACLE
from baobab.nav.layered_costmap import LayeredCostmap
from baobab.nav.layers import StaticLayer
from baobab.nav.planner import GlobalPlanner
from baobab.sim.lidar import LaserScan
from baobab.sim.world import Pose2D, World, load_world


def timed(call: Callable[[], object], repeats: int) -> np.ndarray:
    """Wall-clock milliseconds of ``repeats`` calls."""
    times = np.empty(repeats)
    for i in range(repeats):
        start = time.perf_counter()
        call()
        times[i] = (time.perf_counter() - start) * 1e3
    return times


def summary(times: np.ndarray) -> str:
    return f"median {np.median(times):7.3f} ms   p95 {np.percentile(times, 95):7.3f} ms"


def reachable_free_cells(costmap_layers: LayeredCostmap, world: World) -> np.ndarray:
    """``(ix, iy)`` of the free cells in the spawn's connected free space."""
    grid = costmap_layers.costmap
    labels, _ = ndimage.label(grid.data <= MAX_NON_OBSTACLE, structure=np.ones((3, 3)))
    ix, iy = grid.world_to_map(world.spawn.x, world.spawn.y) or (0, 0)
    rows, cols = np.nonzero(labels == labels[iy, ix])
    return np.column_stack([cols, rows])


def random_scan(rng: np.random.Generator, pose: Pose2D) -> LaserScan:
    """A 360-beam LDS-01-like scan: ranges 0.12-3.5 m, a fifth of the beams without a hit."""
    ranges = rng.uniform(0.12, 3.5, 360)
    ranges[rng.random(360) < 0.2] = np.inf
    increment = 2 * math.pi / 360
    return LaserScan(0.0, "base_scan", 0.0, 359 * increment, increment, 0.12, 3.5, ranges, pose)


def bench_world(name: str, queries: int, seed: int) -> None:
    world = load_world(name)
    rng = np.random.default_rng(seed)
    print(f"\n== {name}: floor {world.floor.size[0]} x {world.floor.size[1]} m")
    start = time.perf_counter()
    static = StaticLayer(world)
    raster_ms = (time.perf_counter() - start) * 1e3
    layers = LayeredCostmap.global_costmap(world, static=static)
    start = time.perf_counter()
    grid = layers.costmap
    inflate_ms = (time.perf_counter() - start) * 1e3
    print(
        f"grid {grid.size_x} x {grid.size_y} = {grid.size_x * grid.size_y} cells; "
        f"static raster {raster_ms:.1f} ms, first full inflation {inflate_ms:.1f} ms"
    )
    cells = reachable_free_cells(layers, world)
    planner = GlobalPlanner()
    xs, ys = grid.map_to_world_array(cells[:, 0], cells[:, 1])
    pairs: list[tuple[Pose2D, Pose2D]] = []
    diagonal = math.hypot(*world.floor.size)
    while len(pairs) < queries:
        a, b = rng.integers(len(cells), size=2)
        if math.dist((xs[a], ys[a]), (xs[b], ys[b])) >= diagonal / 3:  # across the room
            pairs.append(
                (
                    Pose2D(x=float(xs[a]), y=float(ys[a])),
                    Pose2D(x=float(xs[b]), y=float(ys[b]), yaw=float(rng.uniform(-3, 3))),
                )
            )
    start = time.perf_counter()
    planner.create_plan(*pairs[0], grid)
    print(f"first plan (loads the compiled kernels) {(time.perf_counter() - start) * 1e3:.0f} ms")
    search_ms, plan_ms, expansions, lengths = [], [], [], []
    for s, g in pairs:
        t0 = time.perf_counter()
        raw = planner.search(s, g, grid)
        t1 = time.perf_counter()
        path = planner.create_plan(s, g, grid)
        t2 = time.perf_counter()
        search_ms.append((t1 - t0) * 1e3)
        plan_ms.append((t2 - t1) * 1e3)
        expansions.append(raw.expansions)
        lengths.append(path.length())
    print(
        f"{queries} queries >= {diagonal / 3:.1f} m apart, path length median "
        f"{np.median(lengths):.1f} m, expansions median {np.median(expansions):.0f}"
    )
    print(f"  A* search           {summary(np.array(search_ms))}")
    print(f"  plan (A* + smooth)  {summary(np.array(plan_ms))}")

    robot = world.spawn
    scans = [random_scan(rng, robot) for _ in range(50)]
    it = iter(scans * 2)
    obstacle_ms = timed(lambda: layers.obstacle_layer.add_scan(next(it)), 50)
    print(f"  obstacle layer, 360-beam scan      {summary(obstacle_ms)}")

    def scan_and_inflate() -> None:
        layers.add_scan(next(it))
        _ = layers.costmap

    it = iter(scans * 2)
    print(f"  scan + incremental inflation       {summary(timed(scan_and_inflate, 50))}")

    def same_scan_again() -> None:
        layers.add_scan(scans[0])
        _ = layers.costmap

    same_scan_again()
    print(f"  same scan again (nothing changes)  {summary(timed(same_scan_again, 50))}")

    def full_inflation() -> None:
        layers.clear()
        _ = layers.costmap

    print(f"  full inflation (clear)             {summary(timed(full_inflation, 10))}")
    local = LayeredCostmap.local_costmap(world, robot, static=static)
    poses = [Pose2D(x=robot.x + 0.02 * i, y=robot.y, yaw=0.0) for i in range(50)]
    cycle = iter(zip(poses, scans, strict=True))

    def local_cycle() -> None:
        pose, scan = next(cycle)
        local.update(pose, [scan])
        _ = local.costmap

    print(f"  local 3x3 m cycle (move+scan+infl) {summary(timed(local_cycle, 50))}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--queries", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--worlds", nargs="+", default=["cafe", "farm"])
    args = parser.parse_args()
    for name in args.worlds:
        bench_world(name, args.queries, args.seed)


if __name__ == "__main__":
    main()
