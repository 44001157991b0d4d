"""BasicNavigator as Nav2 Rolling has it: rejections, the newer servers' calls, plugged-in action
servers, the task-error API and attributes, tracking errors, waypoint statuses, elapsed times,
region clearing of the costmaps and ``disable_collision_checks`` (real physics, sim time)."""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from typing import Any

import mujoco
import numpy as np
import pytest
from navigation_rig import ContactWatch

from baobab.nav import BasicNavigator, RunningTask, TaskResult
from baobab.nav.feedback import path_tracking
from baobab.nav.interfaces import FEEDBACK_KEY, FEEDBACK_QUEUE_KEY, RESULT_KEY
from baobab.nav.layered_costmap import LayeredCostmap
from baobab.nav.msgs import pose_stamped
from baobab.nav.path import Path
from baobab.nav.ros.nav2_msgs import action
from baobab.nav.ros.nav2_msgs.msg import Route, WaypointStatus
from baobab.nav.ros.nav2_simple_commander.costmap_2d import PyCostmap2D
from baobab.nav.rostime import Duration, DurationMsg
from baobab.sim.builder import movable_slot_name
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus
from baobab.sim.world import Floor, Pose2D, World


def seconds(msg: DurationMsg) -> float:
    return Duration.from_msg(msg).nanoseconds / 1e9


def sim_time(navigator: BasicNavigator) -> float:
    return navigator.get_clock().now().nanoseconds / 1e9


def wait(navigator: BasicNavigator, limit: float, task: object = RunningTask.NONE) -> None:
    start = sim_time(navigator)
    while not navigator.isTaskComplete(task):  # type: ignore[arg-type]
        assert sim_time(navigator) - start < limit, "task still running"


@pytest.fixture
def cafe() -> Iterator[BasicNavigator]:
    navigator = BasicNavigator(world="cafe")
    yield navigator
    navigator.destroy_node()


# --- rejections and the servers baobab does not run yet -------------------------------------


def test_a_rejected_send_returns_none_and_sets_the_task_error(cafe: BasicNavigator) -> None:
    odom_goal = pose_stamped(1.0, 0.0, 0.0, frame_id="odom")
    task = cafe.goToPose(odom_goal)
    assert task is None and not task
    assert cafe.goal_handle is not None and not cafe.goal_handle.accepted
    assert cafe.result_future is None
    code, message = cafe.getTaskError()
    assert code == action.NavigateToPose.Result.UNKNOWN and "'odom'" in message
    assert (cafe.last_action_error_code, cafe.last_action_error_msg) == (code, message)
    assert cafe.isTaskComplete(task) and cafe.getResult() is TaskResult.FAILED
    assert cafe.spin(spin_dist=0.3) is RunningTask.SPIN and cafe.getTaskError() == (0, "")


NEWER_CALLS: dict[str, tuple[Callable[[BasicNavigator], object], int]] = {
    "followGpsWaypoints": (lambda n: n.followGpsWaypoints([]), 600),
    "getAndTrackRoute": (lambda n: n.getAndTrackRoute(0, 3), 400),
}


@pytest.mark.parametrize("name", NEWER_CALLS)
def test_calls_for_absent_servers_fail_cleanly(
    cafe: BasicNavigator, name: str, capsys: pytest.CaptureFixture[str]
) -> None:
    call, unknown = NEWER_CALLS[name]
    before = sim_time(cafe)
    assert call(cafe) is None
    code, message = cafe.getTaskError()
    assert code == unknown and "action server" in message and "not available" in message
    assert cafe.isTaskComplete() and cafe.isTaskComplete(RunningTask.COMPUTE_AND_TRACK_ROUTE)
    assert sim_time(cafe) == before  # nothing waited
    assert "not available" in capsys.readouterr().err


def test_get_route_and_the_collision_monitor_toggle_without_servers(
    cafe: BasicNavigator, capsys: pytest.CaptureFixture[str]
) -> None:
    assert cafe.getRoute(pose_stamped(0.0, 0.0), pose_stamped(1.0, 0.0)) is None
    assert cafe.getTaskError()[0] == action.ComputeRoute.Result.UNKNOWN
    assert cafe.toggleCollisionMonitor(False) is None
    assert "collision_monitor/toggle" in capsys.readouterr().err
    with pytest.raises(TypeError, match="both"):
        cafe.getRoute(0, pose_stamped(1.0, 0.0))


class ScriptedServer:
    """An action server that works ``duration`` s of sim time, then succeeds."""

    def __init__(
        self,
        navigator: BasicNavigator,
        feedback: Callable[[float], Any],
        result: Any,
        duration: float,
        *,
        queue: bool = False,
    ) -> None:
        self.sim = navigator.server.sim
        self.feedback, self.result, self.duration, self.queue = feedback, result, duration, queue
        self.goals: list[Any] = []

    def send_goal(self, goal: Any) -> TaskHandle:
        self.goals.append(goal)
        handle = TaskHandle("scripted", lambda h: h.finish(TaskOutcome(TaskStatus.CANCELED)))
        start = self.sim.time

        def tick(now: float) -> None:
            if handle.outcome is not None:
                timer.cancel()
                return
            message = self.feedback(now - start)
            handle.feedback[FEEDBACK_KEY] = message
            if self.queue:
                handle.feedback.setdefault(FEEDBACK_QUEUE_KEY, []).append(message)
            if now - start >= self.duration - 1e-9:
                handle.feedback[RESULT_KEY] = self.result
                handle.finish(TaskOutcome(TaskStatus.SUCCEEDED))
                timer.cancel()

        timer = self.sim.every(0.1, tick, name="scripted server")
        return handle


def test_a_plugged_in_docking_server_serves_the_docking_calls(cafe: BasicNavigator) -> None:
    docked = action.DockRobot.Result(num_retries=1)
    server = ScriptedServer(
        cafe,
        lambda t: action.DockRobot.Feedback(state=3, docking_time=Duration(seconds=t).to_msg()),
        docked,
        1.0,
    )
    cafe.server.action_servers["dock_robot"] = server
    assert cafe.dockRobotByID("home", nav_to_dock=False) is RunningTask.DOCK_ROBOT
    goal = server.goals[-1]
    assert (goal.use_dock_id, goal.dock_id, goal.navigate_to_staging_pose) == (True, "home", False)
    assert not cafe.isTaskComplete()
    feedback = cafe.getFeedback()
    assert isinstance(feedback, action.DockRobot.Feedback) and feedback.state == 3
    wait(cafe, 2.0)
    assert cafe.getResult() is TaskResult.SUCCEEDED
    assert cafe.result_future is not None
    response = cafe.result_future.result()
    assert response is not None and response.result is docked and response.status == 4
    assert cafe.dockRobotByPose(pose_stamped(1.0, 2.0), "charger") is RunningTask.DOCK_ROBOT
    goal = server.goals[-1]
    assert (goal.use_dock_id, goal.dock_type, goal.dock_pose.pose.position.y) == (
        False,
        "charger",
        2.0,
    )
    cafe.cancelTask()
    assert cafe.getResult() is TaskResult.CANCELED


def test_route_tracking_runs_beside_the_task_and_its_feedback_queues(cafe: BasicNavigator) -> None:
    def progress(t: float) -> Any:
        node = round(t * 10)
        return action.ComputeAndTrackRoute.Feedback(
            last_node_id=node, next_node_id=node + 1, rerouted=node == 0
        )

    route_server = ScriptedServer(
        cafe, progress, action.ComputeAndTrackRoute.Result(), 0.5, queue=True
    )
    cafe.server.action_servers["compute_and_track_route"] = route_server
    planned = action.ComputeRoute.Result(route=Route(route_cost=4.5))
    cafe.server.action_servers["compute_route"] = ScriptedServer(cafe, lambda t: None, planned, 0.2)
    path, route = cafe.getRoute(3, 7)  # type: ignore[misc]
    assert route.route_cost == 4.5 and path is planned.path
    task = cafe.getAndTrackRoute(pose_stamped(0.0, 0.0), pose_stamped(1.0, 0.0), use_start=True)
    assert task is RunningTask.COMPUTE_AND_TRACK_ROUTE
    goal = route_server.goals[-1]
    assert (goal.use_poses, goal.use_start, goal.goal.pose.position.x) == (True, True, 1.0)
    assert cafe.spin(0.5) is RunningTask.SPIN  # the tracked task, beside the route
    seen: list[int] = []
    while not cafe.isTaskComplete(task):
        while (feedback := cafe.getFeedback(task)) is not None:
            seen.append(feedback.last_node_id)
    while (feedback := cafe.getFeedback(task)) is not None:
        seen.append(feedback.last_node_id)
    assert seen == [0, 1, 2, 3, 4, 5] and cafe.route_feedback == []
    assert cafe.route_result_future is not None and cafe.route_result_future.done()
    assert not cafe.isTaskComplete()  # the spin goes on
    cafe.cancelTask()
    assert cafe.getResult() is TaskResult.CANCELED


def test_a_plugged_in_collision_monitor_is_toggled(cafe: BasicNavigator) -> None:
    calls: list[bool] = []

    def toggle(enable: bool) -> tuple[bool, str]:
        calls.append(enable)
        return True, ""

    cafe.server.services["collision_monitor/toggle"] = toggle
    cafe.toggleCollisionMonitor(False)
    cafe.toggleCollisionMonitor(True)
    assert calls == [False, True]


# --- task error, state and attributes ---------------------------------------------------------


def test_task_error_api_and_attributes(cafe: BasicNavigator) -> None:
    cafe.setTaskError(42, "custom")
    assert cafe.getTaskError() == (42, "custom") == cafe.getLastError()
    cafe.last_action_error_code = 7
    assert cafe.getTaskError() == (7, "custom")
    cafe.last_action_error_msg = "changed"
    assert cafe.getTaskError() == (7, "changed")
    cafe.clearTaskError()
    assert cafe.getTaskError() == (0, "")
    assert cafe.spin(1.0) is RunningTask.SPIN
    assert cafe.goal_handle is not None and cafe.goal_handle.accepted
    assert cafe.goal_handle.status == 2 and cafe.status is None
    for _ in range(3):
        assert not cafe.isTaskComplete()
    assert isinstance(cafe.feedback, action.Spin.Feedback)
    cafe.clearPreviousState()
    assert cafe.getFeedback() is None and cafe.feedback is None  # until the task reports again
    assert not cafe.isTaskComplete()
    assert isinstance(cafe.getFeedback(), action.Spin.Feedback)
    wait(cafe, 10.0)
    assert cafe.status == 4 and cafe.goal_handle.status == 4
    first_id = bytes(cafe.goal_handle.goal_id.uuid)
    cafe.spin(0.1)
    assert bytes(cafe.goal_handle.goal_id.uuid) != first_id


# --- feedback and results ---------------------------------------------------------------------


def test_path_tracking_errors_by_hand() -> None:
    straight = Path(np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]))
    left = path_tracking(straight, 0, 0.5, 0.2, 0.1)  # left of the path, turned left
    assert (left.position_error, left.heading_error, left.index) == pytest.approx((0.2, -0.1, 0))
    right = path_tracking(straight, 2, 1.5, -0.3, -0.2)  # right of it, turned right
    assert (right.position_error, right.heading_error, right.index) == pytest.approx((-0.3, 0.2, 1))
    diagonal = Path(np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]]))
    off = path_tracking(diagonal, 0, 1.0, 0.0, 0.0)  # below the diagonal: right of it
    assert off.position_error == pytest.approx(-math.sqrt(0.5))
    assert off.heading_error == pytest.approx(math.pi / 4)
    single = Path(np.array([[1.0, 1.0, math.pi / 2]]))
    alone = path_tracking(single, 0, 0.5, 1.2, math.pi / 2)  # west of a north-facing pose
    assert (alone.position_error, alone.heading_error) == pytest.approx((0.5, 0.0))


def test_navigation_feedback_carries_tracking_errors_and_follow_path_its_tracking_feedback(
    cafe: BasicNavigator,
) -> None:
    assert cafe.goToPose(pose_stamped(1.0, -1.5, 0.0)) is RunningTask.NAVIGATE_TO_POSE
    errors: list[tuple[float, float]] = []
    while not cafe.isTaskComplete():
        feedback = cafe.getFeedback()
        if isinstance(feedback, action.NavigateToPose.Feedback):
            errors.append((feedback.position_tracking_error, feedback.heading_tracking_error))
    assert cafe.getResult() is TaskResult.SUCCEEDED
    positions = [abs(p) for p, _ in errors]
    assert max(positions) < 0.3 and any(p > 0.005 for p in positions)
    assert all(abs(h) <= math.pi for _, h in errors) and any(abs(h) > 0.01 for _, h in errors)

    path = cafe.getPath(None, pose_stamped(-0.5, 1.0, 0.0))
    assert path is not None and cafe.followPath(path) is RunningTask.FOLLOW_PATH
    end = path.poses[-1].pose.position
    indices: list[int] = []
    while not cafe.isTaskComplete():
        feedback = cafe.getFeedback()
        assert isinstance(feedback, action.FollowPath.Feedback)
        tracking = feedback.tracking_feedback
        if tracking.header.frame_id != "map":
            continue  # before the controller's first cycle
        robot = cafe.robot_pose()
        assert tracking.distance_to_goal == pytest.approx(
            math.hypot(end.x - robot.x, end.y - robot.y), abs=0.03
        )
        assert tracking.remaining_path_length == pytest.approx(feedback.distance_to_goal)
        assert tracking.remaining_path_length >= tracking.distance_to_goal - 0.03
        assert tracking.robot_pose.pose.position.x == pytest.approx(robot.x, abs=0.02)
        assert tracking.speed == pytest.approx(feedback.speed)
        indices.append(tracking.current_path_index)
    assert cafe.getResult() is TaskResult.SUCCEEDED
    assert indices == sorted(indices) and indices[-1] > indices[0] + 10


def test_waypoint_statuses_of_navigation_through_poses(cafe: BasicNavigator) -> None:
    poses = [pose_stamped(1.0, -1.0), pose_stamped(1.0, -2.0), pose_stamped(0.0, -2.5)]
    assert cafe.goThroughPoses(poses) is RunningTask.NAVIGATE_THROUGH_POSES
    seen: list[tuple[int, ...]] = []
    while not cafe.isTaskComplete():
        feedback = cafe.getFeedback()
        if isinstance(feedback, action.NavigateThroughPoses.Feedback):
            statuses = tuple(s.waypoint_status for s in feedback.waypoint_statuses)
            if not seen or seen[-1] != statuses:
                seen.append(statuses)
    pending, done = WaypointStatus.PENDING, WaypointStatus.COMPLETED
    assert seen == [(pending,) * 3, (done, pending, pending), (done, done, pending)]
    assert cafe.result_future is not None
    response = cafe.result_future.result()
    assert response is not None
    final = response.result.waypoint_statuses
    assert [s.waypoint_status for s in final] == [done] * 3
    assert [s.waypoint_index for s in final] == [0, 1, 2]
    assert final[2].waypoint_pose.pose.position.y == -2.5

    assert cafe.goThroughPoses(poses[::-1]) is RunningTask.NAVIGATE_THROUGH_POSES
    for _ in range(5):
        cafe.isTaskComplete()
    cafe.cancelTask()
    assert cafe.result_future is not None
    response = cafe.result_future.result()
    assert response is not None
    # The robot stood on the first pose (passed at once); the others failed with the cancel.
    failed = WaypointStatus.FAILED
    assert [s.waypoint_status for s in response.result.waypoint_statuses] == [done, failed, failed]


def test_behaviour_results_carry_their_total_elapsed_time(cafe: BasicNavigator) -> None:
    start = sim_time(cafe)
    assert cafe.spin(spin_dist=1.0) is RunningTask.SPIN
    wait(cafe, 10.0)
    took = sim_time(cafe) - start
    assert cafe.result_future is not None
    response = cafe.result_future.result()
    assert response is not None and isinstance(response.result, action.Spin.Result)
    assert seconds(response.result.total_elapsed_time) == pytest.approx(took, abs=0.11)
    assert took > 1.0
    assert cafe.assistedTeleop(time_allowance=10) is RunningTask.ASSISTED_TELEOP
    for _ in range(10):
        cafe.isTaskComplete()
    cafe.cancelTask()
    assert cafe.result_future is not None
    response = cafe.result_future.result()
    assert response is not None and response.status == 5
    assert seconds(response.result.total_elapsed_time) == pytest.approx(1.0, abs=0.11)


def test_disable_collision_checks_lets_a_back_up_run_into_the_wall() -> None:
    # Facing south 0.55 m from the north wall: backing up 0.5 m would hit it.
    start = Pose2D(x=0.0, y=2.45, yaw=-math.pi / 2)
    for disable, code in ((False, 714), (True, 711)):
        navigator = BasicNavigator(world="walls", start=start)
        try:
            contacts = ContactWatch(navigator.server.sim, "tb3/base_link")
            navigator.backup(0.5, 0.15, 8, disable_collision_checks=disable)
            wait(navigator, 9.0)
            assert navigator.getTaskError()[0] == code  # COLLISION_AHEAD, else TIMEOUT
            assert bool(contacts.touched) is disable
        finally:
            navigator.destroy_node()


# --- clearing regions of the costmaps ---------------------------------------------------------


def open_floor() -> World:
    return World(
        name="open", floor=Floor(size=(20.0, 20.0)), spawns={"default": Pose2D(x=0.0, y=0.0)}
    )


@pytest.mark.parametrize("inside", [True, False])
def test_region_clearing_follows_nav2s_cell_rule(inside: bool) -> None:
    costmap = LayeredCostmap.global_costmap(open_floor())
    grid = costmap.obstacle_layer.grid
    grid.origin_x, grid.origin_y = 0.0, 0.0  # cells of 0.05 m from (0, 0)
    grid.data[:12, :12] = 254
    # The 0.2 m square centred on (0.26, 0.26) runs from 0.16 to 0.36 m: Nav2 truncates
    # 0.16 / 0.05 = 3.2 and 0.36 / 0.05 = 7.2 to cells 3 and 7; the cells strictly between,
    # 4 to 6 on both axes, are the inside.
    costmap.clear_region(0.26, 0.26, 0.2, inside=inside)
    kept = {(int(x), int(y)) for y, x in zip(*np.nonzero(grid.data[:12, :12]), strict=True)}
    everything = {(x, y) for x in range(12) for y in range(12)}
    inner = {(x, y) for x in (4, 5, 6) for y in (4, 5, 6)}
    assert kept == (everything - inner if inside else inner)


def test_navigator_clears_costmap_regions_as_nav2() -> None:
    navigator = BasicNavigator(world="walls", start=Pose2D(x=0.5, y=1.5, yaw=0.0))
    try:
        sim = navigator.server.sim
        near, far = (1.1, 1.5), (1.7, 2.4)  # 0.6 m ahead; outside a 1.6 m square around
        for slot, (x, y) in enumerate((near, far)):
            body = sim.model.body(movable_slot_name(slot))
            sim.data.mocap_pos[body.mocapid[0]] = [x, y, 0.25]
        mujoco.mj_forward(sim.model, sim.data)

        def seen(clear: Callable[[], None]) -> tuple[bool, bool]:
            """Let the lidar mark both boxes, clear, then say which box is still lethal."""
            sim.step_for(0.5)
            costmap = PyCostmap2D(navigator.getLocalCostmap())
            assert lethal_near(costmap, *near) and lethal_near(costmap, *far)
            clear()
            costmap = PyCostmap2D(navigator.getLocalCostmap())
            return lethal_near(costmap, *near), lethal_near(costmap, *far)

        assert seen(lambda: navigator.clearCostmapAroundRobot(1.6)) == (False, True)
        assert seen(lambda: navigator.clearCostmapExceptRegion(1.6)) == (True, False)
        assert seen(lambda: navigator.clearLocalCostmapAroundPose(pose_stamped(*far), 0.6)) == (
            True,
            False,
        )
        assert seen(lambda: navigator.clearCostmapAroundPose(pose_stamped(*near), 0.6)) == (
            False,
            True,
        )
        odom = pose_stamped(*near, frame_id="odom")
        assert seen(lambda: navigator.clearLocalCostmapAroundPose(odom, 0.6)) == (True, True)
        sim.step_for(1.0)  # the global costmap marks at 1 Hz
        global_map = PyCostmap2D(navigator.getGlobalCostmap())
        assert lethal_near(global_map, *near) and lethal_near(global_map, *far)
        navigator.clearGlobalCostmapAroundPose(pose_stamped(*far), 0.6)
        global_map = PyCostmap2D(navigator.getGlobalCostmap())
        assert lethal_near(global_map, *near) and not lethal_near(global_map, *far)
    finally:
        navigator.destroy_node()


def lethal_near(costmap: PyCostmap2D, x: float, y: float, reach: float = 0.2) -> bool:
    """Whether a lethal cell lies within ``reach`` (m) of ``(x, y)``."""
    step = costmap.getResolution()
    offsets = np.arange(-reach, reach + 1e-9, step)
    for dx in offsets:
        for dy in offsets:
            mx, my = costmap.worldToMapValidated(x + dx, y + dy)
            if mx is not None and costmap.getCostXY(mx, my) == 254:
                return True
    return False
