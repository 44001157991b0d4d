"""Goal and progress checkers, and the navigation error codes."""

from __future__ import annotations

import pytest

from baobab.nav.checkers import SimpleGoalChecker, SimpleProgressChecker
from baobab.nav.errors import (
    BackUpError,
    CollisionAheadError,
    ComputePathThroughPosesError,
    ComputePathToPoseError,
    FollowPathError,
    NavigateToPoseError,
    NavigationError,
    SpinError,
    reported_error_code,
)
from baobab.sim.errors import BaobabError
from baobab.sim.world import Pose2D

GOAL = Pose2D(x=1.0, y=2.0, yaw=3.0)


def test_goal_checker_latches_the_position() -> None:
    checker = SimpleGoalChecker()
    assert not checker.is_goal_reached(Pose2D(x=1.3, y=2.0, yaw=3.0), GOAL)  # 0.30 m away
    assert not checker.is_goal_reached(Pose2D(x=1.2, y=2.0, yaw=2.0), GOAL)  # in xy, yaw off
    assert checker.position_latched
    # While rotating in place the robot drifts out of the circle: still accepted.
    assert checker.is_goal_reached(Pose2D(x=1.3, y=2.0, yaw=-3.1), GOAL)  # yaw wraps: 0.18 rad
    checker.reset()
    assert not checker.position_latched
    assert not checker.is_goal_reached(Pose2D(x=1.3, y=2.0, yaw=3.0), GOAL)


def test_goal_checker_without_state_and_at_the_boundaries() -> None:
    checker = SimpleGoalChecker(stateful=False)
    assert not checker.is_goal_reached(Pose2D(x=1.2, y=2.0, yaw=2.0), GOAL)
    assert not checker.is_goal_reached(Pose2D(x=1.3, y=2.0, yaw=3.0), GOAL)
    assert checker.is_goal_reached(Pose2D(x=1.25, y=2.0, yaw=3.0), GOAL)  # xy: <= 0.25 m
    assert not checker.is_goal_reached(Pose2D(x=1.0, y=2.0, yaw=2.75), GOAL)  # yaw: < 0.25 rad
    assert checker.is_goal_reached(Pose2D(x=1.0, y=2.0, yaw=2.76), GOAL)
    assert checker.tolerances() == (0.25, 0.25)
    with pytest.raises(ValueError):
        SimpleGoalChecker(xy_goal_tolerance=-1.0)


def test_progress_checker_fires_after_ten_seconds_without_half_a_metre() -> None:
    checker = SimpleProgressChecker()
    assert checker.check(Pose2D(x=0.0, y=0.0), now=0.0)
    for step in range(1, 101):  # creeping 0.4 m in 10 s
        assert checker.check(Pose2D(x=0.004 * step, y=0.0), now=0.1 * step)
    assert not checker.check(Pose2D(x=0.45, y=0.0), now=10.1)
    # Moving more than 0.5 m from the baseline sets a new one and progress is fine again.
    assert checker.check(Pose2D(x=0.51, y=0.0), now=10.2)
    assert checker.check(Pose2D(x=0.51, y=0.4), now=20.1)
    assert not checker.check(Pose2D(x=0.51, y=0.4), now=20.3)
    checker.reset()
    assert checker.check(Pose2D(x=0.51, y=0.4), now=30.0)


def test_error_codes_have_nav2_numbers() -> None:
    assert [int(c) for c in ComputePathToPoseError] == [0, *range(200, 209)]
    assert ComputePathThroughPosesError.NO_VIAPOINTS_GIVEN == 309
    assert [int(c) for c in FollowPathError] == [0, *range(100, 109)]
    assert (SpinError.COLLISION_AHEAD, BackUpError.INVALID_INPUT) == (703, 713)
    assert NavigateToPoseError.TIMEOUT == 9003
    # The navigator reports the lowest non-zero code: controller before planner before spin.
    assert reported_error_code([0, 703, 208, 105]) == 105
    assert reported_error_code([0, 0]) == 0


def test_navigation_error_carries_code_and_message() -> None:
    error = NavigationError(ComputePathToPoseError.GOAL_OCCUPIED, "goal in a wall")
    assert isinstance(error, BaobabError)
    assert (error.code, error.message, error.code_name) == (206, "goal in a wall", "GOAL_OCCUPIED")
    assert str(error) == "GOAL_OCCUPIED (206): goal in a wall"
    ahead = CollisionAheadError()
    assert isinstance(ahead, NavigationError) and ahead.code == FollowPathError.NO_VALID_CONTROL
    assert NavigationError(4242, "odd").code_name == "4242"
