"""Nav2's graceful control law: it brings a unicycle onto a pose, forwards and backwards."""

from __future__ import annotations

import math

import pytest

from baobab.nav.graceful_control import (
    GracefulParams,
    projected_poses,
    rotate_towards,
    velocity,
)
from baobab.sim.world import Pose2D

PARAMS = GracefulParams()


@pytest.mark.parametrize(
    "start",
    [
        Pose2D(x=-0.7, y=0.0, yaw=0.0),
        Pose2D(x=-0.6, y=0.2, yaw=-0.4),
        Pose2D(x=-0.5, y=-0.15, yaw=0.5),
    ],
)
def test_the_law_reaches_the_target_pose_forwards(start: Pose2D) -> None:
    target = Pose2D(x=0.0, y=0.0, yaw=0.0)
    poses = projected_poses(PARAMS, target, start, horizon=20.0, dt=0.02)
    x, y, yaw = poses[-1]
    assert math.hypot(x, y) <= 0.011
    assert abs(yaw) < 0.1


def test_backwards_the_robot_reverses_onto_the_target() -> None:
    target = Pose2D(x=-0.7, y=0.0, yaw=0.0)
    start = Pose2D(x=0.0, y=0.05, yaw=0.05)
    speed, _ = velocity(PARAMS, target, start, backward=True)
    assert speed < 0
    poses = projected_poses(PARAMS, target, start, backward=True, horizon=20.0, dt=0.02)
    assert math.hypot(poses[-1, 0] + 0.7, poses[-1, 1]) <= 0.011


def test_speeds_stay_within_nav2s_limits() -> None:
    target = Pose2D(x=0.0, y=0.0, yaw=0.0)
    for start in (Pose2D(x=-2.0, y=1.0, yaw=2.0), Pose2D(x=-0.05, y=0.0, yaw=0.0)):
        speed, turn = velocity(PARAMS, target, start)
        assert abs(speed) <= PARAMS.v_linear_max + 1e-12
        assert abs(turn) <= PARAMS.v_angular_max + 1e-12


def test_rotating_in_place_is_bounded_both_ways() -> None:
    assert rotate_towards(PARAMS, 0.01) == PARAMS.v_angular_min
    assert rotate_towards(PARAMS, -3.0) == -PARAMS.v_angular_max
    assert rotate_towards(PARAMS, 0.0) == 0.0
