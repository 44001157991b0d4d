"""The Nav2 tasks end to end: NavigateToPose (cafe), NavigateThroughPoses (farm), FollowWaypoints,
FollowPath, and the navigation tree's shape.

Seed coordinates: seed 000's cafe tables, seed 001's 41 farm poses (tests/test_worlds.py).
"""

from __future__ import annotations

import itertools
import math

import py_trees
import pytest
from navigation_rig import distance, make_rig, yaw_error
from test_worlds import FARM_POSES

from baobab.nav.bt import (
    PipelineSequence,
    RateController,
    ReactiveFallback,
    RecoveryNode,
    RoundRobin,
)
from baobab.nav.errors import ComputePathToPoseError, FollowPathError, FollowWaypointsError
from baobab.nav.navigate import NavigateTask
from baobab.sim.tasks import TaskStatus
from baobab.sim.world import Pose2D


def _yaw(qz: float, qw: float) -> float:
    return math.remainder(2.0 * math.atan2(qz, qw), 2 * math.pi)


def test_cafe_serves_the_five_tables_in_turn_without_touching_anything() -> None:
    rig = make_rig("cafe")
    xy_tolerance, yaw_tolerance = 0.25, 0.25
    for index in range(1, 6):
        goal = rig.world.locations[f"table_{index}"]
        handle = rig.server.navigate_to_pose(goal)
        rig.run(handle, 60.0)
        assert handle.outcome is not None
        assert handle.outcome.status is TaskStatus.SUCCEEDED, (index, handle.outcome)
        assert distance(rig.pose(), goal) <= xy_tolerance, index
        assert yaw_error(rig.pose(), goal) <= yaw_tolerance, index
    assert rig.contacts.touched == set()
    assert rig.contacts.checks >= rig.sim.time / 0.01 - 1  # looked every 10 ms throughout
    assert rig.server.metrics.number_of_recoveries == 0


def test_farm_drives_through_the_41_seed_poses_between_the_crop_rows() -> None:
    rig = make_rig("farm")
    goals = [Pose2D(x=x, y=y, yaw=_yaw(qz, qw)) for x, y, qz, qw in FARM_POSES]
    handle = rig.server.navigate_through_poses(goals)
    samples: list[tuple[float, float, int]] = []
    while handle.status is TaskStatus.RUNNING:
        assert rig.sim.time < 600.0, "still driving after 600 s"
        rig.sim.step_for(5.0)
        fb = handle.feedback
        samples.append((rig.sim.time, fb["distance_remaining"], fb["number_of_poses_remaining"]))
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.SUCCEEDED
    assert rig.contacts.touched == set()  # no crop row, no fence
    assert distance(rig.pose(), goals[-1]) <= 0.25
    remaining = [d for _, d, _ in samples[:-1]]
    assert remaining[0] > 100.0  # the whole route is about 107 m
    # Every 5 s the remaining distance drops by at least 0.5 m, replans included.
    assert all(later < earlier - 0.5 for earlier, later in itertools.pairwise(remaining))
    poses_left = [n for _, _, n in samples]
    assert poses_left == sorted(poses_left, reverse=True) and poses_left[-1] == 1
    assert rig.server.metrics.number_of_recoveries == 0


def test_waypoint_follower_waits_at_each_and_moves_on_past_a_missed_one() -> None:
    rig = make_rig("walls")
    waypoints = [
        rig.world.locations["goal_open"],
        Pose2D(x=9.0, y=0.0),  # off the map: missed
        rig.world.locations["goal_behind_wall"],
    ]
    handle = rig.server.follow_waypoints(waypoints, 2.0, False)
    waiting = []
    seen = set()
    while handle.status is TaskStatus.RUNNING:
        assert rig.sim.time < 120.0
        rig.sim.step_for(0.05)
        seen.add(handle.feedback["current_waypoint"])
        if handle.feedback["current_waypoint"] == 0 and distance(rig.pose(), waypoints[0]) < 0.25:
            waiting.append(rig.sim.time)
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.SUCCEEDED
    assert seen == {0, 1, 2}
    assert waiting[-1] - waiting[0] >= 2.0 - 0.1  # paused at the first waypoint
    (missed,) = handle.feedback["missed_waypoints"]
    assert missed["index"] == 1
    assert missed["error_code"] == ComputePathToPoseError.GOAL_OUTSIDE_MAP
    assert distance(rig.pose(), waypoints[2]) <= 0.25
    assert rig.contacts.touched == set()


def test_waypoint_follower_stops_on_the_first_missed_waypoint_when_asked() -> None:
    rig = make_rig("walls")
    handle = rig.server.follow_waypoints(
        [Pose2D(x=9.0, y=0.0), rig.world.locations["goal_open"]], 0.0, True
    )
    rig.run(handle, 5.0)
    outcome = handle.outcome
    assert outcome is not None and outcome.status is TaskStatus.FAILED
    assert outcome.error_code == FollowWaypointsError.STOP_ON_MISSED_WAYPOINT == 603
    assert "GOAL_OUTSIDE_MAP" in outcome.error_msg
    assert [m["index"] for m in handle.feedback["missed_waypoints"]] == [0]
    empty = rig.server.follow_waypoints([], 0.0, True)
    rig.run(empty, 1.0)
    assert empty.outcome is not None
    assert empty.outcome.error_code == FollowWaypointsError.NO_VALID_WAYPOINTS


def test_a_new_waypoint_list_preempts_the_running_one_from_its_first_waypoint() -> None:
    rig = make_rig("walls")
    locations = rig.world.locations
    first = rig.server.follow_waypoints([locations["goal_open"], locations["goal_behind_wall"]])
    rig.sim.step_for(3.0)
    goal = locations["goal_behind_north_wall"]
    second = rig.server.follow_waypoints([goal], 0.0, True)
    assert first.outcome is not None and first.outcome.status is TaskStatus.FAILED
    assert first.outcome.error_code == 0 and "preempted" in first.outcome.error_msg
    rig.run(second, 60.0)
    assert second.outcome is not None and second.outcome.status is TaskStatus.SUCCEEDED
    assert second.feedback["current_waypoint"] == 0
    assert distance(rig.pose(), goal) <= 0.25
    assert rig.contacts.touched == set()


def test_follow_path_tracks_a_given_path_with_the_controller_alone() -> None:
    rig = make_rig("walls")
    goal = rig.world.locations["goal_behind_north_wall"]
    path = rig.server.compute_path(None, goal)
    poses = [Pose2D(x=float(x), y=float(y), yaw=float(yaw)) for x, y, yaw in path.poses]
    handle = rig.server.follow_path(poses)
    rig.run(handle, 60.0)
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.SUCCEEDED
    assert distance(rig.pose(), goal) <= 0.25
    assert rig.server.metrics.plans == 0  # FollowPath does not plan
    assert rig.contacts.touched == set()
    empty = rig.server.follow_path([])
    rig.run(empty, 1.0)
    assert empty.outcome is not None
    assert empty.outcome.error_code == FollowPathError.INVALID_PATH


def test_navigate_to_pose_tree_has_nav2s_shape() -> None:
    rig = make_rig("walls")
    task = rig.server.navigate_task([rig.world.locations["goal_open"]], through_poses=False)
    root = task.root
    assert isinstance(root, RecoveryNode) and root.number_of_retries == 6
    pipeline, recovery = root.children
    assert isinstance(pipeline, PipelineSequence)
    rate, following = pipeline.children
    assert isinstance(rate, RateController) and rate.period == pytest.approx(1.0)
    assert isinstance(following, RecoveryNode) and following.number_of_retries == 1
    assert [c.name for c in following.children] == ["FollowPath", "ClearLocalContext"]
    would_help, fallback = recovery.children
    assert [c.name for c in would_help.children] == [
        "WouldAControllerRecoveryHelp",
        "WouldAPlannerRecoveryHelp",
    ]
    assert isinstance(fallback, ReactiveFallback)
    goal_updated, actions = fallback.children
    assert goal_updated.name == "GoalUpdated"
    assert isinstance(actions, RoundRobin)
    assert [c.name for c in actions.children] == ["ClearingActions", "Spin", "Wait", "BackUp"]
    through = rig.server.navigate_task([rig.world.locations["goal_open"]], through_poses=True)
    assert isinstance(through, NavigateTask)
    through_rate = through.root.children[0].children[0]
    assert isinstance(through_rate, RateController)
    assert through_rate.period == pytest.approx(1 / 0.333)
    names = [node.name for node in through.root.iterate()]
    assert "RemovePassedGoals" in names and "ComputePathThroughPoses" in names
    assert py_trees.display.unicode_tree(root)  # the tree renders for reports
