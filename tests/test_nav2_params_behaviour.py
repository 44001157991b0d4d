"""The robot behaves as its Nav2 parameter file says (real physics, sim time).

Each test runs the same task twice, with two parameter files that differ in one parameter,
through ``BasicNavigator(params_file=...)``: a wider ``inflation_radius`` keeps the planned
path farther from the walls, a lower ``desired_linear_vel`` drives slower, a larger
``xy_goal_tolerance`` stops farther from the goal, and ``stop_on_failure: true`` ends the
waypoint follower at a blocked waypoint.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from baobab.nav import BasicNavigator, TaskResult
from baobab.nav.msgs import PoseStamped, pose_stamped
from baobab.sim.geometry import nearest_obstacle
from baobab.sim.world import Pose2D


@contextmanager
def navigator(tmp_path: Path, name: str, text: str, **kwargs: object) -> Iterator[BasicNavigator]:
    path = tmp_path / f"{name}.yaml"
    path.write_text(textwrap.dedent(text))
    nav = BasicNavigator(params_file=path, **kwargs)  # type: ignore[arg-type]
    try:
        yield nav
    finally:
        nav.destroy_node()


def wait(nav: BasicNavigator, limit: float) -> None:
    start = nav.server.sim.time
    while not nav.isTaskComplete():
        assert nav.server.sim.time - start < limit, "task still running"


def _inflation(radius: float) -> str:
    return f"""\
    global_costmap:
      global_costmap:
        ros__parameters:
          plugins: [static_layer, obstacle_layer, inflation_layer]
          inflation_layer:
            plugin: nav2_costmap_2d::InflationLayer
            inflation_radius: {radius}
            cost_scaling_factor: 3.0
    """


def test_a_wider_inflation_radius_keeps_the_path_farther_from_the_walls(tmp_path: Path) -> None:
    clearances = []
    for radius in (0.25, 0.9):
        with navigator(tmp_path, f"r{radius}", _inflation(radius), world="walls") as nav:
            path = nav.getPath(PoseStamped(), pose_stamped(2.2, 0.0), use_start=False)
            assert path is not None
            points = [(p.pose.position.x, p.pose.position.y) for p in path.poses]
            clearances.append(min(nearest_obstacle(nav.world, x, y)[1] for x, y in points[5:-5]))
    narrow, wide = clearances
    assert wide > narrow + 0.1


def _speed(velocity: float) -> str:
    return f"""\
    controller_server:
      ros__parameters:
        FollowPath:
          plugin: nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController
          desired_linear_vel: {velocity}
    """


def test_a_lower_desired_linear_vel_drives_slower(tmp_path: Path) -> None:
    top_speeds = []
    for velocity in (0.22, 0.1):
        with navigator(tmp_path, f"v{velocity}", _speed(velocity), world="walls") as nav:
            nav.goToPose(pose_stamped(2.0, 2.0))
            fastest = 0.0
            while not nav.isTaskComplete():
                fastest = max(fastest, abs(nav.server.base.body_velocity()[0]))
                assert nav.server.sim.time < 120.0
            assert nav.getResult() is TaskResult.SUCCEEDED
            top_speeds.append(fastest)
    default, slow = top_speeds
    assert default > 0.18
    assert slow < 0.105


def _tolerance(xy: float) -> str:
    return f"""\
    controller_server:
      ros__parameters:
        goal_checker_plugins: [goal_checker]
        goal_checker:
          plugin: nav2_controller::SimpleGoalChecker
          xy_goal_tolerance: {xy}
          yaw_goal_tolerance: 6.3
    """


def test_xy_goal_tolerance_decides_where_the_goal_counts_as_reached(tmp_path: Path) -> None:
    misses = []
    for xy in (0.05, 0.6):
        with navigator(tmp_path, f"t{xy}", _tolerance(xy), world="walls") as nav:
            nav.goToPose(pose_stamped(2.0, 2.0))
            wait(nav, 120.0)
            assert nav.getResult() is TaskResult.SUCCEEDED
            pose = nav.robot_pose()
            misses.append(math.hypot(pose.x - 2.0, pose.y - 2.0))
    tight, loose = misses
    assert tight <= 0.05
    assert 0.3 < loose <= 0.6


def _stop(stop: bool) -> str:
    return f"""\
    waypoint_follower:
      ros__parameters:
        stop_on_failure: {str(stop).lower()}
    planner_server:
      ros__parameters:
        GridBased:
          plugin: nav2_navfn_planner::NavfnPlanner
          tolerance: 0.0
    """


def test_stop_on_failure_stops_the_follower_at_a_blocked_waypoint(tmp_path: Path) -> None:
    blocked = (1.2, -0.35)  # inside wall_east, no substitute goal within tolerance 0
    outcomes = []
    for stop in (True, False):
        with navigator(tmp_path, f"s{stop}", _stop(stop), world="walls") as nav:
            nav.followWaypoints(
                [pose_stamped(0.8, 0.8), pose_stamped(*blocked), pose_stamped(2.0, 2.0)]
            )
            wait(nav, 120.0)
            pose = nav.robot_pose()
            reached_last = math.hypot(pose.x - 2.0, pose.y - 2.0) <= 0.25
            outcomes.append((nav.getResult(), reached_last))
    assert outcomes == [(TaskResult.FAILED, False), (TaskResult.SUCCEEDED, True)]


def test_the_waypoint_follower_pauses_as_the_file_says(tmp_path: Path) -> None:
    text = """\
    waypoint_follower:
      ros__parameters:
        waypoint_task_executor_plugin: wait_at_waypoint
        wait_at_waypoint:
          plugin: nav2_waypoint_follower::WaitAtWaypoint
          waypoint_pause_duration: 3000
    """
    with navigator(tmp_path, "pause", text, world="walls", start=Pose2D(x=0.0, y=0.0)) as nav:
        nav.followWaypoints([pose_stamped(0.0, 0.0)])
        start = nav.server.sim.time
        wait(nav, 30.0)
        assert nav.getResult() is TaskResult.SUCCEEDED
        assert nav.server.sim.time - start >= 3.0


def test_the_velocity_smoother_limits_the_driven_speed(tmp_path: Path) -> None:
    text = """\
    velocity_smoother:
      ros__parameters:
        max_velocity: [0.12, 0.0, 1.0]
        min_velocity: [-0.12, 0.0, -1.0]
    """
    with navigator(tmp_path, "smoothed", text, world="walls") as nav:
        nav.goToPose(pose_stamped(2.0, 2.0))
        fastest = 0.0
        while not nav.isTaskComplete():
            fastest = max(fastest, abs(nav.server.base.body_velocity()[0]))
            assert nav.server.sim.time < 120.0
        assert nav.getResult() is TaskResult.SUCCEEDED
    assert 0.1 < fastest < 0.125  # RPP asks for 0.22 m/s
