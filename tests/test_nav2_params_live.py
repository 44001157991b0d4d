"""A Nav2 parameter file configures the running navigation stack.

tests/nav2_params/every_mapped.yaml sets every parameter baobab maps to a value other than
baobab's default; a ``BasicNavigator(params_file=...)`` built from it must report each value
from its live objects (costmaps, layers, planner, smoother, controller, checkers, behaviours,
the waypoint follower), not from the parsed file.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from baobab.nav import BasicNavigator
from baobab.nav.nav2_configuration import FILE, load_nav2_params
from baobab.nav.navigation_params import NavigationParams
from baobab.nav.server import NavigationServer
from baobab.nav.velocity_smoother import VelocitySmoother
from baobab.nav.waypoints import WaypointFollower
from baobab.robots.footprint import Footprint
from baobab.sim.world import Pose2D

PARAMS = Path(__file__).parent / "nav2_params"
EVERY = PARAMS / "every_mapped.yaml"

EXPECTED: dict[str, Any] = {
    "global_costmap.resolution": 0.1,
    "local_costmap.resolution": 0.1,
    "global_costmap_update_hz": 0.5,
    "local_costmap_update_hz": 4.0,
    "local_costmap_size.0": 4.0,
    "local_costmap_size.1": 3.5,
    "controller.controller_frequency": 25.0,
    "controller.rpp.controller_frequency": 25.0,
    "controller.failure_tolerance": 0.5,
    "controller.rpp.desired_linear_vel": 0.18,
    "controller.rpp.max_angular_vel": 2.0,
    "controller.rpp.lookahead_dist": 0.5,
    "controller.rpp.min_lookahead_dist": 0.25,
    "controller.rpp.max_lookahead_dist": 1.0,
    "controller.rpp.lookahead_time": 1.2,
    "controller.rpp.use_velocity_scaled_lookahead_dist": True,
    "controller.rpp.use_interpolation": False,
    "controller.rpp.use_rotate_to_heading": False,
    "controller.rpp.rotate_to_heading_min_angle": 0.6,
    "controller.rpp.rotate_to_heading_angular_vel": 1.5,
    "controller.rpp.max_angular_accel": 2.5,
    "controller.rpp.use_regulated_linear_velocity_scaling": False,
    "controller.rpp.regulated_linear_scaling_min_radius": 0.8,
    "controller.rpp.regulated_linear_scaling_min_speed": 0.1,
    "controller.rpp.use_cost_regulated_linear_velocity_scaling": False,
    "controller.rpp.cost_scaling_dist": 0.5,
    "controller.rpp.cost_scaling_gain": 1.2,
    "controller.rpp.inflation_cost_scaling_factor": 4.0,
    "controller.rpp.min_approach_linear_velocity": 0.04,
    "controller.rpp.approach_velocity_scaling_dist": 0.5,
    "controller.rpp.use_collision_detection": False,
    "controller.rpp.max_allowed_time_to_collision_up_to_carrot": 1.5,
    "controller.rpp.max_robot_pose_search_dist": 5.0,
    "controller.rpp.goal_dist_tol": 0.2,
    "controller.xy_goal_tolerance": 0.2,
    "controller.yaw_goal_tolerance": 0.3,
    "controller.stateful": False,
    "controller.required_movement_radius": 0.4,
    "controller.movement_time_allowance": 12.0,
    "planner.tolerance": 0.3,
    "planner.cost_travel_multiplier": 1.5,
    "planner.max_iterations": 500_000,
    "planner.allow_unknown": False,
    "planner.use_final_approach_orientation": True,
    "smoother.tolerance": 1e-8,
    "smoother.max_its": 800,
    "smoother.w_data": 0.25,
    "smoother.w_smooth": 0.35,
    "smoother.do_refinement": False,
    "smoother.refinement_num": 3,
    "behaviors.cycle_frequency": 20.0,
    "behaviors.simulate_ahead_time": 1.5,
    "behaviors.max_rotational_vel": 0.8,
    "behaviors.min_rotational_vel": 0.3,
    "behaviors.rotational_acc_lim": 2.0,
    "behaviors.acceleration_limit": 2.0,
    "behaviors.deceleration_limit": -2.0,
    "behaviors.minimum_speed": 0.12,
    "behaviors.projection_time": 0.8,
    "behaviors.simulation_time_step": 0.05,
    "waypoint_loop_rate": 10.0,
    "waypoint_stop_on_failure": False,
    "waypoint_pause": 0.3,
    "global_costmap.inflation_radius": 0.6,
    "global_costmap.cost_scaling_factor": 4.0,
    "local_costmap.inflation_radius": 0.5,
    "local_costmap.cost_scaling_factor": 5.0,
    "global_costmap.obstacle.obstacle_max_range": 2.2,
    "global_costmap.obstacle.obstacle_min_range": 0.04,
    "global_costmap.obstacle.raytrace_max_range": 2.9,
    "global_costmap.obstacle.raytrace_min_range": 0.03,
    "local_costmap.obstacle.obstacle_max_range": 2.0,
    "local_costmap.obstacle.obstacle_min_range": 0.05,
    "local_costmap.obstacle.raytrace_max_range": 2.8,
    "local_costmap.obstacle.raytrace_min_range": 0.02,
    "local_costmap.use_static_layer": False,
    "global_costmap.footprint": Footprint(
        polygon=((0.14, 0.12), (0.14, -0.12), (-0.12, -0.12), (-0.12, 0.12))
    ),
    "local_costmap.footprint": Footprint.circle(0.12),
    "global_costmap.static.track_unknown_space": True,
    "global_costmap.static.lethal_cost_threshold": 90,
    "global_costmap.static.unknown_cost_value": 254,
    "global_costmap.static.trinary_costmap": False,
    "local_costmap.static.track_unknown_space": True,
    "local_costmap.static.lethal_cost_threshold": 95,
    "local_costmap.static.unknown_cost_value": 253,
    "local_costmap.static.trinary_costmap": False,
    "velocity_smoother.enabled": True,
    "velocity_smoother.max_velocity": (0.2, 1.5),
    "velocity_smoother.min_velocity": (-0.15, -1.5),
    "velocity_smoother.max_accel": (1.5, 2.0),
    "velocity_smoother.max_decel": (-1.8, -2.2),
    "velocity_smoother.deadband_velocity": (0.01, 0.02),
    "velocity_smoother.scale_velocities": True,
    "velocity_smoother.feedback": "CLOSED_LOOP",
}
"""Each ``NavigationParams`` field the file sets, with the value it must have (baobab units)."""


def _layers(server: NavigationServer, target: str) -> Any:
    return server.global_layers if target.startswith("global") else server.local_layers


def _live(server: NavigationServer, waypoints: WaypointFollower, target: str) -> Any:
    """The value the running stack has for ``target``, read from the object that uses it."""
    head, _, rest = target.partition(".")
    rates = {t.name: 1 / (t.period_steps * server.sim.physics_dt) for t in server.timers}
    getters: dict[str, Callable[[], Any]] = {
        "global_costmap_update_hz": lambda: rates["nav global"],
        "local_costmap_update_hz": lambda: rates["nav local"],
        "local_costmap_size": lambda: _window_size(server)[int(rest)],
        "waypoint_loop_rate": lambda: 1.0 / waypoints.period,
        "waypoint_stop_on_failure": lambda: waypoints.stop_on_failure,
        "waypoint_pause": lambda: waypoints.wait_at_waypoint,
        "planner": lambda: getattr(server.planner.params, rest),
        "smoother": lambda: getattr(server.planner.smoother, rest),
        "behaviors": lambda: getattr(server.behavior_context.params, rest),
        "velocity_smoother": lambda: _smoother(server, rest),
    }
    if head in getters:
        return getters[head]()
    if head in ("global_costmap", "local_costmap"):
        layers = _layers(server, target)
        if rest == "resolution":
            return layers.costmap.resolution
        if rest == "footprint":
            return layers.costmap.footprint
        if rest in ("inflation_radius", "cost_scaling_factor"):
            return getattr(layers.inflation_layer.params, rest)
        if rest.startswith("static."):
            return getattr(layers.params.static, rest.removeprefix("static."))
        if rest.startswith("obstacle."):
            return getattr(layers.obstacle_layer.params, rest.removeprefix("obstacle."))
        return getattr(layers.params, rest)
    follower = server.follower
    if rest == "controller_frequency":
        return rates["nav control"]
    if rest.startswith("rpp."):
        return getattr(follower.controller.params, rest.removeprefix("rpp."))
    checker = {
        "xy_goal_tolerance": follower.goal_checker,
        "yaw_goal_tolerance": follower.goal_checker,
        "stateful": follower.goal_checker,
        "required_movement_radius": follower.progress_checker,
        "movement_time_allowance": follower.progress_checker,
    }.get(rest, follower)
    return getattr(checker.params if checker is follower else checker, rest)


def _smoother(server: NavigationServer, name: str) -> Any:
    """A velocity smoother setting; ``enabled``: whether one sits before the base."""
    smoother = server.drive
    if name == "enabled":
        return isinstance(smoother, VelocitySmoother) and server.follower.base is smoother
    assert isinstance(smoother, VelocitySmoother)
    return getattr(smoother.params, name)


def _window_size(server: NavigationServer) -> tuple[float, float]:
    costmap = server.local_costmap()
    return costmap.size_x * costmap.resolution, costmap.size_y * costmap.resolution


@pytest.fixture(scope="module")
def navigator() -> Any:
    nav = BasicNavigator(world="cafe", params_file=EVERY)
    yield nav
    nav.destroy_node()


def test_every_mapped_parameter_is_set_and_not_a_default() -> None:
    configuration = load_nav2_params(EVERY)
    targets = {
        target
        for setting in configuration.settings
        if setting.origin == FILE
        for target in setting.targets
    }
    targets |= {"local_costmap.use_static_layer"}
    assert targets == set(EXPECTED)
    assert all(setting.origin == FILE for setting in configuration.settings)
    assert configuration.unused == {}
    defaults = NavigationParams()
    for target, value in EXPECTED.items():
        assert _get(defaults, target) != value, target


def test_the_running_stack_reports_every_value_of_the_file(navigator: Any) -> None:
    server = navigator.server
    server.follow_waypoints([Pose2D(x=0.0, y=0.0, yaw=0.0)])
    waypoints = server.tasks.task
    assert isinstance(waypoints, WaypointFollower)
    wrong = {
        target: (_live(server, waypoints, target), value)
        for target, value in EXPECTED.items()
        if not _same(_live(server, waypoints, target), value)
    }
    server.cancel()
    assert wrong == {}


def _same(live: Any, expected: Any) -> bool:
    if isinstance(expected, Footprint):
        if expected.is_circle:
            return live == expected
        return live.radius is None and _same(live.polygon, expected.polygon)
    if isinstance(expected, bool | str) or isinstance(live, bool | str):
        return live == expected and type(live) is type(expected)
    if isinstance(expected, tuple):
        return len(live) == len(expected) and all(map(_same, live, expected))
    return math.isclose(live, expected, rel_tol=1e-9)


def _get(params: Any, target: str) -> Any:
    for part in target.split("."):
        params = params[int(part)] if isinstance(params, tuple) else getattr(params, part)
    return params
