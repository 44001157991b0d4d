"""The planner's compiled helpers against the plain numpy / Python code they replaced."""

from __future__ import annotations

import math

import numpy as np
import pytest

from baobab.nav.costmap import MAX_NON_OBSTACLE, NO_INFORMATION, Costmap2D
from baobab.nav.errors import NavigationError
from baobab.nav.path import Path
from baobab.nav.planner import GlobalPlanner, PlannerParams
from baobab.nav.smoother import COLLISION, CONVERGED, MAX_ITERATIONS, SimpleSmoother, _smooth_round
from baobab.sim.world import Pose2D


def reference_goal_candidates(
    planner: GlobalPlanner, grid: np.ndarray, costmap: Costmap2D, goal: Pose2D
) -> np.ndarray:
    """The numpy version the kernel replaced."""
    res = costmap.resolution
    gx, gy = costmap.world_to_map(goal.x, goal.y) or (0, 0)
    reach = math.ceil(planner.params.tolerance / res) + 1
    x0, x1 = max(gx - reach, 0), min(gx + reach + 1, costmap.size_x)
    y0, y1 = max(gy - reach, 0), min(gy + reach + 1, costmap.size_y)
    iy, ix = np.mgrid[y0:y1, x0:x1]
    cx, cy = costmap.map_to_world_array(ix, iy)
    distance = np.hypot(cx - goal.x, cy - goal.y)
    distance[(ix == gx) & (iy == gy)] = -1.0
    usable = (distance <= planner.params.tolerance) & (planner.weights[grid[y0:y1, x0:x1]] > 0)
    order = np.lexsort((iy[usable], ix[usable], distance[usable]))
    return np.column_stack([ix[usable][order], iy[usable][order]])


def test_goal_candidates_match_the_numpy_version() -> None:
    rng = np.random.default_rng(5)
    for case in range(200):
        costmap = Costmap2D(
            int(rng.integers(5, 40)),
            int(rng.integers(5, 40)),
            float(rng.choice([0.05, 0.1, 0.037])),
            (float(rng.normal()), float(rng.normal())),
        )
        values = rng.choice([0, 10, 200, 253, 254, 255], size=costmap.data.shape)
        costmap.data[:] = values.astype(np.uint8)
        x_min, y_min, x_max, y_max = costmap.bounds
        goal = Pose2D(x=float(rng.uniform(x_min, x_max)), y=float(rng.uniform(y_min, y_max)))
        if case % 3 == 0:
            # On a cell centre: equally distant cells, ordered by ix, then iy.
            cell = costmap.world_to_map(goal.x, goal.y) or (0, 0)
            x, y = costmap.map_to_world(*cell)
            goal = Pose2D(x=x, y=y)
        tolerance = float(rng.choice([0.0, 0.2, 0.5, 1.3]))
        planner = GlobalPlanner(PlannerParams(tolerance=tolerance, allow_unknown=case % 2 == 0))
        expected = reference_goal_candidates(planner, costmap.data, costmap, goal)
        got = planner._goal_candidates(costmap.data, costmap, goal)
        assert got.shape == expected.shape
        assert np.array_equal(got, expected)


def reference_smooth_round(
    data: np.ndarray,
    grid: np.ndarray,
    origin: tuple[float, float],
    resolution: float,
    smoother: SimpleSmoother,
) -> tuple[int, np.ndarray]:
    """The smoothing round as first written (whole-array copies, neighbours from memory)."""
    new, last = data.copy(), data.copy()
    n = data.shape[0]
    height, width = grid.shape
    change, its = smoother.tolerance, 0
    while change >= smoother.tolerance:
        its += 1
        change = 0.0
        if its >= smoother.max_its:
            return MAX_ITERATIONS, last
        for i in range(1, n - 1):
            for j in range(2):
                before = new[i, j]
                moved = before + smoother.w_data * (data[i, j] - before)
                moved += smoother.w_smooth * (new[i + 1, j] + new[i - 1, j] - 2.0 * before)
                new[i, j] = moved
                change += abs(moved - before)
            col = int(np.floor((new[i, 0] - origin[0]) / resolution))
            row = int(np.floor((new[i, 1] - origin[1]) / resolution))
            if 0 <= row < height and 0 <= col < width:
                cost = grid[row, col]
                if cost > MAX_NON_OBSTACLE and cost != NO_INFORMATION:
                    return COLLISION, last
        last[:, :] = new
    return CONVERGED, new


def test_smoothing_rounds_match_the_first_version_bit_for_bit() -> None:
    rng = np.random.default_rng(8)
    statuses = set()
    for case in range(60):
        n = int(rng.integers(3, 30))
        points = np.cumsum(rng.normal(0.0, 0.05, (n, 2)), axis=0)
        costmap = Costmap2D(30, 30, 0.05, (-0.75, -0.75))
        costmap.data[:] = np.where(rng.random((30, 30)) < 0.03, 254, 0).astype(np.uint8)
        smoother = SimpleSmoother(max_its=[1000, 40][case % 2])
        expected = reference_smooth_round(
            points, costmap.data, costmap.origin, costmap.resolution, smoother
        )
        got = _smooth_round(points, costmap.data, costmap.pack(), smoother.pack())
        assert got[0] == expected[0]
        assert np.array_equal(got[1], expected[1])
        statuses.add(expected[0])
    assert statuses == {CONVERGED, COLLISION, MAX_ITERATIONS}


def test_a_planned_path_is_the_smoothed_raw_path() -> None:
    costmap = Costmap2D(60, 60, 0.05, (-1.5, -1.5))
    costmap.data[20:40, 28:32] = 254
    planner = GlobalPlanner()
    start, goal = Pose2D(x=-1.0, y=0.0), Pose2D(x=1.0, y=0.1, yaw=0.5)
    raw = planner.search(start, goal, costmap)
    smoothed = SimpleSmoother().smooth(Path.from_points(raw.points, goal.yaw), costmap).path
    path = planner.create_plan(start, goal, costmap)
    assert np.array_equal(path.poses, smoothed.poses)


def test_an_open_goal_cell_is_always_the_first_candidate() -> None:
    rng = np.random.default_rng(12)
    checked = 0
    for case in range(200):
        costmap = Costmap2D(int(rng.integers(5, 40)), int(rng.integers(5, 40)), 0.05, (0.0, 0.0))
        costmap.data[:] = rng.choice([0, 10, 200, 253, 254, 255], size=costmap.data.shape)
        x_min, y_min, x_max, y_max = costmap.bounds
        goal = Pose2D(x=float(rng.uniform(x_min, x_max)), y=float(rng.uniform(y_min, y_max)))
        tolerance = float(rng.choice([0.0, 0.2, 0.5, 1.3]))
        planner = GlobalPlanner(PlannerParams(tolerance=tolerance, allow_unknown=case % 2 == 0))
        gx, gy = costmap.world_to_map(goal.x, goal.y) or (0, 0)
        if planner.weights[costmap.data[gy, gx]] == 0:
            continue
        checked += 1
        candidates = planner._goal_candidates(costmap.data, costmap, goal)
        assert tuple(candidates[0]) == (gx, gy)
    assert checked > 50


def old_path_of(planner: GlobalPlanner, start: Pose2D, goal: Pose2D, costmap: Costmap2D) -> Path:
    """The planned path as it was put together before: a Path of the raw points, smoothed as
    a Path, then oriented again."""
    raw = planner.search(start, goal, costmap)
    path = Path.from_points(raw.points, goal.yaw)
    path = planner.smoother.smooth(path, costmap).path
    if planner.params.use_final_approach_orientation and len(path) > 1:
        path = Path(np.column_stack([path.xy, np.r_[path.yaws[:-1], path.yaws[-2]]]))
    return path


@pytest.mark.parametrize("final_approach", [False, True])
def test_planned_paths_are_the_paths_put_together_as_before(final_approach: bool) -> None:
    rng = np.random.default_rng(13)
    params = PlannerParams(use_final_approach_orientation=final_approach)
    planner = GlobalPlanner(params)
    for _ in range(40):
        costmap = Costmap2D(60, 50, 0.05, (-1.5, -1.25))
        costmap.data[:] = np.where(rng.random((50, 60)) < 0.04, 254, 0).astype(np.uint8)
        free = np.argwhere(costmap.data == 0)
        (sr, sc), (gr, gc) = free[rng.integers(len(free), size=2)]
        sx, sy = costmap.map_to_world(sc + rng.uniform(-0.4, 0.4), sr + rng.uniform(-0.4, 0.4))
        gx, gy = costmap.map_to_world(gc, gr)
        start, goal = Pose2D(x=sx, y=sy), Pose2D(x=gx, y=gy, yaw=float(rng.uniform(-3, 3)))
        try:
            path = planner.create_plan(start, goal, costmap)
        except NavigationError:
            continue
        expected = old_path_of(planner, start, goal, costmap)
        assert np.array_equal(path.poses, expected.poses)
        assert not path.poses.flags.writeable


def test_a_replaced_smoother_is_the_one_used() -> None:
    costmap = Costmap2D(60, 60, 0.05, (-1.5, -1.5))
    costmap.data[20:40, 28:32] = 254
    start, goal = Pose2D(x=-1.0, y=0.0), Pose2D(x=1.0, y=0.1, yaw=0.5)
    planner = GlobalPlanner()
    first = planner.create_plan(start, goal, costmap)
    planner.smoother = SimpleSmoother(w_smooth=0.1, do_refinement=False)
    second = planner.create_plan(start, goal, costmap)
    expected = GlobalPlanner(smoother=SimpleSmoother(w_smooth=0.1, do_refinement=False))
    assert not np.array_equal(first.poses, second.poses)
    assert np.array_equal(second.poses, expected.create_plan(start, goal, costmap).poses)


def test_paths_from_points_are_read_only_copies_and_refuse_non_finite_points() -> None:
    points = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 2.0)])
    path = Path.from_points(points, 0.25)
    step = np.diff(points, axis=0)
    expected = np.column_stack([points, np.r_[np.arctan2(step[:, 1], step[:, 0]), 0.25]])
    assert np.array_equal(path.poses, Path(expected).poses)
    points[1, 0] = 5.0
    assert path.poses[1, 0] == 1.0
    with pytest.raises(ValueError):
        path.poses[0, 0] = 1.0
    with pytest.raises(ValueError, match="finite"):
        Path.from_points(np.array([(0.0, 0.0), (np.nan, 1.0)]), 0.0)
    with pytest.raises(ValueError, match="finite"):
        Path.from_points(np.array([(0.0, 0.0), (1.0, 1.0)]), math.inf)
