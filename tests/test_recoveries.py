"""Behaviours and recoveries: Spin, BackUp, DriveOnHeading, Wait, AssistedTeleop on their own,
and the navigation tree's recoveries when the goal is sealed off or a box traps the robot.

Nav2's semantics (reference/nav2.md §5.4): Spin at clamp(sqrt(2 a r), 0.4, 1.0) rad/s; BackUp and
DriveOnHeading ramp within the acceleration limits, never below 0.10 m/s, project 2 s ahead on
the local costmap and abort with COLLISION_AHEAD before hitting anything.
"""

from __future__ import annotations

import math

import pytest
from navigation_rig import alcove, distance, make_rig, sealed_room

from baobab.missions.run.event_targets import ObstacleSlots
from baobab.nav.errors import (
    AssistedTeleopError,
    BackUpError,
    ComputePathToPoseError,
    DriveOnHeadingError,
    SpinError,
)
from baobab.nav.navigate import CONTROLLER_RECOVERABLE_CODES, PLANNER_RECOVERABLE_CODES
from baobab.sim.tasks import TaskStatus
from baobab.sim.world import Pose2D

TURN_TOLERANCE = 0.1
"""rad: the 10 Hz cycle sees the target late by up to one cycle, then the base decelerates."""


def turned(before: Pose2D, after: Pose2D) -> float:
    return math.remainder(after.yaw - before.yaw, 2 * math.pi)


@pytest.mark.parametrize("target", [1.57, -1.57, 3.0])
def test_spin_turns_by_the_target_angle(target: float) -> None:
    rig = make_rig("walls")
    before = rig.pose()
    handle = rig.server.spin(target, 10.0)
    took = rig.run(handle, 10.0)
    rig.sim.step_for(0.5)  # let the base come to rest
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.SUCCEEDED
    travelled = handle.feedback["angular_distance_traveled"]
    assert math.copysign(1.0, travelled) == math.copysign(1.0, target)
    assert abs(travelled) >= abs(target)
    assert turned(before, rig.pose()) == pytest.approx(
        math.remainder(target, 2 * math.pi), abs=TURN_TOLERANCE
    )
    # At most 1.0 rad/s, at least 0.4 rad/s: the turn takes between |target| / 1.0 and / 0.4.
    assert abs(target) / 1.0 <= took <= abs(target) / 0.4
    assert distance(before, rig.pose()) < 0.01


def test_spin_times_out_and_zero_allowance_means_no_limit() -> None:
    rig = make_rig("walls")
    handle = rig.server.spin(100.0, 2.0)
    took = rig.run(handle, 5.0)
    assert handle.outcome is not None
    assert handle.outcome.error_code == SpinError.TIMEOUT == 701
    assert handle.outcome.error_msg.startswith("Spin:")
    assert took == pytest.approx(2.1, abs=0.06)  # the cycle after the allowance ran out
    unlimited = rig.server.spin(12.0, 0.0)
    assert rig.run(unlimited, 30.0) > 12.0
    assert unlimited.outcome is not None and unlimited.outcome.status is TaskStatus.SUCCEEDED


def test_back_up_and_drive_on_heading_reach_their_distances() -> None:
    rig = make_rig("walls")
    before = rig.pose()
    back = rig.server.back_up(0.30, 0.15, 10.0)
    took = rig.run(back, 10.0)
    rig.sim.step_for(0.5)
    assert back.outcome is not None and back.outcome.status is TaskStatus.SUCCEEDED
    assert 0.30 <= distance(before, rig.pose()) <= 0.33
    assert rig.pose().x < before.x  # backwards: the robot faces +x
    assert took == pytest.approx(0.30 / 0.15, abs=0.4)
    before = rig.pose()
    ahead = rig.server.drive_on_heading(0.5, 0.2, 10.0)
    rig.run(ahead, 10.0)
    rig.sim.step_for(0.5)
    assert ahead.outcome is not None and ahead.outcome.status is TaskStatus.SUCCEEDED
    assert 0.50 <= distance(before, rig.pose()) <= 0.53
    assert rig.pose().x > before.x
    # The BT node's default, 0.025 m/s, runs at the behaviour server's 0.10 m/s minimum.
    slow = rig.server.drive_on_heading()
    assert rig.run(slow, 10.0) < 0.15 / 0.10 + 0.5
    backwards = rig.server.drive_on_heading(-0.2, -0.1, 10.0)
    before = rig.pose()
    rig.run(backwards, 10.0)
    assert backwards.outcome is not None and backwards.outcome.status is TaskStatus.SUCCEEDED
    assert rig.pose().x < before.x
    assert rig.contacts.touched == set()


def test_drive_on_heading_rejects_bad_goals() -> None:
    rig = make_rig("walls")
    for distance_m, speed in [(0.5, -0.1), (-0.5, 0.1), (0.5, 0.0), (math.nan, 0.1)]:
        handle = rig.server.drive_on_heading(distance_m, speed, 5.0)
        rig.run(handle, 1.0)
        assert handle.outcome is not None
        assert handle.outcome.error_code == DriveOnHeadingError.INVALID_INPUT == 724
    handle = rig.server.back_up(math.inf, 0.1, 5.0)
    rig.run(handle, 1.0)
    assert handle.outcome is not None and handle.outcome.error_code == BackUpError.INVALID_INPUT
    assert distance(rig.pose(), rig.world.spawn) < 0.01


def test_back_up_towards_a_wall_stops_with_collision_ahead_before_touching_it() -> None:
    # Facing south 0.55 m from the north wall's face (y = 3.0): backing up 1 m would hit it.
    rig = make_rig("walls", Pose2D(x=0.0, y=2.45, yaw=-math.pi / 2))
    handle = rig.server.back_up(1.0, 0.15, 20.0)
    rig.run(handle, 20.0)
    rig.sim.step_for(1.0)
    assert handle.outcome is not None
    assert (handle.outcome.error_code, handle.outcome.error_name) == (714, "COLLISION_AHEAD")
    assert handle.outcome.error_code == BackUpError.COLLISION_AHEAD
    assert handle.feedback["distance_traveled"] > 0.05  # it did back up first
    assert rig.contacts.touched == set()
    assert rig.robot.base.min_clearance() > 0.05


def test_wait_lasts_its_duration() -> None:
    rig = make_rig("walls")
    handle = rig.server.wait(2.0)
    rig.sim.step_for(1.0)
    assert handle.feedback["time_left"] == pytest.approx(1.1)  # last 10 Hz cycle at t = 0.9 s
    assert rig.run(handle, 5.0) == pytest.approx(1.05, abs=0.06)
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.SUCCEEDED


def test_assisted_teleop_slows_down_before_a_wall_and_times_out() -> None:
    rig = make_rig("walls", Pose2D(x=2.0, y=2.0, yaw=0.0))
    handle = rig.server.assisted_teleop(8.0)
    rig.server.teleop_command(0.2, 0.0)  # straight at the east wall, 1 m away
    rig.run(handle, 10.0)
    assert handle.outcome is not None
    assert handle.outcome.error_code == AssistedTeleopError.TIMEOUT
    assert handle.feedback["current_teleop_duration"] == pytest.approx(8.0, abs=0.11)
    assert rig.contacts.touched == set()
    assert rig.pose().x > 2.5  # it did drive
    assert rig.robot.base.min_clearance() > 0.0
    rig.server.teleop_command(0.0, 1.0)
    preempted = rig.server.assisted_teleop(0.0)
    rig.sim.step_for(1.0)
    rig.server.preempt_teleop()
    rig.run(preempted, 1.0)
    assert preempted.outcome is not None and preempted.outcome.status is TaskStatus.SUCCEEDED


def test_a_goal_sealed_off_by_walls_fails_with_no_valid_path_after_the_recoveries() -> None:
    rig = make_rig(sealed_room())
    handle = rig.server.navigate_to_pose(Pose2D(x=1.5, y=1.0))
    took = rig.run(handle, 60.0)
    outcome = handle.outcome
    assert outcome is not None and outcome.status is TaskStatus.FAILED
    assert outcome.error_code == ComputePathToPoseError.NO_VALID_PATH == 208
    # Seven attempts, each with the contextual global clear (7), and the six recoveries of the
    # round robin: clear both (2), spin, wait, back up, clear both (2), spin.
    assert handle.feedback["number_of_recoveries"] == 7 + 2 + 1 + 1 + 1 + 2 + 1
    # Two spins of 1.57 rad (>= 1.6 s each), a 5 s wait and a 0.3 m back-up (>= 2 s).
    assert 5.0 + 2 * 1.57 + 2.0 <= took <= 20.0
    assert rig.contacts.touched == set()


def test_walls_only_the_lidar_sees_fail_the_goal_with_no_valid_path_untouched() -> None:
    # Four spawned boxes wall the robot in: only the obstacle layers know them. Every clearing
    # of the recoveries keeps what the lidar sees, so no plan leads through them and the robot
    # never drives at them; the navigation ends as in a room sealed by static walls.
    rig = make_rig("walls")
    slots = ObstacleSlots(rig.sim)
    for name, x, y, size in [
        ("north", 0.0, 0.55, (1.3, 0.1, 0.5)),
        ("south", 0.0, -0.55, (1.3, 0.1, 0.5)),
        ("east", 0.55, 0.0, (0.1, 1.3, 0.5)),
        ("west", -0.55, 0.0, (0.1, 1.3, 0.5)),
    ]:
        slots.spawn(name, x, y, 0.0, size)
    rig.sim.step_for(0.3)  # a scan; the global costmap takes it at its 1 Hz update
    handle = rig.server.navigate_to_pose(rig.world.locations["goal_open"])
    rig.run(handle, 60.0)
    outcome = handle.outcome
    assert outcome is not None and outcome.status is TaskStatus.FAILED
    assert outcome.error_code == ComputePathToPoseError.NO_VALID_PATH
    assert handle.feedback["number_of_recoveries"] > 6
    assert rig.contacts.touched == set()
    assert rig.robot.base.min_clearance() > 0.05


def test_a_box_that_traps_the_robot_runs_the_recoveries_and_fails_cleanly() -> None:
    rig = make_rig(alcove())
    handle = rig.server.navigate_to_pose(Pose2D(x=2.0, y=1.0))
    rig.sim.step_for(0.5)
    rig.place_box(0, 0.7, 0.0)  # shuts the only way out, 1.3 m ahead of the robot
    took = rig.run(handle, 120.0)
    outcome = handle.outcome
    assert outcome is not None and outcome.status is TaskStatus.FAILED
    assert outcome.error_code in CONTROLLER_RECOVERABLE_CODES | PLANNER_RECOVERABLE_CODES
    assert handle.feedback["number_of_recoveries"] > 6
    assert took < 120.0
    assert rig.server.active_task is None
    assert rig.robot.base.target == (0.0, 0.0)
    assert rig.contacts.touched == set()
    assert rig.pose().x < 0.7 - 0.15 - 0.105  # still on its side of the box
