"""Navigating on map_server maps: goals reached without contact, keepout and speed filters."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from map_files import image_cells, maze_pixels, room_pixels, write_map
from navigation_rig import distance, make_rig

from baobab.nav import msgs
from baobab.nav.costmap import LETHAL_OBSTACLE, NO_INFORMATION
from baobab.nav.costmap_filters import (
    NO_SPEED_LIMIT,
    KeepoutFilter,
    KeepoutParams,
    SpeedFilter,
    SpeedLimit,
    applied_speed,
    mask_costs,
)
from baobab.nav.errors import ComputePathToPoseError
from baobab.nav.navigator import BasicNavigator, TaskResult
from baobab.nav.navigator_robot import NavigatorSetupError
from baobab.sim.occupancy_map import load_occupancy_map
from baobab.sim.tasks import TaskStatus
from baobab.sim.world import Pose2D, load_world

RES = 0.05


KEEPOUT_ZONE = (2.2, 1.2, 3.8, 4.0)
SLOW_ZONE = (2.0, 0.0, 4.0, 4.0)


def _office(folder: Path, *, keepout: bool = False, speed: str = "") -> Path:
    """A 6 m x 4 m room on a map; a keepout zone touching the north wall; a slow band."""
    pixels = room_pixels(120, 80)
    write_map(folder, pixels, name="office")
    text = "name: office\nmap: ./office.yaml\nspawns: {default: {x: 1.0, y: 2.0}}\n"
    filters = []
    if keepout:
        mask = np.full(pixels.shape, 254, dtype=np.uint8)
        mask[image_cells(KEEPOUT_ZONE, 80)] = 0
        write_map(folder, mask, name="keepout")
        filters.append("  keepout: ./keepout.yaml")
    if speed:
        mask = np.full(pixels.shape, 255, dtype=np.uint8)
        mask[image_cells(SLOW_ZONE, 80)] = 127  # scale mode: m = round(100 (1 - 127/255)) = 50
        write_map(folder, mask, name="speed", mode="scale", occupied_thresh=1.0, free_thresh=0.0)
        filters.append(f"  speed: {speed}")
    if filters:
        text += "filters:\n" + "\n".join(filters) + "\n"
    path = folder / "world.yaml"
    path.write_text(text)
    return path


def _inside(pose: Pose2D, zone: tuple[float, float, float, float]) -> bool:
    return zone[0] <= pose.x <= zone[2] and zone[1] <= pose.y <= zone[3]


@pytest.mark.parametrize("seed", [3, 11])
def test_the_robot_crosses_a_maze_map_without_touching_a_wall(tmp_path: Path, seed: int) -> None:
    pixels = maze_pixels(seed, cells=4, cell_px=24)  # corridors 1.1 m wide
    height = pixels.shape[0]
    world = load_world(write_map(tmp_path, pixels, name="maze", origin=(-1.0, -1.0, 0.0)))

    def room(r: int, c: int) -> Pose2D:
        return Pose2D(x=-1.0 + (c * 24 + 13.5) * RES, y=-1.0 + (height - r * 24 - 13.5) * RES)

    rig = make_rig(world, room(0, 0))
    goal = room(3, 3)
    handle = rig.server.navigate_to_pose(goal)
    rig.run(handle, 300.0)
    assert handle.status is TaskStatus.SUCCEEDED, handle.outcome
    assert distance(rig.pose(), goal) < 0.25
    assert rig.contacts.touched == set()


def test_the_planner_routes_around_a_keepout_zone_the_robot_never_enters(tmp_path: Path) -> None:
    world = load_world(_office(tmp_path, keepout=True))
    rig = make_rig(world)
    costmap = rig.server.global_costmap()
    assert costmap.cost(3.0, 3.0) == LETHAL_OBSTACLE
    assert rig.server.local_costmap().cost(1.6, 2.0) != LETHAL_OBSTACLE
    goal = Pose2D(x=5.0, y=2.0)
    path = rig.server.compute_path(None, goal)
    assert not any(_inside(Pose2D(x=x, y=y), KEEPOUT_ZONE) for x, y in path.xy)
    assert path.xy[:, 1].min() < KEEPOUT_ZONE[1]  # it goes south of the zone
    handle = rig.server.navigate_to_pose(goal)
    entered = False
    while handle.status is TaskStatus.RUNNING and rig.sim.time < 120.0:
        rig.sim.step_for(0.05)
        entered = entered or _inside(rig.pose(), KEEPOUT_ZONE)
    assert handle.status is TaskStatus.SUCCEEDED, handle.outcome
    assert not entered
    assert rig.contacts.touched == set()


def test_a_goal_inside_a_keepout_zone_fails_goal_occupied(tmp_path: Path) -> None:
    world = load_world(_office(tmp_path, keepout=True))
    rig = make_rig(world)
    handle = rig.server.navigate_to_pose(Pose2D(x=3.0, y=3.0))
    rig.run(handle, 30.0)
    assert handle.status is TaskStatus.FAILED
    assert handle.outcome is not None
    assert handle.outcome.error_code == ComputePathToPoseError.GOAL_OCCUPIED == 206


def test_the_local_costmap_shows_the_keepout_zone_too(tmp_path: Path) -> None:
    world = load_world(_office(tmp_path, keepout=True))
    rig = make_rig(world, Pose2D(x=2.0, y=2.5))
    local = rig.server.local_costmap()
    assert local.cost(2.5, 2.5) == LETHAL_OBSTACLE
    assert local.cost(1.5, 2.5) < LETHAL_OBSTACLE
    # The zone is inflated like a wall: just outside it, a robot centre would collide.
    assert local.cost(2.15, 2.5) == 253
    assert 0 < local.cost(1.9, 2.5) < 253


def test_keepout_cells_overwrite_unknown_and_lower_costs_only() -> None:
    values = np.array([[-1, 0, 50, 100]], dtype=np.int8)
    assert mask_costs(values).tolist() == [[255, 0, 127, 254]]


def test_keepout_mask_is_written_after_the_layers_and_overridden_while_the_robot_is_in_it(
    tmp_path: Path,
) -> None:
    mask_pixels = np.array([[205, 0, 254, 0]], dtype=np.uint8)
    mask = load_occupancy_map(write_map(tmp_path, mask_pixels, name="mask"))
    keepout = KeepoutFilter(mask, (0.0, 0.0), RES, (1, 6), KeepoutParams())
    master = np.array([[0, 0, 255, 255, 100, 0]], dtype=np.uint8)
    keepout.apply(master, 0, 0, overriding=False)
    # unknown mask cell: untouched; lethal over free; free over unknown; beyond the mask: kept
    assert master.tolist() == [[0, 254, 0, 254, 100, 0]]
    assert keepout.overrides_at(1, 0) and not keepout.overrides_at(2, 0)
    assert not keepout.overrides_at(9, 0)
    master = np.array([[0, 0, 0, 0, 0, 0]], dtype=np.uint8)
    keepout.apply(master, 0, 0, overriding=True)
    assert master.tolist() == [[0, 200, 0, 200, 0, 0]]


def test_speed_filter_follows_nav2s_speed_filter_semantics(tmp_path: Path) -> None:
    pixels = np.array([[0, 1, 50, 100, 255]], dtype=np.uint8)
    mask = load_occupancy_map(
        write_map(tmp_path, pixels, name="raw", mode="raw", negate=1, origin=(0.0, 0.0, 0.0))
    )
    percent = SpeedFilter(mask, 1, 100.0, -1.0)
    x = [(i + 0.5) * RES for i in range(5)]
    assert percent.limit_at(x[0], 0.01) == SpeedLimit(True, NO_SPEED_LIMIT)  # mask 0
    assert percent.limit_at(x[1], 0.01) == SpeedLimit(True, 99.0)
    assert percent.limit_at(x[2], 0.01) == SpeedLimit(True, 50.0)
    assert percent.limit_at(x[3], 0.01) == SpeedLimit(True, 0.0)  # 0 is also "no limit"
    assert percent.limit_at(x[4], 0.01) is None  # unknown: nothing published
    assert percent.limit_at(-1.0, 0.01) is None  # off the mask
    over = SpeedFilter(mask, 1, 150.0, -1.0)
    assert over.limit_at(x[2], 0.01) == SpeedLimit(True, 100.0)
    assert over.limit_at(x[1], 0.01) == SpeedLimit(True, NO_SPEED_LIMIT)  # 149 % is out of range
    absolute = SpeedFilter(mask, 2, -0.2, 0.01)
    assert absolute.limit_at(x[3], 0.01) == SpeedLimit(False, pytest.approx(0.8))
    assert absolute.limit_at(x[1], 0.01) == SpeedLimit(False, NO_SPEED_LIMIT)  # negative
    assert percent.update(x[2], 0.01) == SpeedLimit(True, 50.0)
    assert percent.update(x[2], 0.01) is None  # unchanged: not published again
    assert applied_speed(SpeedLimit(True, 50.0), 0.22) == pytest.approx(0.11)
    assert applied_speed(SpeedLimit(False, 0.08), 0.22) == pytest.approx(0.08)
    assert applied_speed(SpeedLimit(True, NO_SPEED_LIMIT), 0.22) == 0.22


@pytest.mark.parametrize(
    ("speed", "limit"),
    [
        ("./speed.yaml", 0.11),
        ("{mask: ./speed.yaml, type: 2, base: 0.0, multiplier: 0.0016}", 0.08),
    ],
)
def test_the_robot_slows_down_in_the_speed_zone(tmp_path: Path, speed: str, limit: float) -> None:
    world = load_world(_office(tmp_path, speed=speed))
    rig = make_rig(world, Pose2D(x=0.6, y=2.0))
    handle = rig.server.navigate_to_pose(Pose2D(x=5.4, y=2.0))
    before: list[float] = []
    inside: list[float] = []
    while handle.status is TaskStatus.RUNNING and rig.sim.time < 120.0:
        rig.sim.step_for(0.05)
        pose, speed_now = rig.pose(), abs(rig.robot.base.body_velocity()[0])
        if pose.x < SLOW_ZONE[0]:
            before.append(speed_now)
        elif SLOW_ZONE[0] + 0.3 < pose.x < SLOW_ZONE[2]:
            inside.append(speed_now)
    assert handle.status is TaskStatus.SUCCEEDED, handle.outcome
    assert max(before) > 0.2
    assert inside and max(inside) < limit + 0.01
    assert max(inside) > limit - 0.02


def test_basic_navigator_runs_on_a_map_yaml_and_changes_map(tmp_path: Path) -> None:
    pixels = room_pixels(80, 60)
    first = write_map(tmp_path, pixels, name="first", origin=(-1.0, -1.0, 0.0))
    second = write_map(tmp_path, pixels, name="second", origin=(-2.0, -1.0, 0.0))
    navigator = BasicNavigator(world=str(first))  # no spawn: starts at the map origin
    try:
        assert distance(navigator.robot_pose(), Pose2D(x=0.0, y=0.0)) < 0.01
        costmap = navigator.getGlobalCostmap()
        assert (costmap.metadata.size_x, costmap.metadata.size_y) == (80, 60)
        navigator.goToPose(msgs.pose_stamped(1.5, 1.0))
        while not navigator.isTaskComplete():
            pass
        assert navigator.getResult() is TaskResult.SUCCEEDED
        here = navigator.robot_pose()
        assert navigator.changeMap(str(second))
        assert distance(navigator.robot_pose(), here) < 0.01  # free there too: kept
        assert navigator.getGlobalCostmap().metadata.origin.position.x == -2.0
        navigator.clearAllCostmaps()
        assert not navigator.changeMap(str(tmp_path / "missing.yaml"))
        assert navigator.getTaskError()[0] == 1  # RESULT_MAP_DOES_NOT_EXIST
    finally:
        navigator.destroy_node()


def test_a_map_whose_origin_is_walled_needs_a_start(tmp_path: Path) -> None:
    path = write_map(tmp_path, room_pixels(40, 40), origin=(0.0, 0.0, 0.0))
    with pytest.raises(NavigatorSetupError, match="has no spawn and the map origin"):
        BasicNavigator(world=str(path))
    with pytest.raises(NavigatorSetupError, match="not free"):
        BasicNavigator(world=str(path), start=Pose2D(x=0.06, y=1.0))
    navigator = BasicNavigator(world=str(path), start=Pose2D(x=1.0, y=1.0))
    try:
        assert math.isclose(navigator.robot_pose().x, 1.0, abs_tol=0.01)
        assert navigator.server.global_costmap().cost(0.02, 1.0) == LETHAL_OBSTACLE
        assert navigator.server.global_costmap().cost(1.0, 1.0) != NO_INFORMATION
    finally:
        navigator.destroy_node()
