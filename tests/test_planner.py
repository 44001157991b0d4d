"""Global planner: exact A* against brute-force Dijkstra, error codes, tolerance, smoothing."""

from __future__ import annotations

import heapq
import itertools
import math

import numpy as np
import pytest

from baobab.nav.costmap import MAX_NON_OBSTACLE, Costmap2D
from baobab.nav.errors import ComputePathToPoseError, NavigationError
from baobab.nav.grid_search import EXHAUSTED, FOUND, GridSearch
from baobab.nav.layered_costmap import LayeredCostmap
from baobab.nav.path import Path
from baobab.nav.planner import GlobalPlanner, PlannerParams, step_weights
from baobab.nav.smoother import SimpleSmoother
from baobab.sim.world import Box, Cylinder, Floor, Pose2D, World

CARDINAL, DIAGONAL = 408, 577  # the search's integer step lengths (577 / 408 ~ sqrt 2)


def cell_weight(cost: int) -> int | None:
    """Smac 2D's traversal weight scaled by 252; None for cells a circular robot cannot enter."""
    if cost in (253, 254):
        return None
    return 252 + 2 * cost


def brute_force_dijkstra(grid: np.ndarray, start: tuple[int, int]) -> dict[tuple[int, int], int]:
    """Cheapest cost from ``start`` to every reachable ``(row, col)``, the slow obvious way."""
    rows, cols = grid.shape
    best = {start: 0}
    queue = [(0, start)]
    while queue:
        cost, (r, c) = heapq.heappop(queue)
        if cost > best[(r, c)]:
            continue
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                nr, nc = r + dr, c + dc
                if (dr, dc) == (0, 0) or not (0 <= nr < rows and 0 <= nc < cols):
                    continue
                weight = cell_weight(int(grid[nr, nc]))
                if weight is None:
                    continue
                if (
                    dr
                    and dc
                    and (
                        cell_weight(int(grid[r, nc])) is None
                        or cell_weight(int(grid[nr, c])) is None
                    )
                ):
                    continue  # no squeezing between two blocked corners
                candidate = cost + weight * (DIAGONAL if dr and dc else CARDINAL)
                if candidate < best.get((nr, nc), math.inf):
                    best[(nr, nc)] = candidate
                    heapq.heappush(queue, (candidate, (nr, nc)))
    return best


def path_cost(grid: np.ndarray, cells: np.ndarray) -> int:
    total = 0
    for (r0, c0), (r1, c1) in itertools.pairwise(cells):
        dr, dc = abs(int(r1) - int(r0)), abs(int(c1) - int(c0))
        assert max(dr, dc) == 1, "path cells must be neighbours"
        weight = cell_weight(int(grid[r1, c1]))
        assert weight is not None, "path enters a blocked cell"
        if dr and dc:
            assert cell_weight(int(grid[r0, c1])) is not None
            assert cell_weight(int(grid[r1, c0])) is not None
        total += weight * (DIAGONAL if dr and dc else CARDINAL)
    return total


def random_grid(rng: np.random.Generator, shape: tuple[int, int]) -> np.ndarray:
    kind = rng.random(shape)
    grid = np.where(kind < 0.45, 0, rng.integers(1, 253, shape))
    grid = np.where((kind > 0.78) & (kind < 0.86), 253, grid)
    grid = np.where((kind >= 0.86) & (kind < 0.95), 254, grid)
    grid = np.where(kind >= 0.95, 255, grid)
    return grid.astype(np.uint8)


def test_astar_is_optimal_on_random_grids() -> None:
    rng = np.random.default_rng(2024)
    search = GridSearch()
    weights = step_weights(2.0, allow_unknown=True)
    reachable_cases = 0
    for _ in range(60):
        grid = random_grid(rng, (int(rng.integers(6, 16)), int(rng.integers(6, 16))))
        open_cells = np.argwhere(np.isin(grid, [253, 254], invert=True))
        (sr, sc), (gr, gc) = open_cells[rng.integers(len(open_cells), size=2)]
        start, goal = (int(sr), int(sc)), (int(gr), int(gc))
        truth = brute_force_dijkstra(grid, start)
        result = search.search(grid, weights, start, goal, 10**6)
        if goal in truth:
            reachable_cases += 1
            assert result.status == FOUND
            assert search.cost_to(goal) == truth[goal]
            cells = search.path_to(goal)
            assert tuple(cells[0]) == start and tuple(cells[-1]) == goal
            assert path_cost(grid, cells) == truth[goal]
        else:
            assert result.status == EXHAUSTED
            # The exhausted search closed exactly the reachable cells, each at its optimal cost.
            reached = {tuple(int(v) for v in cell) for cell in np.argwhere(search.reached())}
            assert reached == set(truth)
            assert all(search.cost_to(cell) == cost for cell, cost in truth.items())
    assert reachable_cases >= 30


def test_planner_search_is_optimal_on_a_costmap() -> None:
    rng = np.random.default_rng(5)
    planner = GlobalPlanner(PlannerParams(tolerance=0.0))
    for _ in range(15):
        costmap = Costmap2D(20, 14, 0.05, origin=(-0.5, -0.35))
        costmap.data[:] = random_grid(rng, (14, 20))
        costmap.data[costmap.data == 255] = 0
        free = np.argwhere(costmap.data == 0)
        (sr, sc), (gr, gc) = free[rng.integers(len(free))], free[rng.integers(len(free))]
        sx, sy = costmap.map_to_world(sc, sr)
        gx, gy = costmap.map_to_world(gc, gr)
        truth = brute_force_dijkstra(costmap.data, (int(sr), int(sc)))
        try:
            raw = planner.search(Pose2D(x=sx, y=sy), Pose2D(x=gx, y=gy), costmap)
        except NavigationError as error:
            assert (int(gr), int(gc)) not in truth
            assert error.code == ComputePathToPoseError.NO_VALID_PATH
            continue
        assert raw.cost == truth[(int(gr), int(gc))]
        assert raw.points[0] == pytest.approx((sx, sy))
        assert raw.points[-1] == pytest.approx((gx, gy))


def make_world(boxes: tuple[Box, ...] = (), cylinders: tuple[Cylinder, ...] = ()) -> World:
    return World(
        name="test",
        floor=Floor(size=(6.0, 4.0)),
        boxes=list(boxes),
        cylinders=list(cylinders),
        spawns={"default": Pose2D(x=-2.0, y=0.0)},
    )


def plan_error(planner: GlobalPlanner, costmap: Costmap2D, start: Pose2D, goal: Pose2D) -> int:
    with pytest.raises(NavigationError) as caught:
        planner.create_plan(start, goal, costmap)
    return int(caught.value.code)


def test_error_codes_for_start_and_goal() -> None:
    block = Box(name="block", center=(1.0, 0.0), size=(1.6, 1.6))
    costmap = LayeredCostmap.global_costmap(make_world(boxes=(block,))).costmap
    planner = GlobalPlanner()
    free, inside = Pose2D(x=-2.0, y=0.0), Pose2D(x=1.0, y=0.0)
    assert plan_error(planner, costmap, Pose2D(x=9.0, y=0.0), free) == 203
    assert plan_error(planner, costmap, free, Pose2D(x=0.0, y=-7.0)) == 204
    assert plan_error(planner, costmap, inside, free) == 205
    assert plan_error(planner, costmap, free, inside) == 206  # 0.8 m deep: nothing within 0.5 m
    assert ComputePathToPoseError.START_OCCUPIED.name == "START_OCCUPIED"
    timed_out = GlobalPlanner(PlannerParams(max_iterations=20))
    assert plan_error(timed_out, costmap, free, Pose2D(x=2.5, y=1.5)) == 207


def test_sealed_wall_gives_no_valid_path() -> None:
    wall = Box(name="wall", center=(0.0, 0.0), size=(0.2, 4.2))
    costmap = LayeredCostmap.global_costmap(make_world(boxes=(wall,))).costmap
    code = plan_error(GlobalPlanner(), costmap, Pose2D(x=-2.0, y=0.0), Pose2D(x=2.0, y=0.5))
    assert code == ComputePathToPoseError.NO_VALID_PATH


def test_blocked_goal_is_replaced_by_the_nearest_free_cell_within_tolerance() -> None:
    block = Box(name="block", center=(1.0, 0.0), size=(1.0, 1.0))  # faces at x = 0.5, 1.5
    costmap = LayeredCostmap.global_costmap(make_world(boxes=(block,))).costmap
    start, goal = Pose2D(x=-2.0, y=0.0), Pose2D(x=0.7, y=0.0, yaw=1.0)
    raw = GlobalPlanner().search(start, goal, costmap)
    assert raw.goal_substituted
    end = raw.points[-1]
    # Brute force: the nearest cell a robot centre may occupy.
    rows, cols = np.nonzero(costmap.data <= MAX_NON_OBSTACLE)
    xs, ys = costmap.map_to_world_array(cols, rows)
    nearest = np.hypot(xs - goal.x, ys - goal.y).min()
    assert math.dist(end, (goal.x, goal.y)) == pytest.approx(nearest)
    assert nearest <= 0.5
    path = GlobalPlanner().create_plan(start, goal, costmap)
    assert path.poses[-1] == pytest.approx([*end, 1.0])
    strict = GlobalPlanner(PlannerParams(tolerance=0.2))
    assert plan_error(strict, costmap, start, goal) == ComputePathToPoseError.GOAL_OCCUPIED


def test_unreachable_goal_uses_tolerance_or_reports_no_valid_path() -> None:
    # A closed pen, 0.5 m inside: its centre is free but unreachable.
    pen = (
        Box(name="n", center=(1.0, 0.3), size=(0.7, 0.1)),
        Box(name="s", center=(1.0, -0.3), size=(0.7, 0.1)),
        Box(name="e", center=(1.3, 0.0), size=(0.1, 0.7)),
        Box(name="w", center=(0.7, 0.0), size=(0.1, 0.7)),
    )
    costmap = LayeredCostmap.global_costmap(make_world(boxes=pen)).costmap
    start, goal = Pose2D(x=-2.0, y=0.0), Pose2D(x=1.0, y=0.0)
    assert costmap.cost(goal.x, goal.y) <= MAX_NON_OBSTACLE
    raw = GlobalPlanner().search(start, goal, costmap)
    assert raw.goal_substituted
    assert math.dist(raw.points[-1], (1.0, 0.0)) <= 0.5
    strict = GlobalPlanner(PlannerParams(tolerance=0.3))
    assert plan_error(strict, costmap, start, goal) == ComputePathToPoseError.NO_VALID_PATH


def test_start_inside_the_inscribed_band_may_leave_it() -> None:
    wall = Box(name="wall", center=(0.0, 0.0), size=(0.2, 2.0))
    costmap = LayeredCostmap.global_costmap(make_world(boxes=(wall,))).costmap
    start = Pose2D(x=-0.17, y=0.0)  # 0.07 m from the face
    assert costmap.cost(start.x, start.y) == 253
    path = GlobalPlanner().create_plan(start, Pose2D(x=-2.0, y=1.0), costmap)
    assert path.xy[0] == pytest.approx((start.x, start.y))
    assert costmap.costs(path.xy[3:, 0], path.xy[3:, 1]).max() <= MAX_NON_OBSTACLE


def test_smoothed_path_is_free_no_longer_and_faces_along_the_path() -> None:
    world = make_world(
        boxes=(Box(name="shelf", center=(-0.5, 0.6), size=(0.4, 2.8), yaw=0.2),),
        cylinders=(
            Cylinder(name="t1", center=(0.8, -0.7), radius=0.35),
            Cylinder(name="t2", center=(1.6, 0.9), radius=0.3),
        ),
    )
    costmap = LayeredCostmap.global_costmap(world).costmap
    start, goal = Pose2D(x=-2.3, y=1.2), Pose2D(x=2.4, y=0.0, yaw=-2.0)
    planner = GlobalPlanner()
    raw = planner.search(start, goal, costmap)
    raw_path = Path.from_points(raw.points, goal.yaw)
    path = planner.create_plan(start, goal, costmap)
    assert len(path) == len(raw_path)
    assert not np.allclose(path.xy, raw_path.xy)  # smoothing did something
    assert costmap.costs(path.xy[:, 0], path.xy[:, 1]).max() <= MAX_NON_OBSTACLE
    assert path.length() <= raw_path.length()
    assert path.xy[0] == pytest.approx((start.x, start.y))
    assert path.poses[-1] == pytest.approx([goal.x, goal.y, goal.yaw])
    step = np.diff(path.xy, axis=0)
    assert path.yaws[:-1] == pytest.approx(np.arctan2(step[:, 1], step[:, 0]))


def test_smoother_stops_before_a_collision() -> None:
    corner = np.array(
        [(x, 0.0) for x in np.arange(0.0, 1.0, 0.05)]
        + [(1.0, y) for y in np.arange(0.0, 1.01, 0.05)]
    )
    path = Path.from_points(corner, 0.0)
    free_result = SimpleSmoother().smooth(path)
    assert free_result.was_completed
    costmap = Costmap2D(40, 40, 0.05, origin=(-0.5, -0.5))
    # Block a cell the unconstrained smoothing passes through but the original path avoids.
    ix, iy, _ = costmap.world_to_map_array(free_result.path.xy[:, 0], free_result.path.xy[:, 1])
    ox, oy, _ = costmap.world_to_map_array(corner[:, 0], corner[:, 1])
    original = set(zip(ox.tolist(), oy.tolist(), strict=True))
    cut = next(c for c in zip(ix.tolist(), iy.tolist(), strict=True) if c not in original)
    costmap.data[cut[1], cut[0]] = 254
    result = SimpleSmoother().smooth(path, costmap)
    assert not result.was_completed
    assert costmap.costs(result.path.xy[:, 0], result.path.xy[:, 1]).max() <= MAX_NON_OBSTACLE
