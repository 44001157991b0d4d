"""Polygon footprints as Nav2 has them, on the TurtleBot3 Waffle (0.281 x 0.306 m, base_link
near its front): a goal the Burger fits with 0.10 m to spare but the Waffle cannot stand on is
refused or fails, and a spin in a corridor narrower than the Waffle's sweep fails with
COLLISION_AHEAD, each without contact; the footprint's geometry, kernel and teleop checks."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from navigation_rig import make_rig

from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.nav.costmap import LETHAL_OBSTACLE, Costmap2D
from baobab.nav.footprint import collision_mask, outline_lethal_distances
from baobab.nav.footprint_kernel import footprint_cost
from baobab.robots.catalog import ROBOTS
from baobab.robots.footprint import Footprint
from baobab.sim.tasks import TaskStatus
from baobab.sim.world import Box, Cylinder, Floor, Pose2D, World

WAFFLE = ROBOTS["turtlebot3_waffle"].mobile_facts.footprint
BURGER = ROBOTS["turtlebot3"].mobile_facts.footprint
POST_RADIUS = 0.05
CLEARANCE = 0.10
"""What the Burger keeps at the goal (m)."""
GOAL = Pose2D(x=1.0, y=0.0, yaw=0.0)


def _between_posts() -> World:
    """Two posts behind the goal (facing +x), at the Waffle's rear corners: 0.206 m apart, so
    narrower than the Waffle, and 0.10 m from the Burger's footprint at the goal."""
    centre = BURGER.radius + CLEARANCE + POST_RADIUS  # from the goal, in both posts' direction
    corner = math.atan2(0.153, -0.2045)  # where the Waffle's rear left corner points
    posts = [
        Cylinder(
            name=f"post_{side}",
            center=(
                GOAL.x + centre * math.cos(sign * corner),
                GOAL.y + centre * math.sin(sign * corner),
            ),
            radius=POST_RADIUS,
            height=0.6,
        )
        for side, sign in (("left", 1.0), ("right", -1.0))
    ]
    return World(
        name="posts",
        floor=Floor(size=(5.0, 3.0)),
        cylinders=posts,
        spawns={"default": Pose2D(x=2.2, y=0.0, yaw=math.pi)},
        locations={"between_posts": GOAL},
    )


def test_the_goal_leaves_the_burger_its_clearance_and_the_waffle_none() -> None:
    world = _between_posts()
    name, burger = BURGER.clearance_in(world, GOAL)
    assert burger == pytest.approx(CLEARANCE)
    name, waffle = WAFFLE.clearance_in(world, GOAL)
    assert name.startswith("post_") and waffle < -0.03
    posts = [c.center for c in world.cylinders]
    assert math.dist(*posts) - 2 * POST_RADIUS < 0.306  # narrower than the Waffle


def _mission(folder: Path, robot: str) -> Path:
    import yaml

    world = _between_posts()
    (folder / "posts.yaml").write_text(yaml.safe_dump(world.model_dump(mode="json")))
    path = folder / "mission.yaml"
    path.write_text(
        "mission: posts\nworld: ./posts.yaml\n"
        f"robot: {robot}\n"
        "tree:\n  navigate_to_pose: {goal: between_posts}\n"
        "expect: {result: SUCCEEDED, no_contact: true}\n",
        encoding="utf-8",
    )
    return path


def test_validate_refuses_the_goal_for_the_waffle_and_takes_it_for_the_burger(
    tmp_path: Path,
) -> None:
    assert load_mission(_mission(tmp_path, "turtlebot3")).robot.name == "turtlebot3"
    with pytest.raises(MissionError) as caught:
        load_mission(_mission(tmp_path, "turtlebot3_waffle"))
    message = str(caught.value)
    assert ":5:" in message  # the goal's line
    assert "too narrow for robot 'turtlebot3_waffle'" in message and "'post_" in message


@pytest.mark.parametrize("robot", ["turtlebot3", "turtlebot3_waffle"])
def test_the_navigator_reaches_the_goal_with_the_burger_and_refuses_it_for_the_waffle(
    robot: str,
) -> None:
    rig = make_rig(_between_posts(), robot_name=robot)
    handle = rig.server.navigate_to_pose(GOAL)
    rig.run(handle, limit=120.0)
    assert not rig.contacts.touched
    if robot == "turtlebot3":
        assert handle.status is TaskStatus.SUCCEEDED
        assert math.dist((rig.pose().x, rig.pose().y), (GOAL.x, GOAL.y)) < 0.26  # Nav2: 0.25
        return
    outcome = handle.outcome
    assert outcome is not None and outcome.status is TaskStatus.FAILED
    assert outcome.error_name in ("GOAL_OCCUPIED", "NO_VALID_PATH"), outcome
    assert math.dist((rig.pose().x, rig.pose().y), (GOAL.x, GOAL.y)) > 0.5  # never went there


def _corridor(width: float) -> World:
    """A straight corridor ``width`` m wide (wall faces at y = +-width/2), 4 m long."""
    half = width / 2
    return World(
        name="corridor",
        floor=Floor(size=(5.0, 3.0)),
        boxes=[
            Box(name="wall_left", center=(0.0, half + 0.05), size=(4.0, 0.1)),
            Box(name="wall_right", center=(0.0, -half - 0.05), size=(4.0, 0.1)),
        ],
        spawns={"default": Pose2D(x=0.0, y=0.0)},
    )


@pytest.mark.parametrize("robot", ["turtlebot3", "turtlebot3_waffle"])
def test_spin_in_a_corridor_narrower_than_the_waffles_sweep(robot: str) -> None:
    width = 0.44  # the Waffle fits lengthwise (0.306 wide), not turning (0.51 across)
    assert 2 * WAFFLE.circumscribed_radius > width > 2 * 0.153
    rig = make_rig(_corridor(width), robot_name=robot)
    rig.sim.step_for(0.5)  # a scan or two in the costmaps
    before = rig.pose()
    handle = rig.server.spin(math.pi / 2, time_allowance=20.0)
    rig.run(handle, limit=30.0)
    assert not rig.contacts.touched
    outcome = handle.outcome
    assert outcome is not None
    if robot == "turtlebot3":
        assert outcome.status is TaskStatus.SUCCEEDED
        return
    assert outcome.status is TaskStatus.FAILED and outcome.error_name == "COLLISION_AHEAD"
    assert abs(math.remainder(rig.pose().yaw - before.yaw, math.tau)) < 0.3


def _wall_costmap() -> Costmap2D:
    """A 2 m x 2 m costmap with a lethal wall along x = 0.5 m (cells from x = 0.5 on)."""
    costmap = Costmap2D(40, 40, 0.05, origin=(-1.0, -1.0), footprint=WAFFLE)
    costmap.data[:, 30:] = LETHAL_OBSTACLE
    return costmap


def test_the_outline_cost_is_the_highest_cell_it_crosses_at_the_pose_yaw() -> None:
    costmap = _wall_costmap()
    grid = costmap.pack()[0]
    # Facing the wall the front edge (0.0765 m ahead) is clear; backed onto it, the rear
    # (0.2045 m behind) is on it.
    facing, _ = footprint_cost(costmap.data, grid, costmap.outline, 0.35, 0.0, 0.0)
    backed, _ = footprint_cost(costmap.data, grid, costmap.outline, 0.35, 0.0, math.pi)
    assert facing < LETHAL_OBSTACLE <= backed
    off_grid, unknown = footprint_cost(costmap.data, grid, costmap.outline, -0.95, 0.0, 0.0)
    assert unknown and off_grid < LETHAL_OBSTACLE
    hits = collision_mask(costmap, np.full(2, 0.35), np.zeros(2), yaws=np.array([0.0, math.pi]))
    assert hits.tolist() == [False, True]


def test_assisted_teleop_measures_the_polygon_to_the_wall() -> None:
    costmap = _wall_costmap()
    poses = np.array([[0.2, 0.0, 0.0], [0.35, 0.0, math.pi]])
    front, rear = outline_lethal_distances(costmap, costmap.outline, poses, reach=1.0)
    assert front == pytest.approx(0.5 - (0.2 + 0.0765), abs=0.011)
    assert rear == 0.0  # the rear reaches over the wall


def test_footprint_problems_are_named() -> None:
    assert Footprint.circle(0.0).problem() is not None
    bow_tie = Footprint(polygon=((0.2, 0.1), (-0.1, -0.1), (0.1, -0.1), (-0.1, 0.15)))
    assert "not simple" in (bow_tie.problem() or "")
    away = Footprint.rectangle(0.1, 0.3, -0.1, 0.1)
    assert "base_link" in (away.problem() or "")
    assert Footprint(polygon=((0.1, 0.0), (0.2, 0.0))).problem() is not None
    assert WAFFLE.padded(0.01).polygon[0] == pytest.approx((-0.2145, -0.163))


def test_the_plot_draws_the_waffles_footprint_where_it_started_and_ended(tmp_path: Path) -> None:
    from baobab.missions.language.bundled_missions import resolve_mission
    from baobab.missions.run.plot_data import MobilePlot
    from baobab.missions.run.plotting import save_plot
    from baobab.missions.run.runner import run_mission

    record = run_mission(
        load_mission(resolve_mission("walls_go_to_goal"), robot="turtlebot3_waffle")
    )
    plot = record.plot
    assert isinstance(plot, MobilePlot)
    start, end = plot.footprints
    padded = WAFFLE.padded(0.01)
    expected = padded.at(Pose2D(x=0.0, y=0.0, yaw=0.0))
    assert np.allclose(start, expected, atol=0.01)  # the robot settles a little on its wheels
    assert len(end) == 4 and math.dist(end[0], (plot.xs[-1], plot.ys[-1])) < 0.3
    save_plot(plot, tmp_path / "plot.png")
    assert (tmp_path / "plot.png").stat().st_size > 10_000
