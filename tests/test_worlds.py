"""The bundled worlds: they build and compile, and every seed coordinate fits them.

The coordinates are copied from the tutorials in shared/seeds: seed 000 (test_nav_to_pose.py,
the cafe tables), seed 001 (waypoint_follower.py in the cafe, nav_through_poses.py on the farm,
nav_to_pose.py in the town). A TurtleBot3 (footprint radius 0.105 m) with 0.15 m to spare needs
0.255 m from every obstacle surface; Nav2's 0.55 m inflation wants more, so goals keep 0.45 m
and the routes to them are at least 1.0 m wide.
"""

from __future__ import annotations

import math
from functools import cache

import mujoco
import numpy as np
import pytest

from baobab.sim import geometry
from baobab.sim.builder import STATIC_GROUP, geom_ids_in_group, world_spec
from baobab.sim.world import Box, Cylinder, Floor, Pose2D, World, bundled_world_names, load_world

FOOTPRINT_RADIUS = 0.105
"""TurtleBot3 Burger footprint radius (m)."""
ROBOT_CLEARANCE = FOOTPRINT_RADIUS + 0.15
"""Required distance (m) from every seed point to every obstacle surface."""
GOAL_CLEARANCE = 0.45
"""Distance (m) the seed goals keep so Nav2's inflated costmap does not crowd them."""
PASSAGE_WIDTH = 1.0
"""Narrowest passage (m) on some route from the spawn to every seed point."""
GRID_RESOLUTION = 0.05


def _yaw(qz: float, qw: float) -> float:
    """Yaw (rad, in [-pi, pi)) of the planar quaternion (0, 0, qz, qw) written in a seed."""
    yaw = 2.0 * math.atan2(qz, qw)
    return (yaw + math.pi) % (2.0 * math.pi) - math.pi


# Seed 000, test_nav_to_pose.py: self.locations, sent with orientation (0, 0, 0, 1).
CAFE_TABLES = [(-0.96, -0.92), (1.16, -4.23), (0.792, -8.27), (-3.12, -7.495), (-2.45, -3.55)]
# Seed 001, waypoint_follower.py: (x, y, qz, qw).
CAFE_WAYPOINTS = [
    (1.3, 6.0, 0.23, 0.97),
    (2.0, -3.5, 0.707, -0.707),
    (1.5, -7.7, 0.92, -0.38),
    (-1.4, -7.8, 0.92, 0.38),
    (-2.6, -4.5, 0.38, 0.92),
    (0.0, 0.0, 0.0, 1.0),
]
# Seed 001, nav_through_poses.py: the 41 goal poses (x, y, qz, qw), in order.
FARM_POSES = [
    (-5.0, -4.2, 0.0, 1.0),
    (0.0, -4.2, 0.0, 1.0),
    (5.0, -4.2, 0.0, 1.0),
    (10.0, -4.2, 0.0, 1.0),
    (13.0, -4.2, 0.0, 1.0),
    (13.5, -3.7, 0.38, 0.92),
    (13.5, -3.2, 0.707, 0.707),
    (13.5, -2.7, 0.92, 0.38),
    (13.0, -2.2, 1.0, 0.0),
    (10.0, -2.2, 1.0, 0.0),
    (5.0, -2.2, 1.0, 0.0),
    (0.0, -2.2, 1.0, 0.0),
    (-5.0, -2.2, 1.0, 0.0),
    (-6.5, -2.2, 1.0, 0.0),
    (-7.0, -1.7, 0.92, 0.38),
    (-7.0, -1.2, 0.707, 0.707),
    (-7.0, -0.7, 0.38, 0.92),
    (-6.5, 0.0, 0.0, 1.0),
    (-5.0, 0.0, 0.0, 1.0),
    (0.0, 0.0, 0.0, 1.0),
    (5.0, 0.0, 0.0, 1.0),
    (10.0, 0.0, 0.0, 1.0),
    (13.0, 0.0, 0.0, 1.0),
    (13.5, 0.5, 0.38, 0.92),
    (13.5, 1.0, 0.707, 0.707),
    (13.5, 1.5, 0.92, 0.38),
    (13.0, 2.2, 1.0, 0.0),
    (10.0, 2.2, 1.0, 0.0),
    (5.0, 2.2, 1.0, 0.0),
    (0.0, 2.2, 1.0, 0.0),
    (-5.0, 2.2, 1.0, 0.0),
    (-6.5, 2.2, 1.0, 0.0),
    (-7.0, 2.7, 0.92, 0.38),
    (-7.0, 3.2, 0.707, 0.707),
    (-7.0, 3.7, 0.38, 0.92),
    (-6.5, 4.2, 0.0, 1.0),
    (-5.0, 4.2, 0.0, 1.0),
    (0.0, 4.2, 0.0, 1.0),
    (5.0, 4.2, 0.0, 1.0),
    (10.0, 4.2, 0.0, 1.0),
    (13.0, 4.2, 0.0, 1.0),
]
# Seed 001, nav_through_poses.py: the commented initial pose and the preemption goal.
FARM_START = (-6.5, -4.2)
# Seed 001, nav_to_pose.py: the goal, and the goal after preemption (x set to -3.0).
TOWN_GOALS = [(10.0, -2.0), (-3.0, -2.0)]

SEED_POINTS: dict[str, list[tuple[float, float]]] = {
    "cafe": [(0.0, 0.0), *CAFE_TABLES, *((x, y) for x, y, _, _ in CAFE_WAYPOINTS)],
    "farm": [FARM_START, *((x, y) for x, y, _, _ in FARM_POSES)],
    "town": [(0.0, 0.0), *TOWN_GOALS],
}
SEED_WORLDS = sorted(SEED_POINTS)


@cache
def _world(name: str) -> World:
    return load_world(name)


@cache
def _grid(name: str) -> geometry.ClearanceGrid:
    return geometry.clearance_grid(_world(name), GRID_RESOLUTION)


def _probe_model(world: World, radius: float) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The world's model plus a mocap cylinder of ``radius`` (m), 2 m tall, on the floor."""
    spec = world_spec(world)
    probe = spec.worldbody.add_body(name="probe", mocap=True, pos=[0.0, 0.0, 1.0])
    probe.add_geom(
        name="probe",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[radius, 1.0, 0.0],
        contype=0,
        conaffinity=0,
        group=5,
    )
    model = spec.compile()
    return model, mujoco.MjData(model)


def _mujoco_distances(
    world: World,
    model: mujoco.MjModel,
    data: mujoco.MjData,
    points: np.ndarray,
    distmax: float = 5.0,
) -> np.ndarray:
    """mj_geomDistance from the probe at each point to each obstacle: shape (points, obstacles).

    Columns follow ``geometry.obstacle_names(world)``; distances beyond ``distmax`` read
    ``distmax``.
    """
    probe = model.geom("probe").id
    static = [model.geom(name).id for name in geometry.obstacle_names(world)]
    mocap = model.body("probe").mocapid[0]
    fromto = np.zeros(6)
    rows = []
    for x, y in points:
        data.mocap_pos[mocap] = [x, y, 1.0]
        mujoco.mj_kinematics(model, data)
        rows.append(
            [mujoco.mj_geomDistance(model, data, probe, g, distmax, fromto) for g in static]
        )
    return np.array(rows)


@pytest.mark.parametrize("name", bundled_world_names())
def test_bundled_world_loads_builds_and_compiles(name: str) -> None:
    world = _world(name)
    assert world.name == name
    model = world_spec(world).compile()
    static = {model.geom(int(g)).name for g in geom_ids_in_group(model, STATIC_GROUP)}
    assert static == set(geometry.obstacle_names(world))
    for label, spawn in world.spawns.items():
        nearest, distance = geometry.nearest_obstacle(world, spawn.x, spawn.y)
        assert distance >= ROBOT_CLEARANCE, f"spawn {label}: {distance:.3f} m from {nearest}"


def test_the_seed_worlds_are_bundled() -> None:
    assert set(SEED_WORLDS) <= set(bundled_world_names())


@pytest.mark.parametrize("name", SEED_WORLDS)
def test_seed_points_have_robot_clearance(name: str) -> None:
    world = _world(name)
    for x, y in SEED_POINTS[name]:
        nearest, distance = geometry.nearest_obstacle(world, x, y)
        assert distance >= ROBOT_CLEARANCE, f"{name} ({x}, {y}): {distance:.3f} m from {nearest}"


@pytest.mark.parametrize("name", SEED_WORLDS)
def test_seed_goals_leave_room_for_inflation(name: str) -> None:
    world = _world(name)
    clearances = geometry.clearance(world, SEED_POINTS[name])
    worst = int(np.argmin(clearances))
    assert clearances[worst] >= GOAL_CLEARANCE, (name, SEED_POINTS[name][worst], clearances[worst])


@pytest.mark.parametrize(
    ("name", "radius"),
    [(name, radius) for name in SEED_WORLDS for radius in (ROBOT_CLEARANCE, PASSAGE_WIDTH / 2)],
)
def test_seed_points_are_reachable_from_the_spawn(name: str, radius: float) -> None:
    """Flood fill over cells whose centre keeps ``radius`` from everything.

    With the robot's clearance this proves a collision-free route; with half the passage width
    it proves the route never squeezes through a gap narrower than ``PASSAGE_WIDTH``.
    """
    world, grid = _world(name), _grid(name)
    free = grid.free(radius)
    region = geometry.reachable(free, grid.cell(world.spawn.x, world.spawn.y))
    assert region.any(), f"{name}: the spawn itself is blocked at {radius} m"
    stranded = [(x, y) for x, y in SEED_POINTS[name] if not region[grid.cell(x, y)]]
    assert not stranded, f"{name}: not reachable keeping {radius} m clear: {stranded}"


@pytest.mark.parametrize("name", SEED_WORLDS)
def test_mujoco_sees_no_contact_around_seed_points(name: str) -> None:
    """A 2 m tall cylinder of the robot's clearance radius at each point touches nothing."""
    world = _world(name)
    model, data = _probe_model(world, ROBOT_CLEARANCE)
    points = np.array(SEED_POINTS[name])
    distances = _mujoco_distances(world, model, data, points)
    touching = [
        (float(x), float(y))
        for (x, y), row in zip(points, distances, strict=True)
        if row.min() <= 0
    ]
    assert not touching, f"{name}: the probe touches an obstacle at {touching}"
    exact = geometry.obstacle_distances(world, points).T - ROBOT_CLEARANCE
    np.testing.assert_allclose(np.minimum(distances, 5.0), np.minimum(exact, 5.0), atol=1e-4)


@pytest.mark.parametrize("name", SEED_WORLDS)
def test_exact_geometry_agrees_with_mujoco_everywhere(name: str) -> None:
    """Random probes over the floor: MuJoCo's distance and the planar one match to 0.1 mm.

    Where the probe overlaps an obstacle both must say so; the depths differ there, since
    MuJoCo's penetration depth is 3D and may point up, over a low obstacle.
    """
    world = _world(name)
    radius = 0.2
    model, data = _probe_model(world, radius)
    x_min, y_min, x_max, y_max = world.bounds
    points = np.random.default_rng(7).uniform((x_min, y_min), (x_max, y_max), size=(150, 2))
    distances = np.minimum(_mujoco_distances(world, model, data, points, distmax=2.0), 2.0)
    exact = np.minimum(geometry.obstacle_distances(world, points).T - radius, 2.0)
    apart = exact > 0
    np.testing.assert_allclose(distances[apart], exact[apart], atol=1e-4)
    np.testing.assert_array_less(distances[~apart], 1e-6)
    assert (~apart).any(), "some probes should overlap an obstacle"


def test_cafe_locations_are_the_seed_poses() -> None:
    world = _world("cafe")
    assert world.spawn == Pose2D(x=0.0, y=0.0, yaw=0.0)
    for number, (x, y) in enumerate(CAFE_TABLES, start=1):
        pose = world.locations[f"table_{number}"]
        assert (pose.x, pose.y, pose.yaw) == (x, y, 0.0)
    for number, (x, y, qz, qw) in enumerate(CAFE_WAYPOINTS, start=1):
        pose = world.locations[f"wp_{number}"]
        assert (pose.x, pose.y) == (x, y)
        assert pose.yaw == pytest.approx(_yaw(qz, qw), abs=1e-4)
    kitchen = world.locations["kitchen"]
    assert kitchen.y > max(y for _, y in CAFE_TABLES) + 5.0, "the kitchen is beyond the tables"


def test_each_cafe_table_stands_beside_its_serving_point() -> None:
    """The table of each goal is the nearest obstacle, 0.5-0.8 m from the goal."""
    world = _world("cafe")
    for number, (x, y) in enumerate(CAFE_TABLES, start=1):
        nearest, distance = geometry.nearest_obstacle(world, x, y)
        assert nearest == f"table_{number}"
        assert 0.5 <= distance <= 0.8


def test_farm_lanes_and_headlands_match_the_seed() -> None:
    world = _world("farm")
    assert (world.spawn.x, world.spawn.y, world.spawn.yaw) == (*FARM_START, 0.0)
    assert len(FARM_POSES) == 41
    lanes = sorted({y for x, y, _, _ in FARM_POSES if -6.5 <= x <= 13.0})
    assert lanes == [-4.2, -2.2, 0.0, 2.2, 4.2]
    for number, y in enumerate(lanes, start=1):
        assert (
            world.locations[f"lane_{number}_west"].y,
            world.locations[f"lane_{number}_east"].y,
        ) == (y, y)
    rows = [box for box in world.boxes if box.name.startswith("crop_row")]
    assert len(rows) == 6
    # Every lane pose has crops on both sides: a row south and a row north of it.
    for x, y, _, _ in FARM_POSES:
        if -5.0 <= x <= 10.0:
            assert any(row.center[1] < y for row in rows) and any(row.center[1] > y for row in rows)


def test_town_goals_are_named_locations() -> None:
    world = _world("town")
    assert world.spawn == Pose2D(x=0.0, y=0.0, yaw=0.0)
    assert (world.locations["goal"].x, world.locations["goal"].y) == TOWN_GOALS[0]
    assert (world.locations["preempt_goal"].x, world.locations["preempt_goal"].y) == TOWN_GOALS[1]


@pytest.mark.parametrize("name", SEED_WORLDS)
def test_every_named_location_is_reachable_with_clearance(name: str) -> None:
    world, grid = _world(name), _grid(name)
    region = geometry.reachable(grid.free(ROBOT_CLEARANCE), grid.cell(world.spawn.x, world.spawn.y))
    for label, pose in world.locations.items():
        nearest, distance = geometry.nearest_obstacle(world, pose.x, pose.y)
        assert distance >= GOAL_CLEARANCE, f"{name}.{label}: {distance:.3f} m from {nearest}"
        assert region[grid.cell(pose.x, pose.y)], f"{name}.{label} cannot be reached"


# The geometry the checks above rely on, on worlds small enough to reason about by hand.


def _two_rooms(door_width: float) -> World:
    """A 6 x 3 m floor split by a wall at x = 0, with a door ``door_width`` (m) wide at y = 0."""
    half = (3.0 - door_width) / 2
    return World(
        name="two_rooms",
        floor=Floor(size=(6.0, 3.0)),
        boxes=[
            Box(name="wall_low", center=(0.0, -1.5 + half / 2), size=(0.2, half)),
            Box(name="wall_high", center=(0.0, 1.5 - half / 2), size=(0.2, half)),
        ],
        spawns={"default": Pose2D(x=-2.0, y=0.0)},
    )


@pytest.mark.parametrize(("door_width", "passes"), [(0.45, False), (0.6, True)])
def test_flood_fill_needs_a_door_wide_enough(door_width: float, passes: bool) -> None:
    world = _two_rooms(door_width)
    grid = geometry.clearance_grid(world, GRID_RESOLUTION)
    region = geometry.reachable(grid.free(ROBOT_CLEARANCE), grid.cell(-2.0, 0.0))
    assert bool(region[grid.cell(2.0, 0.0)]) is passes
    assert region[grid.cell(-2.0, 1.0)]


def test_box_and_cylinder_distances_by_hand() -> None:
    box = Box(name="b", center=(1.0, 2.0), size=(2.0, 1.0), yaw=math.pi / 2)
    # Rotated a quarter turn, the box spans x 0.5..1.5 and y 1.0..3.0.
    points = [(1.0, 2.0), (2.5, 2.0), (1.0, 4.0), (2.5, 4.0), (1.0, 2.9)]
    expected = [-0.5, 1.0, 1.0, math.hypot(1.0, 1.0), -0.1]
    np.testing.assert_allclose(geometry.box_distance(points, box), expected, atol=1e-12)
    cylinder = Cylinder(name="c", center=(-1.0, 0.0), radius=0.5)
    np.testing.assert_allclose(
        geometry.cylinder_distance([(-1.0, 0.0), (2.0, 4.0)], cylinder), [-0.5, 4.5], atol=1e-12
    )


def test_clearance_counts_the_floor_edge() -> None:
    world = _two_rooms(1.0)
    assert geometry.clearance(world, (-2.0, 1.3))[0] == pytest.approx(0.2)
    assert geometry.nearest_obstacle(world, -2.0, 1.3) == (geometry.FLOOR_EDGE, pytest.approx(0.2))
    assert geometry.clearance(world, (-3.5, 0.0))[0] == pytest.approx(-0.5)


def test_reachable_from_a_blocked_start_is_empty() -> None:
    free = np.ones((4, 4), dtype=bool)
    free[1, 1] = False
    assert not geometry.reachable(free, (1, 1)).any()
    assert not geometry.reachable(free, (9, 0)).any()
    assert geometry.reachable(free, (0, 0)).sum() == 15
