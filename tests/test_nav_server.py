"""The navigation server wired to a TurtleBot3: the port, fast failures, obstacles, cancel, preempt.

Everything runs on real physics (MuJoCo) with the robot's lidar feeding the costmaps.
"""

from __future__ import annotations

import inspect
import math

import numpy as np
import pytest
from navigation_rig import alcove, distance, make_rig

from baobab.behaviours.ports import NavigationPort
from baobab.nav import NavigationServer, build_navigation
from baobab.nav.costmap import LETHAL_OBSTACLE, Costmap2D
from baobab.nav.errors import (
    ComputePathThroughPosesError,
    ComputePathToPoseError,
    NavigationError,
    SmoothPathError,
)
from baobab.nav.layered_costmap import LayeredCostmap
from baobab.nav.path import Path
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.tasks import TaskStatus
from baobab.sim.world import Pose2D, load_world


def test_a_turtlebot3_wires_to_the_server_and_the_server_is_a_navigation_port() -> None:
    world = load_world("cafe")
    sim, robot = build_turtlebot3_sim(world)
    server = build_navigation(sim, robot.base, robot.lidar, world)
    port: NavigationPort = server  # mypy checks the server against the mission layer's port
    assert isinstance(port, NavigationServer)
    # The same check at run time: every port method, with the port's parameters by name.
    for name, method in inspect.getmembers(NavigationPort, inspect.isfunction):
        if name.startswith("_"):
            continue
        wanted = list(inspect.signature(method).parameters.values())[1:]
        offered = inspect.signature(getattr(server, name)).parameters
        assert [p.name for p in wanted] == list(offered)[: len(wanted)], name
        extra = list(offered.values())[len(wanted) :]
        assert all(p.default is not inspect.Parameter.empty for p in extra), name
    # The lidar feeds the costmaps: after one global update what the robot sees within the
    # marking range (2.5 m: table_1 and its chairs) is in the obstacle layer.
    sim.step_for(1.05)
    assert (server.global_layers.obstacle_layer.grid.data == LETHAL_OBSTACLE).sum() > 10
    assert server.robot_pose() == robot.base.pose()
    robot.base.command(0.2, 0.0)
    sim.step_for(1.0)
    assert server.metrics.distance_driven > 0.1
    server.close()  # no more callbacks: the odometer stops although the robot drives on
    driven = server.metrics.distance_driven
    sim.step_for(1.0)
    assert server.metrics.distance_driven == driven
    assert distance(server.robot_pose(), world.spawn) > driven + 0.1


def test_goals_in_an_obstacle_or_off_the_map_fail_at_once() -> None:
    rig = make_rig("cafe")
    table_3 = next(c for c in rig.world.cylinders if c.name == "table_3")
    inside = rig.server.navigate_to_pose(Pose2D(x=table_3.center[0], y=table_3.center[1]))
    assert rig.run(inside, 1.0) <= 0.05
    assert inside.outcome is not None
    assert (inside.outcome.status, inside.outcome.error_name) == (
        TaskStatus.FAILED,
        "GOAL_OCCUPIED",
    )
    assert inside.outcome.error_code == ComputePathToPoseError.GOAL_OCCUPIED == 206
    assert inside.feedback["number_of_recoveries"] == 0  # not a recoverable code
    outside = rig.server.navigate_to_pose(Pose2D(x=40.0, y=0.0))
    assert rig.run(outside, 1.0) <= 0.05
    assert outside.outcome is not None
    assert outside.outcome.error_code == ComputePathToPoseError.GOAL_OUTSIDE_MAP
    assert distance(rig.pose(), rig.world.spawn) < 0.01


def test_a_box_dropped_on_the_path_is_seen_and_driven_around() -> None:
    rig = make_rig("cafe")
    goal = rig.world.locations["table_3"]
    handle = rig.server.navigate_to_pose(goal)
    rig.sim.step_for(5.0)
    path = rig.server.current_path
    assert path is not None
    here = rig.pose()
    ahead = int(np.argmax(np.hypot(path.xy[:, 0] - here.x, path.xy[:, 1] - here.y) > 2.0))
    box_x, box_y = (float(v) for v in path.xy[ahead])

    def box_cells() -> np.ndarray:
        costmap = rig.server.global_costmap()
        ix, iy = costmap.world_to_map(box_x, box_y) or (0, 0)
        return costmap.data[iy - 4 : iy + 5, ix - 4 : ix + 5]  # 0.45 m around the centre

    assert box_cells().max() < LETHAL_OBSTACLE
    rig.place_box(0, box_x, box_y)
    rig.sim.step_for(1.2)  # a lidar scan and a global costmap update later: the face is seen
    assert box_cells().max() == LETHAL_OBSTACLE
    assert handle.status is TaskStatus.RUNNING
    replanned = rig.server.current_path
    assert replanned is not None and replanned is not path
    # The new path keeps the robot's footprint off the 0.3 m box.
    clearance = np.hypot(replanned.xy[:, 0] - box_x, replanned.xy[:, 1] - box_y).min()
    assert clearance > 0.15 + 0.105
    rig.run(handle, 120.0)
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.SUCCEEDED
    assert rig.contacts.touched == set()
    assert distance(rig.pose(), goal) <= 0.25


def test_cancel_stops_the_wheels_within_a_tenth_of_a_second() -> None:
    rig = make_rig("cafe")
    handle = rig.server.navigate_to_pose(rig.world.locations["table_3"])
    rig.sim.step_for(8.0)
    assert min(abs(w) for w in rig.wheel_speeds()) > 5.0  # cruising at about 0.2 m/s
    handle.cancel()
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.CANCELED
    assert rig.robot.base.target == (0.0, 0.0)  # zero commanded at once, not a tick later
    assert rig.server.active_task is None
    rig.sim.step_for(0.1)
    assert max(abs(w) for w in rig.wheel_speeds()) < 0.1  # rad/s: 3 mm/s at the rim
    assert rig.contacts.touched == set()


def test_a_new_goal_preempts_the_running_one_and_the_robot_ends_there() -> None:
    rig = make_rig("cafe")
    first = rig.server.navigate_to_pose(rig.world.locations["table_3"])
    rig.sim.step_for(6.0)
    assert first.feedback["navigation_time"] == pytest.approx(5.95)
    goal = rig.world.locations["table_2"]
    second = rig.server.navigate_to_pose(goal)
    assert first.outcome is not None
    assert (first.outcome.status, first.outcome.error_code) == (TaskStatus.FAILED, 0)
    assert "preempted" in first.outcome.error_msg
    assert rig.server.active_task is second
    rig.sim.step_for(0.05)
    assert second.feedback["navigation_time"] == 0.0  # restarted with the new goal
    rig.run(second, 60.0)
    assert second.outcome is not None and second.outcome.status is TaskStatus.SUCCEEDED
    assert distance(rig.pose(), goal) <= 0.25
    assert rig.contacts.touched == set()


def test_a_goal_of_another_type_cancels_the_running_task() -> None:
    rig = make_rig("cafe")
    navigation = rig.server.navigate_to_pose(rig.world.locations["table_3"])
    rig.sim.step_for(1.0)
    spin = rig.server.spin(0.5, 5.0)
    assert navigation.outcome is not None and navigation.outcome.status is TaskStatus.CANCELED
    rig.run(spin, 5.0)
    assert spin.outcome is not None and spin.outcome.status is TaskStatus.SUCCEEDED


def test_feedback_follows_nav2_while_driving() -> None:
    rig = make_rig("cafe")
    goal = rig.world.locations["table_3"]
    handle = rig.server.navigate_to_pose(goal)
    rig.sim.step_for(10.0)
    fb = handle.feedback
    assert set(fb) >= {
        "current_pose",
        "navigation_time",
        "estimated_time_remaining",
        "distance_remaining",
        "number_of_recoveries",
    }
    assert fb["navigation_time"] == pytest.approx(9.95)
    assert distance(fb["current_pose"], rig.pose()) < 0.02  # sampled at the last tick
    path = rig.server.current_path
    assert path is not None
    closest = int(np.argmin(np.hypot(path.xy[:, 0] - rig.pose().x, path.xy[:, 1] - rig.pose().y)))
    assert fb["distance_remaining"] == pytest.approx(path.length(closest), abs=0.1)
    # Driving at about 0.22 m/s: ETA = distance over the smoothed speed.
    assert fb["estimated_time_remaining"] == pytest.approx(fb["distance_remaining"] / 0.22, rel=0.1)
    rig.run(handle, 60.0)
    assert handle.feedback["estimated_time_remaining"] == 0.0
    assert handle.feedback["distance_remaining"] < 0.3


def test_metrics_count_driven_and_planned_length() -> None:
    rig = make_rig("cafe")
    handle = rig.server.navigate_to_pose(rig.world.locations["table_1"])
    rig.run(handle, 60.0)
    metrics = rig.server.metrics
    assert metrics.plans == metrics.replans + 1 >= 5  # replanning at 1 Hz
    assert 1.0 < metrics.planned_path_length < 2.0
    assert metrics.distance_driven == pytest.approx(metrics.planned_path_length, abs=0.4)
    assert metrics.number_of_recoveries == 0


def test_planning_services() -> None:
    rig = make_rig("cafe")
    server = rig.server
    tables = [rig.world.locations[f"table_{i}"] for i in (1, 2)]
    direct = server.compute_path(None, tables[1])
    assert isinstance(direct, Path)
    assert distance(direct.pose(0), rig.pose()) < 1e-9
    assert distance(direct.goal, tables[1]) < 1e-9
    through = server.compute_path_through_poses(None, tables)
    assert min(np.hypot(through.xy[:, 0] - tables[0].x, through.xy[:, 1] - tables[0].y)) < 1e-9
    assert through.length() > direct.length()
    # The leg between the two tables is reused while the costmap there is unchanged.
    reused = server.through_poses.legs_reused
    again = server.compute_path_through_poses(None, tables)
    assert server.through_poses.legs_reused == reused + 1
    np.testing.assert_array_equal(again.poses, through.poses)
    with pytest.raises(NavigationError) as caught:
        server.compute_path_through_poses(None, [tables[0], Pose2D(x=40.0, y=0.0)])
    assert caught.value.code == ComputePathThroughPosesError.GOAL_OUTSIDE_MAP
    assert "goal 1" in caught.value.message
    with pytest.raises(NavigationError) as caught:
        server.compute_path_through_poses(None, [])
    assert caught.value.code == ComputePathThroughPosesError.NO_VIAPOINTS_GIVEN
    raw = Path.from_points(np.array([[0.0, 0.0], [0.5, 0.3], [1.0, 0.0], [1.5, 0.3]]), 0.0)
    smoothed = server.smooth_path(raw, check_for_collisions=True)
    np.testing.assert_allclose(smoothed.xy[[0, -1]], raw.xy[[0, -1]])
    assert smoothed.length() < raw.length()
    with pytest.raises(NavigationError) as caught:
        server.smooth_path(Path(np.zeros((0, 3))))
    assert caught.value.code == SmoothPathError.INVALID_PATH


def test_costmaps_and_clearing() -> None:
    rig = make_rig("cafe", Pose2D(x=-0.96, y=-0.92))  # table_1's serving point
    server = rig.server
    rig.sim.step_for(1.05)
    assert isinstance(server.global_costmap(), Costmap2D)
    local = server.local_costmap()
    assert (local.size_x, local.size_y) == (60, 60)  # 3 m x 3 m at 0.05 m
    x0, y0, x1, y1 = local.bounds
    here = rig.pose()
    assert math.isclose((x0 + x1) / 2, here.x, abs_tol=0.05)
    assert math.isclose((y0 + y1) / 2, here.y, abs_tol=0.05)
    marked = server.global_layers.obstacle_layer.grid.data
    assert (marked == LETHAL_OBSTACLE).any()
    # What the latest scan alone marks on a fresh obstacle layer: what a clear keeps.
    scan = rig.robot.lidar.latest
    assert scan is not None
    seen = LayeredCostmap.global_costmap(rig.world).obstacle_layer
    seen.add_scan(scan)
    assert np.array_equal(marked, seen.grid.data)
    stale = server.global_costmap().world_to_map(2.5, -2.5) or (0, 0)  # nothing there
    marked[stale[1], stale[0]] = LETHAL_OBSTACLE
    local_marks = server.local_layers.obstacle_layer.grid.data
    local_before = local_marks.copy()
    server.clear_costmaps("global")
    assert marked[stale[1], stale[0]] != LETHAL_OBSTACLE  # forgotten: no beam marks it
    assert np.array_equal(marked, seen.grid.data)  # what the lidar sees stays
    assert np.array_equal(local_marks, local_before)  # the local costmap was left alone
    local_marks[:] = LETHAL_OBSTACLE
    server.clear_costmaps("all")
    assert 0 < np.count_nonzero(local_marks == LETHAL_OBSTACLE) < local_marks.size // 10
    with pytest.raises(ValueError, match="local"):
        server.clear_costmaps("both")


def test_a_plan_right_after_a_clear_avoids_what_the_lidar_sees() -> None:
    # Nav2's planner waits after a clear until the costmap has marked the latest scan again
    # (waitForCostmap): it never plans through an obstacle it sees, here a 0.3 m box sealing
    # the only way out of an alcove and known to the lidar alone.
    rig = make_rig(alcove())
    rig.place_box(0, -0.1, 0.0)
    rig.sim.step_for(1.05)  # a scan and a global costmap update
    goal = Pose2D(x=2.0, y=1.0)
    with pytest.raises(NavigationError) as blocked:
        rig.server.compute_path(None, goal)
    assert blocked.value.code == ComputePathToPoseError.NO_VALID_PATH
    for which in ("global", "all"):
        rig.server.clear_costmaps(which)
        with pytest.raises(NavigationError) as caught:
            rig.server.compute_path(None, goal)
        assert caught.value.code == ComputePathToPoseError.NO_VALID_PATH
    rig.place_box(0, 2.5, -1.5)  # taken away: the next scans see through
    rig.sim.step_for(1.0)
    assert len(rig.server.compute_path(None, goal)) > 0
