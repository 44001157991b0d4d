"""BasicNavigator: Nav2's Simple Commander API over the simulated TurtleBot3 (real physics).

Every test drives the navigator as a Nav2 script would: send, poll ``isTaskComplete()``, read
``getFeedback()``, then ``getResult()``; sim time is the only clock.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import mujoco
import numpy as np
import pytest
from navigation_rig import ContactWatch, distance

from baobab.nav import BasicNavigator, NavigationResult, RunningTask, TaskResult
from baobab.nav.errors import (
    ComputePathThroughPosesError,
    ComputePathToPoseError,
    DriveOnHeadingError,
    FollowPathError,
    NavigateThroughPosesError,
    NavigateToPoseError,
    SmoothPathError,
)
from baobab.nav.msgs import (
    DurationMsg,
    Goals,
    OccupancyGrid,
    Path,
    PoseStamped,
    Quaternion,
    Twist,
    pose_stamped,
    to_pose2d,
)
from baobab.nav.navigator import LoadMapResult
from baobab.nav.navigator_core import POLL_HORIZON
from baobab.nav.navigator_feedback import GoalStatus
from baobab.nav.navigator_robot import NavigatorSetupError
from baobab.nav.ros.nav2_msgs.action import (
    BackUp,
    FollowWaypoints,
    NavigateThroughPoses,
    NavigateToPose,
    Spin,
)
from baobab.nav.ros.nav2_msgs.msg import WaypointStatus
from baobab.nav.rostime import ClockType, Duration
from baobab.sim.builder import movable_slot_name
from baobab.sim.errors import WorldError
from baobab.sim.world import Pose2D

TABLE_1 = (-0.96, -0.92)
"""The cafe's first serving point (seed 000), 1.3 m from the spawn."""


def seconds(msg: DurationMsg) -> float:
    return Duration.from_msg(msg).nanoseconds / 1e9


def goal(
    navigator: BasicNavigator, x: float, y: float, qz: float = 0.0, qw: float = 1.0
) -> PoseStamped:
    """A goal built field by field, as Nav2 scripts do."""
    pose = PoseStamped()
    pose.header.frame_id = "map"
    pose.header.stamp = navigator.get_clock().now().to_msg()
    pose.pose.position.x = x
    pose.pose.position.y = y
    pose.pose.orientation.z = qz
    pose.pose.orientation.w = qw
    return pose


def sim_time(navigator: BasicNavigator) -> float:
    return navigator.get_clock().now().nanoseconds / 1e9


@pytest.fixture
def cafe() -> Iterator[BasicNavigator]:
    navigator = BasicNavigator(world="cafe")
    yield navigator
    navigator.destroy_node()


def wait(navigator: BasicNavigator, limit: float) -> int:
    """Poll until the task completes; the number of polls. Fails past ``limit`` s of sim time."""
    polls, start = 0, sim_time(navigator)
    while not navigator.isTaskComplete():
        polls += 1
        assert sim_time(navigator) - start < limit, "task still running"
    return polls


def test_go_to_pose_with_a_feedback_loop(cafe: BasicNavigator) -> None:
    contacts = ContactWatch(cafe.server.sim, "tb3/base_link")
    assert cafe.goToPose(goal(cafe, *TABLE_1)) is RunningTask.NAVIGATE_TO_POSE
    samples: list[tuple[float, float, float]] = []
    before = sim_time(cafe)
    while not cafe.isTaskComplete():
        after = sim_time(cafe)
        assert 0.0 < after - before <= POLL_HORIZON + 1e-9  # one poll, at most 0.1 s of sim time
        before = after
        feedback = cafe.getFeedback()
        assert isinstance(feedback, NavigateToPose.Feedback)
        assert isinstance(feedback.navigation_time, DurationMsg)
        assert feedback.current_pose.header.frame_id == "map"
        samples.append(
            (
                seconds(feedback.navigation_time),
                feedback.distance_remaining,
                seconds(feedback.estimated_time_remaining),
            )
        )
        assert sim_time(cafe) < 30.0
    times, distances, etas = (np.array(column) for column in zip(*samples, strict=True))
    assert np.all(np.diff(times) > 0) and times[-1] > 5.0
    assert distances[0] > 1.2 and distances[-1] < 0.3
    assert np.all(np.diff(distances) <= 0.05)  # shrinks, up to the jitter of 1 Hz replanning
    moving = etas[etas > 0]
    assert len(moving) > 10 and moving[0] > moving[-1] + 2.0
    assert cafe.getResult() is TaskResult.SUCCEEDED
    assert cafe.getResult() == NavigationResult.SUCCEEDED
    assert cafe.getTaskError() == (0, "")
    assert distance(cafe.robot_pose(), Pose2D(x=TABLE_1[0], y=TABLE_1[1])) <= 0.25
    assert not contacts.touched
    # Completed: further polls return at once, without advancing the simulation.
    done_at = sim_time(cafe)
    assert cafe.isTaskComplete() and cafe.isNavComplete()
    assert sim_time(cafe) == done_at


def test_preempt_then_cancel_mid_way(cafe: BasicNavigator) -> None:
    cafe.goToPose(goal(cafe, 0.0, -3.0))
    for _ in range(30):
        assert not cafe.isTaskComplete()
    first = cafe.getFeedback()
    assert isinstance(first, NavigateToPose.Feedback) and seconds(first.navigation_time) > 2.5
    # Same type: preempted in place, the navigation time starts again.
    assert cafe.goToPose(goal(cafe, 1.0, -3.0)) is RunningTask.NAVIGATE_TO_POSE
    for _ in range(5):
        assert not cafe.isTaskComplete()
    second = cafe.getFeedback()
    assert isinstance(second, NavigateToPose.Feedback) and seconds(second.navigation_time) < 1.0
    assert abs(cafe.server.base.body_velocity()[0]) > 0.05

    cafe.cancelNav()
    assert cafe.isTaskComplete()
    assert cafe.getResult() is TaskResult.CANCELED
    assert cafe.getFeedback() is None  # Rolling clears feedback on cancel
    assert cafe.result_future is not None
    response = cafe.result_future.result()
    assert response is not None and response.status == GoalStatus.STATUS_CANCELED
    cafe.server.sim.step_for(0.3)
    assert abs(cafe.server.base.body_velocity()[0]) < 0.01


def test_follow_waypoints_skips_a_waypoint_inside_a_table(cafe: BasicNavigator) -> None:
    waypoints = [goal(cafe, 0.5, -0.5), goal(cafe, -2.0, -0.6), goal(cafe, *TABLE_1)]
    assert cafe.followWaypoints(waypoints) is RunningTask.FOLLOW_WAYPOINTS
    seen: list[int] = []
    polls_on_the_occupied_waypoint = 0
    while not cafe.isTaskComplete():
        feedback = cafe.getFeedback()
        assert isinstance(feedback, FollowWaypoints.Feedback)
        if not seen or seen[-1] != feedback.current_waypoint:
            seen.append(feedback.current_waypoint)
        polls_on_the_occupied_waypoint += feedback.current_waypoint == 1
        assert sim_time(cafe) < 40.0
    assert seen in ([0, 2], [0, 1, 2])
    # Waypoint 1 fails (GOAL_OCCUPIED) in the loop tick it starts: a 0.1 s poll sees it at most
    # once, when the tick that reached waypoint 0 and the one that fails 1 fall in two polls.
    assert polls_on_the_occupied_waypoint <= 1
    assert cafe.getResult() is TaskResult.SUCCEEDED  # stop_on_failure false, as nav2_bringup
    assert cafe.result_future is not None
    response = cafe.result_future.result()
    assert response is not None and response.status == GoalStatus.STATUS_SUCCEEDED
    missed = response.result.missed_waypoints  # type: ignore[attr-defined]
    assert [m.waypoint_index for m in missed] == [1]
    assert missed[0].waypoint_status == WaypointStatus.FAILED
    assert missed[0].error_code == ComputePathToPoseError.GOAL_OCCUPIED
    assert missed[0].waypoint_pose.pose.position.x == -2.0
    assert distance(cafe.robot_pose(), Pose2D(x=TABLE_1[0], y=TABLE_1[1])) <= 0.25


def test_go_through_poses_in_the_farm() -> None:
    navigator = BasicNavigator(world="farm", start=Pose2D(x=-6.5, y=-4.2))
    try:
        poses = [goal(navigator, -5.0, -4.2), goal(navigator, -3.5, -4.2)]
        assert navigator.goThroughPoses(Goals(goals=poses)) is RunningTask.NAVIGATE_THROUGH_POSES
        remaining: list[int] = []
        while not navigator.isTaskComplete():
            feedback = navigator.getFeedback()
            if isinstance(feedback, NavigateThroughPoses.Feedback):
                remaining.append(feedback.number_of_poses_remaining)
            assert sim_time(navigator) < 30.0
        assert navigator.getResult() is TaskResult.SUCCEEDED
        assert remaining[0] == 2 and remaining[-1] == 1 and remaining == sorted(remaining)[::-1]
        assert distance(navigator.robot_pose(), Pose2D(x=-3.5, y=-4.2)) <= 0.25
    finally:
        navigator.destroyNode()


def test_spin_back_up_and_drive_on_heading(cafe: BasicNavigator) -> None:
    start = cafe.robot_pose()
    assert cafe.spin(spin_dist=1.57) is RunningTask.SPIN
    turned: list[float] = []
    while not cafe.isTaskComplete():
        feedback = cafe.getFeedback()
        assert isinstance(feedback, Spin.Feedback)
        turned.append(feedback.angular_distance_traveled)
    assert cafe.getResult() is TaskResult.SUCCEEDED
    assert turned[-1] > 1.3 and turned == sorted(turned)
    assert abs(math.remainder(cafe.robot_pose().yaw - start.yaw - 1.57, 2 * math.pi)) < 0.1

    facing = cafe.robot_pose()
    assert cafe.backUp(backup_dist=0.2, backup_speed=0.1) is RunningTask.BACKUP
    assert BasicNavigator.backUp is BasicNavigator.backup
    assert isinstance(cafe.getFeedback(), BackUp.Feedback | None)
    wait(cafe, 10.0)
    assert cafe.getResult() is TaskResult.SUCCEEDED
    backed = cafe.robot_pose()
    along = (backed.x - facing.x) * math.cos(facing.yaw) + (backed.y - facing.y) * math.sin(
        facing.yaw
    )
    assert -0.3 < along < -0.18

    assert cafe.driveOnHeading(dist=0.3, speed=0.15) is RunningTask.DRIVE_ON_HEADING
    wait(cafe, 10.0)
    assert cafe.getResult() is TaskResult.SUCCEEDED
    assert 0.28 < distance(cafe.robot_pose(), backed) < 0.4

    # Accepted, then aborted by the behaviour server: speed and distance of opposite signs.
    assert cafe.driveOnHeading(dist=0.3, speed=-0.1) is RunningTask.DRIVE_ON_HEADING
    wait(cafe, 1.0)
    assert cafe.getResult() is TaskResult.FAILED
    assert cafe.getTaskError()[0] == DriveOnHeadingError.INVALID_INPUT


def test_clear_all_costmaps_during_a_run_and_get_costmaps(cafe: BasicNavigator) -> None:
    sim = cafe.server.sim
    box = sim.model.body(movable_slot_name(0))
    sim.data.mocap_pos[box.mocapid[0]] = [1.0, 1.2, 0.25]  # beside the route, not on it
    mujoco.mj_forward(sim.model, sim.data)
    cafe.goToPose(goal(cafe, *TABLE_1))
    for _ in range(15):
        assert not cafe.isTaskComplete()

    def highest_cost_near(x: float, y: float, radius: float = 0.25) -> int:
        grid = cafe.getGlobalCostmap()
        meta = grid.metadata
        assert len(grid.data) == meta.size_x * meta.size_y
        costs = np.frombuffer(grid.data, dtype=np.uint8).reshape(meta.size_y, meta.size_x)
        i0, j0 = (
            math.floor((value - radius - origin) / meta.resolution)
            for value, origin in ((x, meta.origin.position.x), (y, meta.origin.position.y))
        )
        cells = round(2 * radius / meta.resolution)
        return int(costs[j0 : j0 + cells, i0 : i0 + cells].max())

    assert highest_cost_near(1.0, 1.2) >= 253  # the lidar marked the box
    cafe.clearAllCostmaps()
    assert highest_cost_near(1.0, 1.2) >= 253  # a clear forgets only what the lidar no longer sees
    sim.data.mocap_pos[box.mocapid[0]] = [50.0, 50.0, 0.25]  # carried far out of the cafe
    mujoco.mj_forward(sim.model, sim.data)
    for _ in range(3):
        cafe.isTaskComplete()  # 0.3 s: a scan that no longer sees it
    cafe.clearAllCostmaps()
    assert highest_cost_near(1.0, 1.2) == 0
    cafe.clearLocalCostmap()
    cafe.clearGlobalCostmap()
    wait(cafe, 30.0)
    assert cafe.getResult() is TaskResult.SUCCEEDED
    local = cafe.getLocalCostmap()
    assert local.header.frame_id == "map" and local.metadata.resolution == pytest.approx(0.05)
    assert local.metadata.size_x == local.metadata.size_y == 60
    assert not isinstance(local, OccupancyGrid)


def test_get_path_leaves_the_running_task_alone(cafe: BasicNavigator) -> None:
    cafe.goToPose(goal(cafe, *TABLE_1))
    for _ in range(10):
        assert not cafe.isTaskComplete()
    path = cafe.getPath(None, goal(cafe, 0.0, -5.0))
    assert path is not None and path.header.frame_id == "map"
    first, last = to_pose2d(path.poses[0]), to_pose2d(path.poses[-1])
    assert distance(first, cafe.robot_pose()) < 0.1
    assert distance(last, Pose2D(x=0.0, y=-5.0)) < 0.1
    assert cafe.getPath(None, goal(cafe, -2.0, -0.6)) is None  # inside table 1
    through = cafe.getPathThroughPoses(
        pose_stamped(0.0, 0.0), [goal(cafe, 0.0, -2.0), goal(cafe, 1.0, -2.5)], use_start=True
    )
    assert through is not None
    assert distance(to_pose2d(through.poses[0]), Pose2D(x=0.0, y=0.0)) < 0.1
    smoothed = cafe.smoothPath(through)
    assert smoothed is not None and len(smoothed.poses) == len(through.poses)
    assert cafe.smoothPath(through, smoother_id="constrained_smoother") is None
    # The navigation goes on: same task, same feedback type, and it arrives.
    assert isinstance(cafe.getFeedback(), NavigateToPose.Feedback)
    wait(cafe, 30.0)
    assert cafe.getResult() is TaskResult.SUCCEEDED
    assert distance(cafe.robot_pose(), Pose2D(x=TABLE_1[0], y=TABLE_1[1])) <= 0.25


def test_planning_and_smoothing_failures_are_the_task_error(cafe: BasicNavigator) -> None:
    # As Nav2 Kilted's client: each request clears the error, a failure sets the server's.
    table = goal(cafe, -2.0, -0.6)  # inside table 1
    assert cafe.getPath(None, table) is None
    code, message = cafe.getTaskError()
    assert code == ComputePathToPoseError.GOAL_OCCUPIED and "in an obstacle" in message
    path = cafe.getPath(None, goal(cafe, 1.0, -1.0))
    assert path is not None and cafe.getTaskError() == (0, "")
    assert cafe.getPath(None, goal(cafe, 1.0, -1.0), planner_id="NavFn") is None
    code, message = cafe.getTaskError()
    assert code == ComputePathToPoseError.INVALID_PLANNER and "'NavFn'" in message
    assert cafe.getPathThroughPoses(None, []) is None
    assert cafe.getTaskError()[0] == ComputePathThroughPosesError.NO_VIAPOINTS_GIVEN
    assert cafe.getPathThroughPoses(None, [goal(cafe, 0.0, -2.0), table]) is None
    assert cafe.getTaskError()[0] == ComputePathThroughPosesError.GOAL_OCCUPIED
    odom = goal(cafe, 1.0, -1.0)
    odom.header.frame_id = "odom"
    assert cafe.getPathThroughPoses(None, [odom]) is None  # refused before the planner
    assert cafe.getTaskError()[0] == ComputePathThroughPosesError.UNKNOWN
    assert cafe.smoothPath(path, smoother_id="constrained_smoother") is None
    assert cafe.getTaskError()[0] == SmoothPathError.INVALID_SMOOTHER
    assert cafe.smoothPath(Path(header=path.header)) is None
    assert cafe.getTaskError() == (SmoothPathError.INVALID_PATH, "the path has no poses")
    assert cafe.smoothPath(path) is not None and cafe.getTaskError() == (0, "")
    # A request that fails while a task runs: the task's own failure, when it comes, is newer.
    assert cafe.goToPose(table) is RunningTask.NAVIGATE_TO_POSE
    assert cafe.getPath(None, goal(cafe, 1.0, -1.0), planner_id="NavFn") is None
    assert cafe.getTaskError()[0] == ComputePathToPoseError.INVALID_PLANNER
    wait(cafe, 2.0)
    assert cafe.getResult() is TaskResult.FAILED
    assert cafe.getTaskError()[0] == ComputePathToPoseError.GOAL_OCCUPIED  # the navigation's


def test_follow_path_tracks_a_planned_path(cafe: BasicNavigator) -> None:
    path = cafe.getPath(None, goal(cafe, 1.0, -1.0))
    assert path is not None
    assert cafe.followPath(path) is RunningTask.FOLLOW_PATH
    wait(cafe, 20.0)
    assert cafe.getResult() is TaskResult.SUCCEEDED
    assert distance(cafe.robot_pose(), Pose2D(x=1.0, y=-1.0)) <= 0.25
    assert cafe.followPath(path, controller_id="MPPI") is None
    assert cafe.getTaskError()[0] == FollowPathError.INVALID_CONTROLLER


def test_rejected_goals_end_at_once_and_fail() -> None:
    navigator = BasicNavigator(world="cafe", seed=3)
    try:
        assert navigator.isTaskComplete()  # no task: done (Nav2 Kilted would say False)
        assert navigator.getResult() is TaskResult.UNKNOWN
        navigator.cancelTask()
        assert navigator.getTaskError() == (0, "Cancel task failed, goal handle is None")

        navigator.goToPose(goal(navigator, 1.0, 1.0))
        assert not navigator.isTaskComplete()
        odom_goal = goal(navigator, 1.0, 0.0)
        odom_goal.header.frame_id = "odom"
        assert navigator.goToPose(odom_goal) is None
        start = sim_time(navigator)
        polls = 0
        while not navigator.isTaskComplete():  # the Nav2 pitfall: this loop must end
            polls += 1
        assert polls == 0 and sim_time(navigator) == start
        assert navigator.getResult() is TaskResult.FAILED
        code, message = navigator.getTaskError()
        assert code == NavigateToPoseError.UNKNOWN and "'odom'" in message
        assert navigator.getFeedback() is None
        navigator.server.sim.step_for(0.3)  # the task that was running was canceled
        assert abs(navigator.server.base.body_velocity()[0]) < 0.01

        zero = goal(navigator, 1.0, 0.0)
        zero.pose.orientation = Quaternion(x=0.0, y=0.0, z=0.0, w=0.0)
        assert navigator.goToPose(zero) is None
        assert navigator.goThroughPoses([]) is None
        assert navigator.getTaskError()[0] == NavigateThroughPosesError.UNKNOWN
        assert navigator.goToPose(goal(navigator, 1.0, 0.0), behavior_tree="my_bt.xml") is None
        assert navigator.getTaskError()[0] == NavigateToPoseError.FAILED_TO_LOAD_BEHAVIOR_TREE
        with pytest.raises(TypeError, match="PoseStamped"):
            navigator.goToPose(Pose2D(x=1.0, y=0.0))  # type: ignore[arg-type]

        # A goal the server accepts but cannot reach fails with Nav2's planner code.
        assert navigator.goToPose(goal(navigator, -2.0, -0.6)) is RunningTask.NAVIGATE_TO_POSE
        wait(navigator, 2.0)
        assert navigator.getResult() is TaskResult.FAILED
        assert navigator.getTaskError()[0] == ComputePathToPoseError.GOAL_OCCUPIED
    finally:
        navigator.destroy_node()


def test_assisted_teleop_stops_short_of_a_bench() -> None:
    # Facing east, 0.7 m from the cafe's east bench (its west face at x = 3.1).
    navigator = BasicNavigator(world="cafe", start=Pose2D(x=2.3, y=-1.0, yaw=0.0))
    try:
        contacts = ContactWatch(navigator.server.sim, "tb3/base_link")
        twist = Twist()
        twist.linear.x = 0.2
        navigator.publishTeleop(twist)
        assert navigator.assistedTeleop(time_allowance=0) is RunningTask.ASSISTED_TELEOP
        for _ in range(80):
            assert not navigator.isTaskComplete()
        pose = navigator.robot_pose()
        assert 2.8 < pose.x < 3.1 - 0.105  # within 0.3 m of the bench, not touching it
        assert abs(navigator.server.base.body_velocity()[0]) < 0.02
        assert not contacts.touched
        feedback = navigator.getFeedback()
        assert feedback is not None and seconds(feedback.current_teleop_duration) > 7.0  # type: ignore[union-attr]
        navigator.preemptTeleop()
        wait(navigator, 1.0)
        assert navigator.getResult() is TaskResult.SUCCEEDED
    finally:
        navigator.destroy_node()


def test_change_map_keeps_a_free_pose_and_sim_time() -> None:
    navigator = BasicNavigator(world="farm")
    try:
        assert navigator.changeMap("cafe")  # the farm's spawn is off the cafe's floor
        assert navigator.world.name == "cafe"
        assert distance(navigator.robot_pose(), Pose2D(x=0.0, y=0.0)) < 0.01
        navigator.setInitialPose(pose_stamped(1.0, 1.0, 0.5))
        navigator.spin(0.5)
        for _ in range(3):
            assert not navigator.isTaskComplete()
        before = sim_time(navigator)
        here = navigator.robot_pose()
        assert navigator.changeMap("town")  # free there: the robot stays, the spin ends
        assert navigator.getResult() is TaskResult.CANCELED
        assert distance(navigator.robot_pose(), here) < 0.01
        assert abs(navigator.robot_pose().yaw - here.yaw) < 0.01
        assert sim_time(navigator) == pytest.approx(before)
        assert not navigator.changeMap("/nowhere/map.yaml")
        assert navigator.getTaskError()[0] == LoadMapResult.RESULT_MAP_DOES_NOT_EXIST
        assert navigator.world.name == "town"
        navigator.goToPose(goal(navigator, 2.0, 0.0))
        wait(navigator, 20.0)
        assert navigator.getResult() is TaskResult.SUCCEEDED
        assert sim_time(navigator) > before
    finally:
        navigator.destroy_node()


def test_construction_defaults_clock_and_errors() -> None:
    with pytest.raises(WorldError, match="unknown world 'atlantis'"):
        BasicNavigator(world="atlantis")
    with pytest.raises(NavigatorSetupError, match="unknown robot 'turtlebot9'"):
        BasicNavigator(robot="turtlebot9")
    with pytest.raises(NavigatorSetupError, match="robot 'panda' does not drive"):
        BasicNavigator(robot="panda")
    with pytest.raises(NavigatorSetupError, match="table_1"):
        BasicNavigator(world="cafe", start=Pose2D(x=-2.0, y=-0.6))
    navigator = BasicNavigator("commander", "robot1")
    try:
        assert navigator.get_fully_qualified_name() == "/robot1/commander"
        assert navigator.world.name == "cafe"
        clock = navigator.get_clock()
        assert clock.clock_type is ClockType.ROS_TIME
        assert clock.now().nanoseconds == 0
        navigator.waitUntilNav2Active()
        navigator.lifecycleStartup()
        navigator._spin_once(None)
        assert clock.now().nanoseconds == 100_000_000
        with pytest.raises(NavigatorSetupError, match="not free"):
            navigator.setInitialPose(pose_stamped(-2.0, -0.6))
    finally:
        navigator.destroyNode()
    with pytest.raises(Exception, match="destroyed"):
        navigator.goToPose(pose_stamped(1.0, 0.0))


@pytest.mark.parametrize("flip_at", [0.0, 0.035, 0.05, 0.2, 0.455])
def test_a_poll_skips_only_checks_that_cannot_change(cafe: BasicNavigator, flip_at: float) -> None:
    """Stepping from callback to callback stops at the same step as checking every slice: the
    end of the first 10 ms slice after the callback that made the condition true."""
    sim = cafe._rig.sim
    ended: list[float] = []
    stops = []
    for skipping in (True, False):
        ended.clear()
        start = sim.step_count
        handle = sim.every(10.0, ended.append, name="flip", first_call=sim.time + flip_at)
        cafe._advance(1.0, lambda: bool(ended), changes_in_callbacks=skipping)
        handle.cancel()
        stops.append(sim.step_count - start)
    slice_steps = round(0.01 / sim.physics_dt)
    flip_step = round(flip_at / sim.physics_dt)
    assert stops[0] == stops[1] == (flip_step // slice_steps + 1) * slice_steps


def test_a_poll_whose_condition_already_holds_stops_after_one_slice(cafe: BasicNavigator) -> None:
    """A condition true before any step (a goal that had ended) stops the poll at the end of
    the first slice, skipping or not: no callback has to run first."""
    sim = cafe._rig.sim
    cafe._advance(0.003, None)  # off the callbacks' steps: the next one is a slice or more away
    slice_steps = round(0.01 / sim.physics_dt)
    stops = []
    for skipping in (True, False):
        start = sim.step_count
        cafe._advance(1.0, lambda: True, changes_in_callbacks=skipping)
        stops.append(sim.step_count - start)
    assert stops == [slice_steps, slice_steps]
