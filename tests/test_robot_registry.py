"""The robot registry: robots as data, their published figures, and the defaults their facts
decide (navigation, teleop, fault monitors), checked on the costmap and on real physics."""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest

from baobab.nav.costmap import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from baobab.nav.footprint import collision_mask
from baobab.nav.layered_costmap import LayeredCostmap
from baobab.nav.robot_params import navigation_params
from baobab.nav.server import NavigationParams
from baobab.robots.catalog import (
    ALIASES,
    MOBILE_ROBOTS,
    ROBOTS,
    RobotInfo,
    default_mobile_robot,
    robot_named,
)
from baobab.robots.footprint import Footprint
from baobab.robots.tuning import tune
from baobab.sim.world import Box, Floor, Pose2D, World

REPO = Path(__file__).resolve().parents[1]
PACKAGES = ("missions", "behaviours", "nav", "robots", "sim")
REGISTRY = (
    "robots/catalog.py",
    "robots/__init__.py",  # the package's map of its folders
)
ROBOT_FOLDERS = (
    "robots/turtlebot3/",
    "robots/turtlebot4/",
    "robots/panda/",
    "missions/ros/",  # bundled node files: user code a mission runs, as its YAML names a robot
)


def _robot_words() -> re.Pattern[str]:
    """Every name of a bundled robot, its folder, and the words that name one in prose."""
    names = {*ROBOTS, *ALIASES, "turtlebot", "burger", "waffle", "franka", "create ?3", "tb[34]/"}
    return re.compile("|".join(sorted(names, key=len, reverse=True)), re.IGNORECASE)


def test_nothing_outside_a_robot_folder_and_the_registry_names_a_robot() -> None:
    pattern = _robot_words()
    found = []
    for package in PACKAGES:
        for path in sorted((REPO / package).rglob("*.py")):
            relative = path.relative_to(REPO).as_posix()
            if relative in REGISTRY or relative.startswith(ROBOT_FOLDERS):
                continue
            for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                match = pattern.search(line)
                if match:
                    found.append(f"{relative}:{number}: {match.group(0)!r}: {line.strip()}")
    assert not found, "\n".join(found)


def test_the_grep_finds_a_robot_named_outside_its_folder(tmp_path: Path) -> None:
    pattern = _robot_words()
    assert pattern.search("from baobab.robots.turtlebot4.facts import TURTLEBOT4")
    assert pattern.search('if robot != "turtlebot3":')
    assert pattern.search("the Burger's radius")
    assert pattern.search("FAULT = 'panda/joint1'")
    assert not pattern.search("a differential-drive robot's footprint")


def test_every_bundled_mobile_robot_has_the_published_figures() -> None:
    burger = ROBOTS["turtlebot3"].mobile_facts
    assert (burger.wheel_radius, burger.wheel_separation) == (0.033, 0.160)
    assert (burger.max_linear_speed, burger.max_angular_speed) == (0.22, 2.84)
    assert burger.footprint == Footprint.circle(0.105)
    waffle = ROBOTS["turtlebot3_waffle"].mobile_facts
    xs = [x for x, _ in waffle.footprint.polygon]
    ys = [y for _, y in waffle.footprint.polygon]
    assert max(xs) - min(xs) == pytest.approx(0.281) and max(ys) - min(ys) == pytest.approx(0.306)
    assert (waffle.wheel_radius, waffle.wheel_separation) == (0.033, 0.287)
    assert (waffle.max_linear_speed, waffle.max_angular_speed) == (0.26, 1.82)
    assert waffle.lidar.model == burger.lidar.model == "LDS-01"
    tb4 = ROBOTS["turtlebot4"].mobile_facts
    assert tb4.body.shape == "cylinder" and 2 * tb4.body.radius == pytest.approx(0.342)
    assert tb4.wheel_separation == pytest.approx(0.235, abs=0.003)
    assert tb4.wheel_radius == pytest.approx(0.036, abs=0.001)
    assert (tb4.max_linear_speed, tb4.max_angular_speed) == (0.306, 1.90)
    assert (tb4.lidar.range_min, tb4.lidar.range_max) == (0.15, 12.0)
    for name in MOBILE_ROBOTS:
        facts = ROBOTS[name].mobile_facts
        assert facts.footprint.problem() is None, name
        assert facts.sources, f"{name} states no source for its figures"


def test_the_burger_answers_to_its_alias_and_the_registry_lists_the_mobile_robots() -> None:
    assert robot_named("turtlebot3_burger") is ROBOTS["turtlebot3"]
    assert robot_named("turtlebot3") is ROBOTS["turtlebot3"]
    assert robot_named("turtlebot") is None
    assert MOBILE_ROBOTS == ("turtlebot3", "turtlebot3_waffle", "turtlebot4")
    assert not ROBOTS["panda"].mobile and ROBOTS["panda"].footprint is None


def test_the_default_robots_settings_are_the_navigation_defaults() -> None:
    burger = default_mobile_robot()
    params = navigation_params(burger)
    assert params == NavigationParams()
    assert params.global_costmap.robot_radius == 0.105
    assert params.global_costmap.inflation_radius == 0.55
    rpp = params.controller.rpp
    assert (rpp.desired_linear_vel, rpp.max_angular_vel) == (0.22, 2.84)
    assert rpp.regulated_linear_scaling_min_speed == 0.11
    assert (rpp.rotate_to_heading_angular_vel, rpp.max_angular_accel) == (1.8, 3.2)
    assert params.behaviors.minimum_speed == 0.10


def test_each_robots_navigation_defaults_come_from_its_facts() -> None:
    for name in MOBILE_ROBOTS:
        facts = ROBOTS[name].mobile_facts
        params = navigation_params(ROBOTS[name])
        rpp = params.controller.rpp
        assert rpp.desired_linear_vel == facts.max_linear_speed
        assert rpp.max_angular_vel == facts.max_angular_speed
        assert rpp.rotate_to_heading_angular_vel <= facts.max_angular_speed
        assert params.behaviors.max_rotational_vel <= facts.max_angular_speed
        assert params.behaviors.acceleration_limit == facts.max_linear_accel
        costmap = params.local_costmap
        assert costmap.inflation_radius >= costmap.footprint.circumscribed_radius
    waffle = navigation_params(ROBOTS["turtlebot3_waffle"]).local_costmap
    # Nav2's padFootprint: 0.01 m outward; the inscribed radius is base_link to the front edge.
    assert waffle.robot_radius == pytest.approx(0.0765 + 0.01)
    assert waffle.footprint.circumscribed_radius == pytest.approx(math.hypot(0.2145, 0.163))
    assert tune(ROBOTS["turtlebot4"].mobile_facts).scan_timeout == pytest.approx(5 / 5.5)


def _corridor() -> World:
    """A 2 m corridor between two walls 1 m apart (their faces at y = +-0.5 m)."""
    return World(
        name="corridor",
        floor=Floor(size=(4.0, 3.0)),
        boxes=[
            Box(name="north", center=(0.0, 0.6), size=(4.0, 0.2)),
            Box(name="south", center=(0.0, -0.6), size=(4.0, 0.2)),
        ],
        spawns={"default": Pose2D(x=0.0, y=0.0)},
    )


def _double(footprint: Footprint) -> RobotInfo:
    """The Burger with another footprint: a test double of a robot."""
    burger = default_mobile_robot()
    facts = dataclasses.replace(burger.mobile_facts, footprint=footprint)
    return dataclasses.replace(burger, name="double", aliases=(), facts=facts)


def _costmap(robot: RobotInfo) -> LayeredCostmap:
    return LayeredCostmap.global_costmap(_corridor(), navigation_params(robot).global_costmap)


def _band(robot: RobotInfo) -> float:
    """How far (m) from the north wall's face the inscribed band reaches along x = 0."""
    costmap = _costmap(robot).costmap
    ys = np.arange(0.0, 0.5, 0.01)
    costs = costmap.costs(np.zeros_like(ys), ys)
    blocked = ys[costs >= INSCRIBED_INFLATED_OBSTACLE]
    return 0.5 - float(blocked.min())


def test_a_bigger_footprint_widens_the_inflation_and_the_collision_checks_follow() -> None:
    small, large = _double(Footprint.circle(0.105)), _double(Footprint.circle(0.3))
    assert _band(small) == pytest.approx(0.105, abs=0.05)
    assert _band(large) == pytest.approx(0.3, abs=0.05)
    ys = np.array([0.25])
    assert not collision_mask(_costmap(small).costmap, np.zeros(1), ys)[0]
    assert collision_mask(_costmap(large).costmap, np.zeros(1), ys)[0]


def test_a_polygon_double_collides_by_its_outline_and_its_yaw() -> None:
    # 1.2 m long, 0.3 m wide: lengthwise it fits the 1 m corridor, crosswise it does not.
    bar = _double(Footprint.rectangle(-0.6, 0.6, -0.15, 0.15))
    costmap = _costmap(bar).costmap
    assert costmap.has_polygon
    assert costmap.inscribed_radius == pytest.approx(0.16)
    along, across = 0.0, math.pi / 2
    hits = collision_mask(
        costmap, np.zeros(2), np.zeros(2), yaws=np.array([along, across])
    ).tolist()
    assert hits == [False, True]
    # The outline on a lethal cell, however far from it the centre is.
    assert int(costmap.cost(0.0, 0.55)) == LETHAL_OBSTACLE


@pytest.mark.parametrize("name", MOBILE_ROBOTS)
def test_each_mobile_robot_stands_drives_at_its_limit_and_scans_from_its_mount(name: str) -> None:
    robot = ROBOTS[name]
    facts = robot.mobile_facts
    sim, built = robot.build_sim("walls", Pose2D(x=-2.5, y=2.4))
    model = sim.model
    sim.step_for(0.5)
    assert not built.base.robot_contacts()
    chassis = sim.data.body(built.names.body)
    assert abs(chassis.xpos[2]) < 0.005  # base_link on the floor: on its wheels and casters
    built.base.command(10.0, 0.0)
    sim.step_for(3.0)
    speed, _ = built.base.body_velocity()
    assert speed == pytest.approx(facts.max_linear_speed, rel=0.03)
    site = sim.data.site(built.names.lidar_site).xpos
    assert site[2] == pytest.approx(facts.lidar.z, abs=0.005)
    # Every robot geom lies within the footprint (the navigation stack's outline of it).
    root = model.body(built.names.body).id
    pose = built.base.pose()
    for geom in np.flatnonzero(model.body_rootid[model.geom_bodyid] == root):
        if model.geom(geom).name == built.names.footprint_geom:
            continue
        x, y = sim.data.geom_xpos[geom][:2]
        local_x = math.cos(pose.yaw) * (x - pose.x) + math.sin(pose.yaw) * (y - pose.y)
        local_y = -math.sin(pose.yaw) * (x - pose.x) + math.cos(pose.yaw) * (y - pose.y)
        assert facts.footprint.contains((local_x, local_y), tolerance=0.002), model.geom(geom).name


def test_teleop_and_fault_monitor_settings_follow_the_facts() -> None:
    from baobab.missions.run.fault_monitors import MonitorParams

    burger = default_mobile_robot()
    assert MonitorParams.for_robot(burger.tuning) == MonitorParams()
    assert (MonitorParams().scan_timeout, MonitorParams().max_plausible_speed) == (1.0, 2.0)
    tb4 = MonitorParams.for_robot(ROBOTS["turtlebot4"].tuning)
    assert tb4.scan_timeout == pytest.approx(5 / 5.5)  # five of its lidar's periods
    fast = dataclasses.replace(burger.mobile_facts, max_linear_speed=1.5, max_angular_speed=5.0)
    assert MonitorParams.for_robot(tune(fast)).max_plausible_speed == pytest.approx(4.5)
    slow = dataclasses.replace(burger.mobile_facts, max_linear_speed=0.15, max_angular_speed=1.0)
    tuning = tune(slow)
    assert tuning.teleop_speeds == (0.15, 1.0)
    assert tuning.progress == (pytest.approx(0.375), 10.0)  # a quarter of 10 s at top speed
    assert tuning.spin_speeds == (0.4, 1.0) and tuning.rotate_to_heading_speed == 1.0
    assert tune(burger.mobile_facts).teleop_speeds == (0.22, 1.2)
