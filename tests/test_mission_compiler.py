"""The compiler's trees, tick by tick, over fake ports whose task handles the test drives.

Fakes are right here: these are unit tests of tree semantics (memory, retry, sim-time
timeouts, preemption cancelling goals, parallel policies), not of the servers. Each test is a
small tick table: set the clock and the tasks' outcomes, tick, compare statuses.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import py_trees
import pytest

from baobab.behaviours.actions import GoalTaskLeaf
from baobab.behaviours.ports import Capabilities
from baobab.missions.language.compiler import CompiledMission, compile_mission
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D

S, F = py_trees.common.Status.SUCCESS, py_trees.common.Status.FAILURE
RUNNING, INVALID = py_trees.common.Status.RUNNING, py_trees.common.Status.INVALID
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
MOBILE = (
    "mission: m\nworld: walls\nrobot: turtlebot3\n"
    "locations: {a: {x: 0.5, y: 0.5}, b: {x: 2.0, y: 2.0}, c: {x: -2.0, y: -0.5}}\n"
)
ARM = (
    "mission: m\nrobot: panda\n"
    "locations: {above: {position: [0.4, 0.3, 0.7], orientation: [0, 0, 0, 2]}}\n"
)


class FakeClock:
    """Sim time the test sets by hand (s)."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


class FakeServer:
    """Records every request and hands out handles that only the test finishes."""

    def __init__(self) -> None:
        self.calls: list[tuple[str, tuple[object, ...]]] = []
        self.handles: list[TaskHandle] = []

    def _task(self, name: str, *args: object) -> TaskHandle:
        self.calls.append((name, args))
        handle = TaskHandle(name, on_cancel=lambda _handle: None)
        self.handles.append(handle)
        return handle

    def finish(self, index: int, status: TaskStatus, code: int = 0) -> None:
        self.handles[index].finish(TaskOutcome(status, code, "", "X" if code else "NONE"))


class FakeNavigation(FakeServer):
    def __init__(self) -> None:
        super().__init__()
        self.pose = Pose2D(x=0.0, y=0.0, yaw=0.0)

    def navigate_to_pose(self, goal: Pose2D) -> TaskHandle:
        return self._task("navigate_to_pose", goal)

    def navigate_through_poses(self, goals: Sequence[Pose2D]) -> TaskHandle:
        return self._task("navigate_through_poses", list(goals))

    def follow_waypoints(
        self, waypoints: Sequence[Pose2D], wait_at_waypoint: float, stop_on_failure: bool
    ) -> TaskHandle:
        return self._task("follow_waypoints", list(waypoints), wait_at_waypoint, stop_on_failure)

    def follow_path(self, path: Sequence[Pose2D]) -> TaskHandle:
        return self._task("follow_path", list(path))

    def spin(self, target_yaw: float, time_allowance: float) -> TaskHandle:
        return self._task("spin", target_yaw, time_allowance)

    def back_up(self, distance: float, speed: float, time_allowance: float) -> TaskHandle:
        return self._task("back_up", distance, speed, time_allowance)

    def drive_on_heading(self, distance: float, speed: float, time_allowance: float) -> TaskHandle:
        return self._task("drive_on_heading", distance, speed, time_allowance)

    def wait(self, duration: float) -> TaskHandle:
        return self._task("wait", duration)

    def assisted_teleop(self, time_allowance: float) -> TaskHandle:
        return self._task("assisted_teleop", time_allowance)

    def clear_costmaps(self, which: str) -> None:
        self.calls.append(("clear_costmaps", (which,)))

    def robot_pose(self) -> Pose2D:
        return self.pose


class FakeBase(FakeServer):
    def go_to_goal(self, goal: Pose2D) -> TaskHandle:
        return self._task("go_to_goal", goal)

    def bug2(self, goal: Pose2D) -> TaskHandle:
        return self._task("bug2", goal)


class FakeArm(FakeServer):
    def __init__(self) -> None:
        super().__init__()
        self.objects = {"cube": (0.5, -0.1, 0.525)}
        self.tcp = ((0.3, 0.0, 0.6), (1.0, 0.0, 0.0, 0.0))

    def move_to(
        self, position: Sequence[float], orientation_xyzw: Sequence[float], duration: float
    ) -> TaskHandle:
        return self._task("move_to", tuple(position), tuple(orientation_xyzw), duration)

    def gripper(self, command: str) -> TaskHandle:
        return self._task("gripper", command)

    def object_position(self, name: str) -> tuple[float, float, float]:
        return self.objects[name]

    def tcp_pose(self) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        return self.tcp


class Rig:
    """A compiled mission over fake ports."""

    def __init__(self, tmp_path: Path, text: str) -> None:
        path = tmp_path / "mission.yaml"
        path.write_text(HEADER + text)
        self.clock = FakeClock()
        self.nav = FakeNavigation()
        self.base = FakeBase()
        self.arm = FakeArm()
        capabilities = Capabilities(self.clock, self.nav, self.base, self.arm)
        self.compiled: CompiledMission = compile_mission(load_mission(path), capabilities)

    def tick(self, at: float | None = None) -> py_trees.common.Status:
        if at is not None:
            self.clock.now = at
        self.compiled.tree.tick()
        return self.compiled.root.status

    def leaf(self, name: str) -> GoalTaskLeaf:
        (leaf,) = [b for b in self.compiled.goal_leaves() if b.name == name]
        return leaf


def _mobile(tmp_path: Path, tree: str) -> Rig:
    return Rig(tmp_path, MOBILE + "tree:\n" + tree)


def test_sequence_with_memory_resumes_at_the_running_child(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  sequence: [{navigate_to_pose: a}, {navigate_to_pose: b}]\n")
    assert rig.tick() is RUNNING
    assert [call[0] for call in rig.nav.calls] == ["navigate_to_pose"]
    assert rig.nav.calls[0][1][0] == Pose2D(x=0.5, y=0.5, yaw=0.0)
    rig.nav.finish(0, TaskStatus.SUCCEEDED)
    assert rig.tick() is RUNNING
    assert rig.tick() is RUNNING
    assert rig.leaf("navigate_to_pose a").goals_sent == 1  # not re-ticked
    assert len(rig.nav.handles) == 2
    rig.nav.finish(1, TaskStatus.SUCCEEDED)
    assert rig.tick() is S


def test_sequence_without_memory_rechecks_and_preempts(tmp_path: Path) -> None:
    rig = _mobile(
        tmp_path,
        "  sequence:\n    memory: false\n"
        "    children: [{invert: {elapsed: 10}}, {navigate_to_pose: b}]\n",
    )
    table = [(0.0, RUNNING), (5.0, RUNNING), (9.9, RUNNING), (10.0, F)]
    assert [rig.tick(t) for t, _ in table] == [status for _, status in table]
    (handle,) = rig.nav.handles
    assert handle.cancel_requested  # the guard failed: the running goal was canceled
    assert rig.leaf("navigate_to_pose b").status is INVALID


def test_selector_with_memory_resumes_after_a_failed_child(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  selector: [{navigate_to_pose: a}, {navigate_to_pose: b}]\n")
    assert rig.tick() is RUNNING
    rig.nav.finish(0, TaskStatus.FAILED, code=104)
    assert rig.tick() is RUNNING
    assert rig.leaf("navigate_to_pose a").outcome == TaskOutcome(TaskStatus.FAILED, 104, "", "X")
    assert rig.tick() is RUNNING
    assert rig.leaf("navigate_to_pose a").goals_sent == 1
    rig.nav.finish(1, TaskStatus.SUCCEEDED)
    assert rig.tick() is S


def test_selector_without_memory_lets_a_higher_priority_child_preempt(tmp_path: Path) -> None:
    rig = _mobile(
        tmp_path, "  selector:\n    memory: false\n    children: [{elapsed: 5}, {spin: 3.0}]\n"
    )
    assert [rig.tick(t) for t in (0.0, 2.0, 5.0)] == [RUNNING, RUNNING, S]
    assert rig.nav.calls == [("spin", (3.0, 10.0))]
    assert rig.nav.handles[0].cancel_requested


def test_retry_counts_failed_attempts(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  retry: {num_failures: 3, child: {navigate_to_pose: a}}\n")
    statuses = []
    for attempt in range(3):
        statuses.append(rig.tick())  # sends goal number `attempt`
        rig.nav.finish(attempt, TaskStatus.FAILED)
        statuses.append(rig.tick())
    assert statuses == [RUNNING, RUNNING, RUNNING, RUNNING, RUNNING, F]
    assert len(rig.nav.handles) == 3


def test_retry_succeeds_on_a_later_attempt(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  retry: {num_failures: 3, child: {navigate_to_pose: a}}\n")
    rig.tick()
    rig.nav.finish(0, TaskStatus.FAILED)
    assert rig.tick() is RUNNING
    assert rig.tick() is RUNNING
    rig.nav.finish(1, TaskStatus.SUCCEEDED)
    assert rig.tick() is S


def test_timeout_reads_the_sim_clock_and_cancels_the_goal(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  timeout: {duration: 30, child: {navigate_to_pose: a}}\n")
    table = [(100.0, RUNNING), (110.0, RUNNING), (129.99, RUNNING), (130.0, F)]
    assert [rig.tick(t) for t, _ in table] == [status for _, status in table]
    assert rig.nav.handles[0].cancel_requested
    assert rig.compiled.root.feedback_message == "timed out after 30 s"


def test_timeout_keeps_a_result_that_arrives_on_the_deadline_tick(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  timeout: {duration: 30, child: {navigate_to_pose: a}}\n")
    assert rig.tick(0.0) is RUNNING
    rig.nav.finish(0, TaskStatus.SUCCEEDED)
    assert rig.tick(30.0) is S
    assert not rig.nav.handles[0].cancel_requested


def test_wait_counts_sim_seconds_from_activation(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  sequence: [{elapsed: 2}, {wait: 5}]\n")
    table = [(0.0, F), (3.0, RUNNING), (7.99, RUNNING), (8.0, S)]
    assert [rig.tick(t) for t, _ in table] == [status for _, status in table]


def test_repeat_reruns_after_success_and_stops_on_failure(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  repeat: {num_success: 2, child: {drive_on_heading: 0.1}}\n")
    assert rig.tick() is RUNNING
    rig.nav.finish(0, TaskStatus.SUCCEEDED)
    assert rig.tick() is RUNNING
    assert rig.tick() is RUNNING  # second run started
    rig.nav.finish(1, TaskStatus.SUCCEEDED)
    assert rig.tick() is S
    assert rig.nav.calls[0] == ("drive_on_heading", (0.1, 0.025, 10.0))
    forever = _mobile(tmp_path, "  repeat: {num_success: -1, child: {back_up: {}}}\n")
    for index in range(4):
        assert forever.tick() is RUNNING
        forever.nav.finish(index, TaskStatus.SUCCEEDED)
        assert forever.tick() is RUNNING
    forever.tick()
    forever.nav.finish(4, TaskStatus.FAILED)
    assert forever.tick() is F


@pytest.mark.parametrize(
    ("decorator", "outcome", "expected"),
    [
        ("invert", TaskStatus.SUCCEEDED, F),
        ("invert", TaskStatus.FAILED, S),
        ("invert", TaskStatus.CANCELED, S),
        ("force_success", TaskStatus.SUCCEEDED, S),
        ("force_success", TaskStatus.FAILED, S),
        ("force_failure", TaskStatus.SUCCEEDED, F),
        ("force_failure", TaskStatus.FAILED, F),
    ],
)
def test_status_decorators(
    tmp_path: Path, decorator: str, outcome: TaskStatus, expected: py_trees.common.Status
) -> None:
    rig = _mobile(tmp_path, f"  {decorator}: {{go_to_goal: b}}\n")
    assert rig.tick() is RUNNING
    rig.base.finish(0, outcome)
    assert rig.tick() is expected


def test_parallel_success_on_all_waits_for_every_child(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  parallel: [{navigate_to_pose: a}, {bug2: c}]\n")
    assert rig.tick() is RUNNING
    rig.nav.finish(0, TaskStatus.SUCCEEDED)
    assert rig.tick() is RUNNING
    assert rig.leaf("navigate_to_pose a").goals_sent == 1  # synchronised: not re-run
    rig.base.finish(0, TaskStatus.SUCCEEDED)
    assert rig.tick() is S


def test_parallel_success_on_one_stops_and_cancels_the_others(tmp_path: Path) -> None:
    rig = _mobile(
        tmp_path,
        "  parallel:\n    policy: success_on_one\n"
        "    children: [{navigate_to_pose: a}, {assisted_teleop: 20}]\n",
    )
    assert rig.tick() is RUNNING
    rig.nav.finish(1, TaskStatus.SUCCEEDED)
    assert rig.tick() is S
    assert rig.nav.handles[0].cancel_requested
    assert not rig.nav.handles[1].cancel_requested


def test_parallel_failure_of_one_child_cancels_the_running_ones(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  parallel: [{navigate_to_pose: a}, {go_to_goal: b}]\n")
    rig.tick()
    rig.base.finish(0, TaskStatus.FAILED)
    assert rig.tick() is F
    assert rig.nav.handles[0].cancel_requested


def test_halting_the_tree_cancels_the_running_goal_once(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  sequence: [{navigate_to_pose: a}, {navigate_to_pose: b}]\n")
    rig.tick()
    rig.nav.finish(0, TaskStatus.SUCCEEDED)
    rig.tick()
    rig.compiled.root.stop(INVALID)
    first, second = rig.nav.handles
    assert not first.cancel_requested  # already finished: nothing to cancel
    assert second.cancel_requested
    rig.compiled.root.stop(INVALID)  # a second halt is harmless
    assert second.cancel_requested


def test_navigation_leaves_send_their_parameters(tmp_path: Path) -> None:
    rig = _mobile(
        tmp_path,
        "  sequence:\n"
        "    - navigate_through_poses: [a, {x: 1.0, y: 2.0, yaw_deg: 90}]\n"
        "    - follow_waypoints: {waypoints: [b], wait_at_waypoint: 2.0}\n"
        "    - follow_path: [a, b]\n"
        "    - spin: {angle_deg: -90, time_allowance: 5}\n"
        "    - clear_costmaps: global\n"
        "    - is_at: {location: a, tolerance: 0.1}\n",
    )
    for index in range(4):
        rig.tick()
        rig.nav.finish(index, TaskStatus.SUCCEEDED)
    rig.nav.pose = Pose2D(x=0.55, y=0.5, yaw=3.0)
    assert rig.tick() is S
    a, b = Pose2D(x=0.5, y=0.5), Pose2D(x=2.0, y=2.0)
    names = [name for name, _ in rig.nav.calls]
    assert names == [
        "navigate_through_poses",
        "follow_waypoints",
        "follow_path",
        "spin",
        "clear_costmaps",
    ]
    calls = dict(rig.nav.calls)
    through = calls["navigate_through_poses"][0]
    assert isinstance(through, list)
    assert through[0] == a
    assert through[1].yaw == pytest.approx(math.pi / 2)
    assert calls["follow_waypoints"] == ([b], 2.0, None)  # None: the stack's setting
    assert calls["follow_path"] == ([a, b],)
    assert calls["spin"] == (pytest.approx(-math.pi / 2), 5.0)
    assert calls["clear_costmaps"] == ("global",)


def test_is_at_compares_the_robot_pose(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  is_at: {location: b, tolerance: 0.2, yaw_tolerance: 0.1}\n")
    for pose, expected in [
        (Pose2D(x=2.1, y=2.1, yaw=0.05), S),
        (Pose2D(x=2.1, y=2.2, yaw=0.0), F),
        (Pose2D(x=2.0, y=2.0, yaw=0.5), F),
        (Pose2D(x=2.0, y=2.0, yaw=math.tau - 0.05), S),
    ]:
        rig.nav.pose = pose
        assert rig.tick() is expected


def test_arm_moves_resolve_relative_targets_when_they_start(tmp_path: Path) -> None:
    rig = Rig(
        tmp_path,
        ARM + "tree:\n  sequence:\n"
        "    - move_to: {relative_to: cube, offset: [0, 0, 0.1], orientation: [2, 0, 0, 0]}\n"
        "    - gripper: close\n"
        "    - move_to: {relative_to: tcp, offset: [0, 0, 0.15], duration: 1.0}\n"
        "    - move_to: above\n"
        "    - object_at: {object: cube, target: {position: [0.4, 0.3, 0.5]}, tolerance: 0.05}\n",
    )
    rig.arm.objects["cube"] = (0.52, -0.08, 0.525)  # moved after compiling: read at start
    for index in range(4):
        if index == 2:  # the tool moved since compiling: 'relative_to: tcp' reads it at start
            rig.arm.tcp = ((0.52, -0.08, 0.63), (1.0, 0.0, 0.0, 0.0))
        rig.tick()
        rig.arm.finish(index, TaskStatus.SUCCEEDED)
    rig.arm.objects["cube"] = (0.41, 0.31, 0.5)  # placed
    assert rig.tick() is S
    pregrasp, grip, lift, above = (call[1] for call in rig.arm.calls)
    assert pregrasp[0] == pytest.approx((0.52, -0.08, 0.625))
    assert pregrasp[1:] == ((1.0, 0.0, 0.0, 0.0), 2.0)
    assert grip == ("close",)
    assert lift[0] == pytest.approx((0.52, -0.08, 0.78))
    assert lift[1:] == ((1.0, 0.0, 0.0, 0.0), 1.0)
    assert above[0] == pytest.approx((0.4, 0.3, 0.7))
    assert above[1] == pytest.approx((0.0, 0.0, 0.0, 1.0))  # normalised


def test_object_at_reads_the_object_each_tick(tmp_path: Path) -> None:
    rig = Rig(
        tmp_path,
        ARM + "tree:\n  object_at: {object: cube, target: above, tolerance: 0.05}\n",
    )
    table = [((0.4, 0.3, 0.5), F), ((0.42, 0.29, 0.69), S), ((0.4, 0.36, 0.7), F)]
    for position, expected in table:
        rig.arm.objects["cube"] = position
        assert rig.tick() is expected


def test_every_compile_clears_the_blackboard(tmp_path: Path) -> None:
    py_trees.blackboard.Blackboard.set("/leftover", 1)
    _mobile(tmp_path, "  wait: 1\n")
    assert not py_trees.blackboard.Blackboard.exists("/leftover")


def test_a_missing_port_is_a_located_error(tmp_path: Path) -> None:
    path = tmp_path / "mission.yaml"
    path.write_text(HEADER + MOBILE + "tree:\n  sequence: [{wait: 1}, {bug2: a}]\n")
    mission = load_mission(path)
    navigation_only = Capabilities(FakeClock(), navigation=FakeNavigation())
    with pytest.raises(MissionError) as caught:
        compile_mission(mission, navigation_only)
    assert str(caught.value) == (
        f"{path}:7:26: bug2 needs capability 'base_controllers', which this run does not provide"
    )
    detached = compile_mission(mission, navigation_only, require_ports=False)
    detached.tree.tick()
    assert detached.root.status is RUNNING


def test_behaviours_point_back_at_their_lines(tmp_path: Path) -> None:
    rig = _mobile(tmp_path, "  sequence:\n    - wait: 1\n    - navigate_to_pose: a\n")
    path = tmp_path / "mission.yaml"
    where = {b.name: rig.compiled.where(b) for b in rig.compiled.root.iterate()}
    assert where == {
        "wait 1 s": f"{path}:8:7",
        "navigate_to_pose a": f"{path}:9:7",
        "sequence": f"{path}:7:3",
    }


def test_every_composite_states_its_memory(tmp_path: Path) -> None:
    rig = Rig(tmp_path, (Path(__file__).parent / "missions" / "patrol.yaml").read_text()[52:])
    composites = [
        b
        for b in rig.compiled.root.iterate()
        if isinstance(b, py_trees.composites.Sequence | py_trees.composites.Selector)
    ]
    assert {b.memory for b in composites} == {True, False}
