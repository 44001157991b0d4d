"""Nav2's docking server over the sim: staging, lidar detection, approach, charging, undock."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from navigation_rig import ROOM_DOCK, NavRig, dock_room, feedback_states, make_rig

from baobab.nav.docking import DockingParams, staging_pose
from baobab.nav.docking_tasks import DockState
from baobab.nav.errors import DockRobotError, UndockRobotError
from baobab.nav.interfaces import FEEDBACK_KEY, RESULT_KEY
from baobab.sim.docks import Dock
from baobab.sim.tasks import TaskHandle, TaskStatus
from baobab.sim.world import Box, Pose2D

DOCK = ROOM_DOCK
DOCKED = Pose2D(x=DOCK.x, y=DOCK.y, yaw=DOCK.yaw)
PARAMS = DockingParams()
STAGING = staging_pose(DOCKED, PARAMS)


def _near_staging(dx: float = 0.0, dy: float = 0.0, dyaw: float = 0.0) -> Pose2D:
    x, y = DOCK.to_map(PARAMS.staging_x_offset + dx, dy)
    return Pose2D(x=x, y=y, yaw=DOCK.yaw + dyaw)


def _state(handle: TaskHandle) -> int | None:
    feedback = handle.feedback.get(FEEDBACK_KEY)
    return None if feedback is None else int(feedback.state)


def _assert_docked(rig: NavRig) -> None:
    here = rig.pose()
    assert math.hypot(here.x - DOCK.x, here.y - DOCK.y) < PARAMS.docking_threshold + 0.01
    assert abs(math.remainder(here.yaw - DOCK.yaw, math.tau)) < 0.1
    assert rig.server.docking.is_charging()
    assert not {name for name in rig.contacts.touched if not name.startswith("home/")}


@pytest.mark.parametrize(
    "start",
    [_near_staging(), _near_staging(0.15, 0.2, -0.35), _near_staging(-0.2, -0.25, 0.3)],
    ids=["at-staging", "ahead-left", "behind-right"],
)
def test_the_robot_docks_from_near_the_staging_pose(start: Pose2D) -> None:
    rig = make_rig(dock_room(start))
    handle = rig.server.docking.dock_robot("home")
    rig.run(handle, 40.0)
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.SUCCEEDED
    result = handle.feedback[RESULT_KEY]
    assert (result.success, result.error_code, result.num_retries) == (True, 0, 0)
    _assert_docked(rig)


def test_the_robot_navigates_to_staging_then_docks_where_the_lidar_sees_the_dock() -> None:
    # The database believes the dock stands 12 cm and 0.15 rad off: the detector corrects it.
    rig = make_rig(dock_room(Pose2D(x=-1.5, y=-1.0, yaw=0.0)))
    rig.server.docking.database["home"] = Dock(pose=(DOCK.x - 0.1, DOCK.y + 0.07, DOCK.yaw + 0.15))
    handle = rig.server.docking.dock_robot("home")
    states: list[int] = []

    while handle.status is TaskStatus.RUNNING:
        rig.sim.step_for(0.05)
        state = _state(handle)
        if state is not None and (not states or states[-1] != state):
            states.append(state)
        assert rig.sim.time < 90.0
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.SUCCEEDED
    assert states == [
        DockState.NAV_TO_STAGING_POSE,
        DockState.INITIAL_PERCEPTION,
        DockState.CONTROLLING,
        DockState.WAIT_FOR_CHARGE,
    ]
    _assert_docked(rig)
    undock = rig.server.docking.undock_robot()
    rig.run(undock, 30.0)
    assert undock.outcome is not None and undock.outcome.status is TaskStatus.SUCCEEDED
    here = rig.pose()
    assert math.hypot(here.x - STAGING.x, here.y - STAGING.y) < PARAMS.undock_linear_tolerance
    assert not rig.server.docking.is_charging()


def test_a_blocked_approach_fails_to_control_after_the_retries() -> None:
    crate_x, crate_y = DOCK.to_map(-0.42, 0.0)
    crate = Box(name="crate", center=(crate_x, crate_y), size=(0.06, 0.06), yaw=DOCK.yaw)
    rig = make_rig(dock_room(_near_staging(), boxes=[crate]))
    handle = rig.server.docking.dock_robot("home")
    rig.run(handle, 60.0)
    assert handle.outcome is not None
    assert handle.outcome.error_code == DockRobotError.FAILED_TO_CONTROL
    result = handle.feedback[RESULT_KEY]
    assert (result.success, result.num_retries) == (False, PARAMS.max_retries + 1)
    assert "crate" not in rig.contacts.touched


@pytest.mark.parametrize(
    ("dock_id", "pose", "dock_type", "code"),
    [
        ("nowhere", None, "", DockRobotError.DOCK_NOT_IN_DB),
        ("", DOCKED, "nova_carter_dock", DockRobotError.DOCK_NOT_VALID),
        ("", Pose2D(x=-1.0, y=1.5, yaw=0.0), "", DockRobotError.FAILED_TO_DETECT_DOCK),
    ],
    ids=["not-in-database", "unknown-type", "no-dock-there"],
)
def test_bad_dock_goals_fail_with_nav2s_codes(
    dock_id: str, pose: Pose2D | None, dock_type: str, code: DockRobotError
) -> None:
    rig = make_rig(dock_room(_near_staging()))
    handle = rig.server.docking.dock_robot(dock_id, pose, dock_type, navigate_to_staging_pose=False)
    rig.run(handle, 20.0)
    assert handle.outcome is not None and handle.outcome.error_code == code
    assert handle.outcome.error_name == code.name
    assert handle.feedback[RESULT_KEY].error_code == code


def test_undocking_without_a_dock_fails_as_dock_not_valid() -> None:
    rig = make_rig(dock_room(_near_staging()))
    handle = rig.server.docking.undock_robot()
    rig.run(handle, 5.0)
    assert handle.outcome is not None
    assert handle.outcome.error_code == UndockRobotError.DOCK_NOT_VALID


def _at_rest(rig: NavRig) -> bool:
    rig.sim.step_for(1.0)
    before = rig.pose()
    rig.sim.step_for(0.5)
    after = rig.pose()
    return math.hypot(after.x - before.x, after.y - before.y) < 1e-3


@pytest.mark.parametrize(
    ("start", "phase"),
    [
        (Pose2D(x=-1.5, y=-1.0, yaw=0.0), DockState.NAV_TO_STAGING_POSE),
        (_near_staging(), DockState.INITIAL_PERCEPTION),
        (_near_staging(), DockState.CONTROLLING),
    ],
    ids=["staging", "perception", "controlling"],
)
def test_cancel_in_each_phase_leaves_the_robot_at_rest(start: Pose2D, phase: DockState) -> None:
    rig = make_rig(dock_room(start))
    handle = rig.server.docking.dock_robot("home")
    while _state(handle) != phase:
        rig.sim.step_for(0.05)
        assert handle.status is TaskStatus.RUNNING
    rig.sim.step_for(0.3 if phase is not DockState.INITIAL_PERCEPTION else 0.0)
    handle.cancel()
    assert handle.status is TaskStatus.CANCELED
    assert _at_rest(rig)
    assert not handle.feedback[RESULT_KEY].success


def test_cancel_while_backing_out_for_a_retry_or_undocking_leaves_the_robot_at_rest() -> None:
    crate_x, crate_y = DOCK.to_map(-0.42, 0.0)
    crate = Box(name="crate", center=(crate_x, crate_y), size=(0.06, 0.06), yaw=DOCK.yaw)
    rig = make_rig(dock_room(_near_staging(), boxes=[crate]))
    handle = rig.server.docking.dock_robot("home")
    while _state(handle) != DockState.RETRY:
        rig.sim.step_for(0.05)
        assert handle.status is TaskStatus.RUNNING
    handle.cancel()
    assert _at_rest(rig)

    rig = make_rig(dock_room(_near_staging()))
    rig.run(rig.server.docking.dock_robot("home"), 40.0)
    undock = rig.server.docking.undock_robot()
    rig.sim.step_for(1.0)
    undock.cancel()
    assert undock.status is TaskStatus.CANCELED
    assert _at_rest(rig)


def test_the_simple_commander_docks_by_id_and_by_pose_and_undocks() -> None:
    from baobab.nav.msgs import from_pose2d
    from baobab.nav.navigator import BasicNavigator, TaskResult
    from baobab.nav.ros.nav2_msgs import action

    navigator = BasicNavigator(world=dock_room(_near_staging()))
    try:
        assert navigator.dockRobotByID("home", nav_to_dock=False) is not None
        states = feedback_states(navigator)
        assert navigator.getResult() is TaskResult.SUCCEEDED
        assert action.DockRobot.Feedback.CONTROLLING in states
        assert navigator.undockRobot() is not None
        while not navigator.isTaskComplete():
            pass
        assert navigator.getResult() is TaskResult.SUCCEEDED
        navigator.dockRobotByPose(from_pose2d(DOCKED, frame_id="map"), nav_to_dock=False)
        while not navigator.isTaskComplete():
            pass
        assert navigator.getResult() is TaskResult.SUCCEEDED
        navigator.undockRobot()
        while not navigator.isTaskComplete():
            pass
        navigator.dockRobotByID("garage")
        while not navigator.isTaskComplete():
            pass
        assert navigator.getResult() is TaskResult.FAILED
        assert navigator.getTaskError()[0] == action.DockRobot.Result.DOCK_NOT_IN_DB
    finally:
        navigator.destroyNode()


def test_reload_database_reads_a_nav2_dock_database_file(tmp_path: Path) -> None:
    rig = make_rig(dock_room(_near_staging()))
    reload = rig.server.services["docking_server/reload_database"]
    good = tmp_path / "docks.yaml"
    good.write_text("docks:\n  spare:\n    type: charging_dock\n    pose: [0.0, 1.0, 3.14]\n")
    assert reload(str(good)) is True
    assert list(rig.server.docking.database) == ["spare"]
    bad = tmp_path / "bad.yaml"
    bad.write_text("docks:\n  broken: {type: charging_dock}\n")
    assert reload(str(bad)) is False
    assert list(rig.server.docking.database) == ["spare"]
