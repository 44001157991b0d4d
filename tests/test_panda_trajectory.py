"""The linear trajectory planner: the seed's goal checks, lerp + Slerp, and both time scalings."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from baobab.robots.panda.errors import TrajectoryGoalError
from baobab.robots.panda.trajectory import (
    PANDA_CARTESIAN_LIMITS,
    LinearTrajectory,
    TimeScaling,
    parse_goal,
)
from baobab.sim.errors import BaobabError

START_POSITION = np.array([0.3, 0.0, 0.5])
START_QUATERNION = np.array([1.0, 0.0, 0.0, 0.0])


def _trajectory(goal: list[float], scaling: TimeScaling = TimeScaling.RUCKIG) -> LinearTrajectory:
    return LinearTrajectory(
        START_POSITION, START_QUATERNION, parse_goal(goal), time_scaling=scaling
    )


@pytest.mark.parametrize(
    ("goal", "message"),
    [
        ([2.0, 0.5, 0.0, 0.3, 1.0, 0.0, 0.0], "size 8"),
        ([2.0, 0.5, 0.0, 0.3, 1.0, 0.0, 0.0, 0.0, 0.0], "size 8"),
        ([0.0, 0.5, 0.0, 0.3, 1.0, 0.0, 0.0, 0.0], "strictly positive"),
        ([-1.0, 0.5, 0.0, 0.3, 1.0, 0.0, 0.0, 0.0], "strictly positive"),
        ([2.0, 0.5, 0.0, 0.3, 0.0, 0.0, 0.0, 0.0], "near zero"),
        ([2.0, 0.5, 0.0, 0.3, 1e-9, 0.0, 0.0, 0.0], "near zero"),
        ([2.0, float("nan"), 0.0, 0.3, 1.0, 0.0, 0.0, 0.0], "finite"),
        (["two", 0.5, 0.0, 0.3, 1.0, 0.0, 0.0, 0.0], "numbers"),
    ],
)
def test_invalid_goals_are_rejected_as_the_seed_says(goal: list[object], message: str) -> None:
    with pytest.raises(TrajectoryGoalError, match=message) as raised:
        parse_goal(goal)  # type: ignore[arg-type]
    assert isinstance(raised.value, ValueError)
    assert isinstance(raised.value, BaobabError)


def test_goal_quaternion_is_normalised() -> None:
    goal = parse_goal([3.0, 0.6, 0.2, 0.3, 2.0, 0.0, 0.0, 0.0])
    assert goal.duration == 3.0
    np.testing.assert_allclose(goal.position, [0.6, 0.2, 0.3])
    np.testing.assert_allclose(goal.quaternion, [1.0, 0.0, 0.0, 0.0])


def test_linear_scaling_is_the_seeds_alpha_t_over_t() -> None:
    goal_rotation = Rotation.from_euler("z", 0.8) * Rotation.from_quat(START_QUATERNION)
    goal = [2.0, 0.5, 0.2, 0.3, *goal_rotation.as_quat()]
    trajectory = _trajectory(goal, TimeScaling.LINEAR)
    assert trajectory.duration == 2.0
    times = np.array([0.0, 0.5, 1.0, 2.0, 3.0])
    positions, quaternions = trajectory.sample(times)
    alpha = np.clip(times / 2.0, 0.0, 1.0)
    np.testing.assert_allclose(
        positions, START_POSITION + alpha[:, None] * ([0.5, 0.2, 0.3] - START_POSITION)
    )
    slerp = Slerp([0.0, 1.0], Rotation.from_quat([START_QUATERNION, goal[4:]]))
    expected = slerp(alpha)
    assert np.allclose(
        (Rotation.from_quat(quaternions).inv() * expected).magnitude(), 0.0, atol=1e-12
    )


def test_ruckig_keeps_the_requested_duration_when_it_is_feasible() -> None:
    trajectory = _trajectory([2.5, 0.5, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0])
    assert trajectory.duration == pytest.approx(2.5)
    positions, _ = trajectory.sample(np.array([0.0, 2.5]))
    np.testing.assert_allclose(positions, np.array([START_POSITION, [0.5, 0.2, 0.3]]), atol=1e-12)


def test_ruckig_stretches_an_infeasible_duration_to_the_pandas_minimum() -> None:
    trajectory = _trajectory([0.01, 0.8, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0])
    length = 0.5
    # No profile beats bang-bang acceleration, 2 sqrt(L / a_max), or cruising at v_max, L / v_max.
    lower_bound = max(2 * np.sqrt(length / PANDA_CARTESIAN_LIMITS.acceleration), length / 1.7)
    assert trajectory.duration > max(0.01, lower_bound)
    assert trajectory.duration < lower_bound + 0.1


def _differentiate(values: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    velocity = np.gradient(values, dt, axis=0)
    return velocity, np.gradient(velocity, dt, axis=0)


@pytest.mark.parametrize("duration", [0.05, 1.0])
def test_ruckig_profile_respects_the_cartesian_limits(duration: float) -> None:
    goal_rotation = Rotation.from_euler("xz", [0.4, 1.2]) * Rotation.from_quat(START_QUATERNION)
    trajectory = _trajectory([duration, 0.6, 0.3, 0.2, *goal_rotation.as_quat()])
    dt = 1e-4
    times = np.arange(0.0, trajectory.duration + dt, dt)
    positions, quaternions = trajectory.sample(times)
    velocity, acceleration = _differentiate(positions, dt)
    rotations = Rotation.from_quat(quaternions)
    angular_rate = (rotations[1:] * rotations[:-1].inv()).magnitude() / dt
    angular_acceleration = np.diff(angular_rate) / dt
    limits = PANDA_CARTESIAN_LIMITS
    assert np.linalg.norm(velocity, axis=1).max() <= limits.velocity * 1.001
    assert np.linalg.norm(acceleration, axis=1).max() <= limits.acceleration * 1.01
    assert angular_rate.max() <= limits.angular_velocity * 1.001
    assert np.abs(angular_acceleration).max() <= limits.angular_acceleration * 1.01
    # The short goal is stretched to the minimum time: one of the limits is (nearly) reached.
    if duration < 0.1:
        usage = [
            np.linalg.norm(velocity, axis=1).max() / limits.velocity,
            np.linalg.norm(acceleration, axis=1).max() / limits.acceleration,
            angular_rate.max() / limits.angular_velocity,
            np.abs(angular_acceleration).max() / limits.angular_acceleration,
        ]
        assert max(usage) > 0.9


def test_path_is_a_straight_line_with_monotonic_progress() -> None:
    trajectory = _trajectory([1.5, 0.6, -0.2, 0.4, 0.0, 1.0, 0.0, 0.0])
    times = np.linspace(0.0, trajectory.duration, 301)
    s, s_dot, _ = trajectory.path_parameter(times)
    assert s[0] == 0.0 and s[-1] == pytest.approx(1.0)
    assert np.all(np.diff(s) >= -1e-12) and np.all(s_dot >= -1e-12)
    positions, _ = trajectory.sample(times)
    direction = (np.array([0.6, -0.2, 0.4]) - START_POSITION) / trajectory.length
    offsets = positions - START_POSITION
    off_line = offsets - np.outer(offsets @ direction, direction)
    assert np.abs(off_line).max() < 1e-12


def test_a_goal_at_the_start_pose_takes_the_requested_time() -> None:
    trajectory = _trajectory([0.7, *START_POSITION, *START_QUATERNION])
    assert trajectory.duration == 0.7
    positions, _ = trajectory.sample(np.array([0.0, 0.35, 0.7]))
    np.testing.assert_allclose(positions, np.tile(START_POSITION, (3, 1)))
