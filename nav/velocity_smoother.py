"""Nav2's velocity smoother between the navigation stack's commands and the robot's base.

Nav2 runs ``nav2_velocity_smoother`` between the controller and behaviour servers'
``cmd_vel_nav`` and the robot: each command is clamped to ``[min_velocity, max_velocity]``
and, in ``OPEN_LOOP`` feedback, its change from the last smoothed command is limited by
``max_accel`` / ``max_decel`` over the time since then; with ``scale_velocities`` all axes are
scaled by the most limiting axis, so a turn keeps its curvature; a smoothed speed below
``deadband_velocity`` becomes 0. For a differential-drive base the axes are x (m/s) and theta
(rad/s); Nav2's y axis has nothing to drive here. ``CLOSED_LOOP`` feedback ramps from the
base's measured velocity instead of the last command.

baobab's stack runs without it by default (each robot's base limits its own acceleration); a
Nav2 parameter file with a ``velocity_smoother`` section turns it on
(:mod:`baobab.nav.nav2_param_table`). A stop command (a cancel, a task's end) reaches the base
at once, as the controller server's zero velocity does.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from baobab.nav.interfaces import MobileBase
from baobab.sim.world import Pose2D

Axes = tuple[float, float]
"""Values for the x (linear) and theta (angular) axes."""
_AT_REST = 1e-9
"""A speed (m/s or rad/s) this close to 0 is 0."""


@dataclass(frozen=True)
class VelocitySmootherParams:
    """Nav2's velocity smoother settings (x in m/s, m/s²; theta in rad/s, rad/s²).

    Attributes:
        enabled: whether the smoother sits between the stack and the base.
        max_velocity: highest command per axis.
        min_velocity: lowest command per axis (negative: backwards, clockwise).
        max_accel: largest increase of speed per second per axis (positive).
        max_decel: largest decrease of speed per second per axis (negative).
        deadband_velocity: smoothed speeds below this per axis become 0.
        scale_velocities: scale both axes by the most limiting one (keeps the curvature).
        feedback: ``OPEN_LOOP`` ramps from the last smoothed command, ``CLOSED_LOOP`` from the
            base's measured velocity.
    """

    enabled: bool = False
    max_velocity: Axes = (0.5, 2.5)
    min_velocity: Axes = (-0.5, -2.5)
    max_accel: Axes = (2.5, 3.2)
    max_decel: Axes = (-2.5, -3.2)
    deadband_velocity: Axes = (0.0, 0.0)
    scale_velocities: bool = False
    feedback: str = "OPEN_LOOP"


class VelocitySmoother:
    """A :class:`~baobab.nav.interfaces.MobileBase` that smooths commands on their way to a base.

    Args:
        base: the robot's base.
        clock: sim time (s).
        params: the limits.
    """

    def __init__(
        self, base: MobileBase, clock: Callable[[], float], params: VelocitySmootherParams
    ) -> None:
        self.base = base
        self.params = params
        self._clock = clock
        self._last: Axes = (0.0, 0.0)
        self._last_time: float | None = None

    def pose(self) -> Pose2D:
        """The base's pose (map frame)."""
        return self.base.pose()

    def body_velocity(self) -> tuple[float, float]:
        """The base's forward speed (m/s) and yaw rate (rad/s)."""
        return self.base.body_velocity()

    def command(self, linear: float, angular: float) -> None:
        """Send the smoothed ``(linear, angular)`` (m/s, rad/s) to the base."""
        now = self._clock()
        dt = 0.0 if self._last_time is None else max(now - self._last_time, 0.0)
        self._last_time = now
        if self.params.feedback == "CLOSED_LOOP":
            self._last = self.base.body_velocity()
        smoothed = self.smooth((linear, angular), dt)
        self._last = smoothed
        self.base.command(*smoothed)

    def stop(self) -> None:
        """Stop at once (not smoothed), and start the next ramp from rest."""
        self._last = (0.0, 0.0)
        self._last_time = self._clock()
        self.base.stop()

    def smooth(self, wanted: Axes, dt: float) -> Axes:
        """The command to send for ``wanted`` ``dt`` seconds after the last one."""
        p = self.params
        clamped = [
            min(max(value, low), high)
            for value, low, high in zip(wanted, p.min_velocity, p.max_velocity, strict=True)
        ]
        if p.scale_velocities:
            clamped = _scaled(wanted, clamped)
        limited = [
            _ramp(last, value, accel, decel, dt)
            for last, value, accel, decel in zip(
                self._last, clamped, p.max_accel, p.max_decel, strict=True
            )
        ]
        if p.scale_velocities:
            limited = _scaled(clamped, limited)
        linear, angular = (
            0.0 if abs(value) < band else value
            for value, band in zip(limited, p.deadband_velocity, strict=True)
        )
        return linear, angular


def _ramp(last: float, wanted: float, accel: float, decel: float, dt: float) -> float:
    """``wanted`` within what ``dt`` seconds of acceleration allow from ``last``.

    Speeding up (away from zero) is limited by ``accel``, slowing down by ``-decel``.
    """
    if abs(last) < _AT_REST:
        last = 0.0  # what rounding left of a ramp down to rest: speeding up from here
    speeding_up = last * wanted >= 0.0 and abs(wanted) > abs(last)
    step = (accel if speeding_up else -decel) * dt
    return min(max(wanted, last - step), last + step)


def _scaled(wanted: Axes | list[float], limited: list[float]) -> list[float]:
    """``wanted`` scaled down by the most limiting axis of ``limited`` (same curvature)."""
    ratios = [
        abs(limit / value) for value, limit in zip(wanted, limited, strict=True) if value != 0.0
    ]
    factor = min(ratios, default=1.0)
    return [value * min(factor, 1.0) for value in wanted]


def smoothed(
    base: MobileBase, clock: Callable[[], float], params: VelocitySmootherParams
) -> MobileBase:
    """``base`` itself, or a :class:`VelocitySmoother` in front of it when ``params.enabled``."""
    return VelocitySmoother(base, clock, params) if params.enabled else base
