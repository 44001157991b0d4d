"""Nav2 map_server maps as worlds: pixels -> occupancy, the physics walls, the static costmap."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest
from map_files import UNKNOWN_PIXEL, maze_pixels, room_pixels, write_map
from scipy import ndimage

from baobab.nav.costmap import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from baobab.nav.layered_costmap import CostmapParams, LayeredCostmap
from baobab.nav.layers import InflationLayer, StaticLayer
from baobab.nav.static_map import StaticLayerParams, map_costs
from baobab.robots.footprint import Footprint
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.builder import STATIC_GROUP, world_spec
from baobab.sim.geometry import nearest_obstacle
from baobab.sim.map_geometry import solid_rectangles
from baobab.sim.point_clearance import MAP_WALLS
from baobab.sim.world import Pose2D, World, load_world

FORMATS = ("P2", "P5", "PNG", "BMP")


def _grey_strip() -> np.ndarray:
    """Two rows: the top row's pixels, then a free bottom row (to see the flip)."""
    top = [0, 89, 90, 205, 206, 254, 255, 128]
    return np.array([top, [254] * len(top)], dtype=np.uint8)


@pytest.mark.parametrize("fmt", FORMATS)
def test_trinary_values_follow_map_servers_thresholds_in_every_format(
    tmp_path: Path, fmt: str
) -> None:
    world = load_world(write_map(tmp_path, _grey_strip(), fmt=fmt))
    assert world.grid is not None
    # Row 0 of the grid is the image's bottom row; p = 1 - g/255 against 0.65 / 0.196.
    assert world.grid.data[0].tolist() == [0] * 8
    assert world.grid.data[1].tolist() == [100, 100, -1, -1, 0, 0, 0, -1]


def test_negate_swaps_white_and_black(tmp_path: Path) -> None:
    world = load_world(write_map(tmp_path, _grey_strip(), negate=1))
    assert world.grid is not None
    # p = g/255: 0 -> free, 89 .. 128 between, 205 and brighter at least 0.65
    assert world.grid.data[1].tolist() == [0, -1, -1, 100, 100, 100, 100, -1]
    assert world.grid.data[0].tolist() == [100] * 8


def test_scale_mode_interpolates_between_the_thresholds(tmp_path: Path) -> None:
    pixels = np.array([[0, 51, 204, 255, 128]], dtype=np.uint8)
    path = write_map(tmp_path, pixels, mode="scale", occupied_thresh=1.0, free_thresh=0.0)
    grid = load_world(path).grid
    assert grid is not None
    # p = 1 - g/255: 1 -> 100, 0.8 -> 80, 0.2 -> 20, 0 -> 0, 0.498 -> 50
    assert grid.data[0].tolist() == [100, 80, 20, 0, 50]


def test_raw_mode_keeps_values_up_to_100(tmp_path: Path) -> None:
    pixels = np.array([[0, 50, 100, 101, 255]], dtype=np.uint8)
    grid = load_world(write_map(tmp_path, pixels, mode="raw", negate=1)).grid
    assert grid is not None
    assert grid.data[0].tolist() == [0, 50, 100, -1, -1]


@pytest.mark.parametrize("mode", ["trinary", "scale"])
def test_translucent_pixels_are_unknown(tmp_path: Path, mode: str) -> None:
    rgba = np.zeros((1, 3, 4), dtype=np.uint8)
    rgba[0, :, :3] = [[0, 0, 0], [254, 254, 254], [254, 254, 254]]
    rgba[0, :, 3] = [255, 255, 128]
    grid = load_world(write_map(tmp_path, rgba, fmt="PNG", mode=mode)).grid
    assert grid is not None
    assert grid.data[0].tolist() == [100, 0, -1]


def test_colour_pixels_are_averaged_to_grey(tmp_path: Path) -> None:
    # Yellow: mean 170 -> p 0.333, between the thresholds (unknown); by luminance (226) it
    # would be free.
    rgb = np.array([[[255, 255, 0], [0, 0, 0], [254, 254, 254]]], dtype=np.uint8)
    grid = load_world(write_map(tmp_path, rgb, fmt="BMP")).grid
    assert grid is not None
    assert grid.data[0].tolist() == [-1, 100, 0]


def test_a_map_world_takes_its_floor_from_the_map_and_has_no_spawn(tmp_path: Path) -> None:
    path = write_map(tmp_path, room_pixels(40, 20), origin=(-1.0, 2.0, 0.0))
    world = load_world(path)
    assert world.name == "map"
    assert world.bounds == pytest.approx((-1.0, 2.0, 1.0, 3.0))
    assert world.spawns == {}


def test_solid_cells_merge_into_rectangles_that_cover_them_exactly() -> None:
    rng = np.random.default_rng(4)
    for _ in range(5):
        solid = rng.random((37, 53)) < 0.4
        covered = np.zeros(solid.shape, dtype=int)
        for x0, y0, x1, y1 in solid_rectangles(solid):
            covered[y0:y1, x0:x1] += 1
        assert np.array_equal(covered, solid.astype(int))
    room = room_pixels(200, 100) == 0
    assert len(solid_rectangles(room)) == 4


def test_the_model_has_one_box_per_rectangle_at_the_cells_and_the_lidar_sees_them(
    tmp_path: Path,
) -> None:
    pixels = room_pixels(60, 40)
    pixels[10:30, 30] = 0  # a wall at x 1.50..1.55 m, y 0.50..1.50 m
    world = load_world(write_map(tmp_path, pixels))
    model = world_spec(world).compile()
    boxes = [g for g in range(model.ngeom) if model.geom_group[g] == STATIC_GROUP]
    assert len(boxes) == 5
    sizes = sorted(tuple(np.round(model.geom_size[g], 4)) for g in boxes)
    assert (0.025, 0.5, 0.5) in sizes  # the inner wall: 1 x 20 cells, 1 m tall
    sim, robot = build_turtlebot3_sim(world, Pose2D(x=1.0, y=1.0))
    scan = robot.lidar.scan()
    # Beam 0 looks along +x from the lidar (0.032 m behind the base centre) to x = 1.50.
    assert scan.ranges[0] == pytest.approx(0.532, abs=1e-6)
    assert sim.model.ngeom > len(boxes)


def test_unknown_cells_are_solid_unless_the_world_says_free(tmp_path: Path) -> None:
    pixels = np.full((10, 10), 254, dtype=np.uint8)
    pixels[4:6, 4:6] = 205
    write_map(tmp_path, pixels)
    solid = load_world(tmp_path / "map.yaml").map_solid()
    assert solid is not None and solid.sum() == 4
    (tmp_path / "open.yaml").write_text("name: open\nmap: {file: map.yaml, unknown: free}\n")
    assert load_world(tmp_path / "open.yaml").map_solid().sum() == 0  # type: ignore[union-attr]


def test_start_poses_are_checked_against_the_map_walls(tmp_path: Path) -> None:
    world = load_world(write_map(tmp_path, room_pixels(60, 40)))
    name, distance = nearest_obstacle(world, 0.5, 1.0)
    assert name == MAP_WALLS
    assert distance == pytest.approx(0.4)  # the west wall's inner face is at x = 0.10
    assert nearest_obstacle(world, 0.05, 1.0)[1] < 0


def test_a_polygon_footprint_is_checked_against_the_map_walls(tmp_path: Path) -> None:
    world = load_world(write_map(tmp_path, room_pixels(60, 40)))  # west wall's face at x = 0.1
    long = Footprint.rectangle(-0.3, 0.3, -0.05, 0.05)
    name, clearance = long.clearance_in(world, Pose2D(x=0.35, y=1.0))  # back edge at x = 0.05
    assert name == MAP_WALLS and clearance < 0
    name, clearance = long.clearance_in(world, Pose2D(x=0.35, y=1.0, yaw=np.pi / 2))
    assert name == MAP_WALLS and clearance == pytest.approx(0.2)  # its circle would not fit


def test_the_static_costmap_is_the_map_as_nav2s_static_layer_reads_it() -> None:
    values = np.array([[-1, 0, 50, 98, 99, 100]], dtype=np.int8)
    assert map_costs(values).tolist() == [[0, 0, 0, 0, 253, 254]]
    tracked = StaticLayerParams(track_unknown_space=True)
    assert map_costs(values, tracked).tolist() == [[255, 0, 0, 0, 253, 254]]
    lower = StaticLayerParams(lethal_cost_threshold=50)
    assert map_costs(values, lower).tolist() == [[0, 0, 254, 254, 253, 254]]
    scaled = StaticLayerParams(trinary_costmap=False)
    assert map_costs(values, scaled).tolist() == [[0, 0, 127, 248, 253, 254]]
    own_unknown = StaticLayerParams(unknown_cost_value=0, track_unknown_space=True)
    # -1 is then 255, above the lethal threshold
    assert map_costs(values, own_unknown).tolist() == [[254, 255, 0, 0, 253, 254]]


@pytest.mark.parametrize("track_unknown", [False, True])
def test_global_costmap_is_cell_exact_over_a_maze(tmp_path: Path, track_unknown: bool) -> None:
    pixels = maze_pixels(7, cells=4)
    pixels[30:33, 30:33] = 205  # an unknown patch
    world = load_world(write_map(tmp_path, pixels, origin=(-2.0, -1.0, 0.0)))
    grid = world.grid
    assert grid is not None
    params = CostmapParams(static=StaticLayerParams(track_unknown_space=track_unknown))
    costmap = LayeredCostmap.global_costmap(world, params).costmap
    assert (costmap.size_x, costmap.size_y) == (grid.width, grid.height)
    assert costmap.origin == (-2.0, -1.0)
    # Reference: exact distances to the lethal cells (beyond the map counts as lethal).
    lethal = np.pad(grid.data == 100, 1, constant_values=True)
    distance = ndimage.distance_transform_edt(~lethal)[1:-1, 1:-1] * grid.resolution
    inflation = InflationLayer(params.inflation).cost_of_distance(distance)
    static = map_costs(grid.data, params.static)
    expected = np.maximum(static, inflation)
    unknown = static == NO_INFORMATION
    expected[unknown] = np.where(inflation[unknown] >= 253, inflation[unknown], NO_INFORMATION)
    assert np.array_equal(costmap.data, expected)
    assert (costmap.data == LETHAL_OBSTACLE).sum() == (grid.data == 100).sum()
    assert ((costmap.data == NO_INFORMATION).sum() > 0) == track_unknown


def test_lidar_hits_on_unknown_map_cells_are_lethal_as_in_nav2(tmp_path: Path) -> None:
    pixels = room_pixels(80, 60)
    pixels[:, 50:] = UNKNOWN_PIXEL  # the east part unexplored: solid, and unknown to the costmap
    world = load_world(write_map(tmp_path, pixels))
    _sim, robot = build_turtlebot3_sim(world, Pose2D(x=1.5, y=1.5))
    params = CostmapParams(static=StaticLayerParams(track_unknown_space=True))
    layers = LayeredCostmap.global_costmap(world, params)
    before = layers.costmap.data.copy()
    layers.update(robot.base.pose(), [robot.lidar.scan()])
    after = layers.costmap.data
    edge = after[5:55, 50]  # the unknown cells the beams hit: the first unknown column
    assert (before[5:55, 50] == NO_INFORMATION).all()
    assert (edge == LETHAL_OBSTACLE).sum() >= 40
    assert (after[5:55, 53:75] == NO_INFORMATION).all()  # behind the hits: still unknown
    # A cleared beam does not free unknown cells (baobab's obstacle layer does not track them).
    assert (after[before == NO_INFORMATION] >= INSCRIBED_INFLATED_OBSTACLE).all()


def test_boxes_and_cylinders_of_a_world_file_stand_on_the_map(tmp_path: Path) -> None:
    write_map(tmp_path, room_pixels(60, 40))
    (tmp_path / "world.yaml").write_text(
        "name: furnished\nmap: ./map.yaml\n"
        "boxes: [{name: crate, center: [1.5, 1.0], size: [0.2, 0.2]}]\n"
        "cylinders: [{name: bin, center: [0.5, 1.0], radius: 0.1}]\n"
        "spawns: {default: {x: 2.5, y: 1.0}}\n"
        "locations: {door: {x: 1.0, y: 0.5}}\n"
    )
    world = load_world(tmp_path / "world.yaml")
    assert world.spawn == Pose2D(x=2.5, y=1.0)
    static = StaticLayer(world)
    crate = static.raster[18:22, 28:32]
    assert (crate == LETHAL_OBSTACLE).all()
    assert static.raster[20, 10] == LETHAL_OBSTACLE  # the bin's centre
    assert static.raster[20, 40] == 0
    model = world_spec(world).compile()
    assert model.geom("crate").type == mujoco.mjtGeom.mjGEOM_BOX


def test_a_world_built_in_python_loads_its_map_relative_to_the_working_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    write_map(tmp_path, room_pixels(20, 20))
    monkeypatch.chdir(tmp_path)
    world = World(name="here", map="map.yaml")  # type: ignore[arg-type]
    assert world.grid is not None and world.grid.width == 20
