"""Nav2's velocity smoother: clamping, acceleration limits, curvature, deadband, feedback."""

from __future__ import annotations

from dataclasses import dataclass, field

import pytest

from baobab.nav.velocity_smoother import VelocitySmoother, VelocitySmootherParams
from baobab.sim.world import Pose2D


@dataclass
class FakeBase:
    """Records commands; its measured velocity is whatever the test sets."""

    commands: list[tuple[float, float]] = field(default_factory=list)
    measured: tuple[float, float] = (0.0, 0.0)
    stops: int = 0

    def pose(self) -> Pose2D:
        return Pose2D(x=0.0, y=0.0, yaw=0.0)

    def body_velocity(self) -> tuple[float, float]:
        return self.measured

    def command(self, linear: float, angular: float) -> None:
        self.commands.append((linear, angular))

    def stop(self) -> None:
        self.stops += 1


class Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


PARAMS = VelocitySmootherParams(
    enabled=True,
    max_velocity=(0.4, 2.0),
    min_velocity=(-0.2, -2.0),
    max_accel=(1.0, 4.0),
    max_decel=(-2.0, -8.0),
)


def _drive(params: VelocitySmootherParams, wanted: list[tuple[float, float]]) -> FakeBase:
    base, clock = FakeBase(), Clock()
    smoother = VelocitySmoother(base, clock, params)
    for command in wanted:
        smoother.command(*command)
        clock.now += 0.1
    return base


def test_speeding_up_and_slowing_down_are_limited_and_speeds_clamped() -> None:
    base = _drive(PARAMS, [(1.0, 0.0)] * 6 + [(0.0, 0.0)] * 3)
    linear = [round(v, 9) for v, _ in base.commands]
    # First command at dt 0 sends 0; then +0.1 per 0.1 s up to the 0.4 clamp; then -0.2 per step.
    assert linear == [0.0, 0.1, 0.2, 0.3, 0.4, 0.4, 0.2, 0.0, 0.0]


def test_reversing_slows_down_first_then_clamps_backwards() -> None:
    base = _drive(PARAMS, [(0.4, 0.0)] * 5 + [(-1.0, 0.0)] * 5)
    linear = [round(v, 9) for v, _ in base.commands][4:]
    assert linear == [0.4, 0.2, 0.0, -0.1, -0.2, -0.2]


def test_scale_velocities_keeps_the_curvature() -> None:
    scaled = VelocitySmootherParams(**{**PARAMS.__dict__, "scale_velocities": True})
    base = _drive(scaled, [(0.8, 2.0)] * 3)
    for linear, angular in base.commands[1:]:
        assert angular == pytest.approx(linear * 2.0 / 0.8)


def test_deadband_and_closed_loop_feedback() -> None:
    banded = VelocitySmootherParams(**{**PARAMS.__dict__, "deadband_velocity": (0.15, 0.0)})
    assert _drive(banded, [(1.0, 0.0)] * 3).commands[1][0] == 0.0  # 0.1 < 0.15
    closed = VelocitySmootherParams(**{**PARAMS.__dict__, "feedback": "CLOSED_LOOP"})
    base, clock = FakeBase(measured=(0.3, 0.0)), Clock()
    smoother = VelocitySmoother(base, clock, closed)
    smoother.command(0.0, 0.0)
    clock.now = 0.1
    smoother.command(1.0, 0.0)
    assert base.commands[-1][0] == pytest.approx(0.4)  # from the measured 0.3, not from 0.0


def test_a_stop_is_not_smoothed() -> None:
    base, clock = FakeBase(), Clock()
    smoother = VelocitySmoother(base, clock, PARAMS)
    smoother.command(0.4, 0.0)
    smoother.stop()
    assert base.stops == 1
