"""Nav2's behaviour server: Spin, BackUp, DriveOnHeading, Wait, clear costmaps (AssistedTeleop:
:mod:`baobab.nav.assisted_teleop`).

Each behaviour is a small state machine ticked at ``cycle_frequency`` (10 Hz) of sim time:
the first tick checks the goal and records the start, every tick after that runs one cycle
(reference/nav2.md §5.4). A behaviour stops the robot whenever it ends. The same objects run
as stand-alone tasks of the navigation server and as recovery leaves inside the navigation
trees.

Motion behaviours project their command ahead on the local costmap (``simulate_ahead_time``,
2 s, in cycle steps) and end with COLLISION_AHEAD instead of driving into something. With a
circular footprint that is the footprint's inscribed radius, a pose collides when the cost
under its centre is ``INSCRIBED_INFLATED_OBSTACLE`` or more; a polygon footprint collides when
its outline at the pose's yaw crosses a lethal cell (:mod:`baobab.nav.footprint`), so Spin
checks the turn ahead too.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import IntEnum
from typing import Any, ClassVar

import numpy as np

from baobab.nav.costmap import Costmap2D
from baobab.nav.errors import (
    BackUpError,
    DriveOnHeadingError,
    SpinError,
    WaitError,
)
from baobab.nav.footprint import collision_mask
from baobab.nav.interfaces import MobileBase
from baobab.nav.layered_costmap import LayeredCostmap
from baobab.robots.catalog import default_mobile_robot
from baobab.sim.tasks import TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D

_ROBOT = default_mobile_robot().tuning


@dataclass(frozen=True)
class BehaviorParams:
    """Behaviour server settings (Hz, s, rad/s, rad/s², m/s², m/s): Nav2's defaults within a
    robot's limits (the default robot's unless given)."""

    cycle_frequency: float = 10.0
    simulate_ahead_time: float = 2.0
    max_rotational_vel: float = _ROBOT.spin_speeds[1]
    min_rotational_vel: float = _ROBOT.spin_speeds[0]
    rotational_acc_lim: float = _ROBOT.max_angular_accel
    acceleration_limit: float = _ROBOT.max_linear_accel
    deceleration_limit: float = -_ROBOT.max_linear_accel
    minimum_speed: float = _ROBOT.backup_min_speed
    projection_time: float = 1.0
    simulation_time_step: float = 0.1
    teleop_footprint_padding: float = 0.05
    """Margin (m) assisted teleop keeps between the footprint and lethal cells."""
    teleop_costmap_clear_frequency: float = 2.0
    """How often (Hz) assisted teleop clears all costmaps while it runs, as the Nav2 Simple
Commander tutorial's assisted teleop node does; 0: never."""


@dataclass
class TeleopInput:
    """The latest teleop twist (Nav2's ``cmd_vel_teleop``) and the ``preempt_teleop`` flag."""

    linear: float = 0.0
    angular: float = 0.0
    preempt_requested: bool = False


@dataclass
class AssistedTeleopStats:
    """Run totals of assisted teleop, for metrics (every session of the server adds up).

    Attributes:
        cycles: cycles with a non-zero teleop command.
        min_scaling: smallest factor applied to a non-zero command (1: never slowed,
            0: stopped); None before the first such cycle.
        slowed_cycles: cycles whose command was scaled by a factor strictly between 0 and 1.
        stopped_cycles: cycles whose non-zero command was replaced by zero.
        max_linear: largest ``|linear|`` (m/s) sent to the base.
        costmap_clears: periodic clearings of the costmaps.
    """

    cycles: int = 0
    min_scaling: float | None = None
    slowed_cycles: int = 0
    stopped_cycles: int = 0
    max_linear: float = 0.0
    costmap_clears: int = 0

    def record(self, scaling: float, linear_speed: float) -> None:
        """Count one cycle with a non-zero command: its ``scaling`` and the speed sent (m/s)."""
        self.cycles += 1
        self.min_scaling = scaling if self.min_scaling is None else min(self.min_scaling, scaling)
        if scaling == 0.0:
            self.stopped_cycles += 1
        elif scaling < 1.0:
            self.slowed_cycles += 1
        self.max_linear = max(self.max_linear, linear_speed)


@dataclass
class BehaviorContext:
    """What behaviours act on: the base, the local costmap (for collision checks), teleop input.

    ``clear_costmaps(which)`` is what assisted teleop calls to clear the costmaps while it
    runs (None: it does not clear).
    """

    base: MobileBase
    local_costmap: Callable[[], Costmap2D]
    params: BehaviorParams = field(default_factory=BehaviorParams)
    teleop: TeleopInput = field(default_factory=TeleopInput)
    clear_costmaps: Callable[[str], None] | None = None
    teleop_stats: AssistedTeleopStats = field(default_factory=AssistedTeleopStats)


class Behavior(ABC):
    """A timed behaviour (Nav2's ``TimedBehavior``): validate, then cycle until it ends.

    Satisfies the server's task protocol: ``period`` (s), ``feedback``, ``tick(now)``,
    ``halt()``.

    Args:
        context: base, costmap and settings.
        time_allowance: seconds of sim time before TIMEOUT; 0 means no limit.
    """

    label: ClassVar[str]
    """Nav2's behaviour name, prefixed to every error message."""
    codes: ClassVar[type[IntEnum]]
    """The action's result codes (UNKNOWN, TIMEOUT, ...)."""

    def __init__(self, context: BehaviorContext, time_allowance: float = 0.0) -> None:
        self.context = context
        self.base = context.base
        self.params = context.params
        self.period = 1.0 / context.params.cycle_frequency
        self.time_allowance = time_allowance
        self.feedback: dict[str, Any] = {}
        self.collision_checks = True
        """False skips the projected-motion collision check (``disable_collision_checks``)."""
        self._started = False
        self._start_time = 0.0

    def tick(self, now: float) -> TaskOutcome | None:
        """One cycle at sim time ``now`` (s); the outcome once the behaviour ended, else None."""
        if not self._started:
            self._started = True
            self._start_time = now
            if not (math.isfinite(self.time_allowance) and self.time_allowance >= 0):
                return self._fail(
                    "UNKNOWN", f"time_allowance must be >= 0 s, got {self.time_allowance}"
                )
            invalid = self.start(now)
            if invalid is not None:
                return invalid
        if self.time_allowance > 0 and now - self._start_time > self.time_allowance + 1e-9:
            return self._fail("TIMEOUT", "Exceeded time allowance")
        return self.cycle(now)

    def halt(self) -> None:
        """Stop the robot (cancel, preemption, halted tree)."""
        self.base.stop()

    @abstractmethod
    def start(self, now: float) -> TaskOutcome | None:
        """Check the goal and take the initial state; an outcome rejects the goal."""

    @abstractmethod
    def cycle(self, now: float) -> TaskOutcome | None:
        """One control cycle: command the base; the outcome when done."""

    def _fail(self, code_name: str, message: str) -> TaskOutcome:
        self.base.stop()
        code = self.codes[code_name]
        return TaskOutcome(TaskStatus.FAILED, int(code), f"{self.label}: {message}", code.name)

    def _succeed(self) -> TaskOutcome:
        self.base.stop()
        return TaskOutcome(TaskStatus.SUCCEEDED)

    def _projection_collides(self, poses: np.ndarray) -> bool:
        """True when any projected pose (rows x, y, yaw) collides on the local costmap
        (never with :attr:`collision_checks` off)."""
        if len(poses) == 0 or not self.collision_checks:
            return False
        costmap = self.context.local_costmap()
        hits = collision_mask(costmap, poses[:, 0], poses[:, 1], yaws=poses[:, 2])
        return bool(hits.any())


class Spin(Behavior):
    """Turn in place by ``target_yaw`` (rad, signed) at ω = clamp(√(2·acc·remaining), 0.4, 1.0)."""

    label = "Spin"
    codes = SpinError

    def __init__(
        self, context: BehaviorContext, target_yaw: float, time_allowance: float = 10.0
    ) -> None:
        super().__init__(context, time_allowance)
        self.target_yaw = target_yaw
        self._previous_yaw = 0.0
        self._relative_yaw = 0.0

    def start(self, now: float) -> TaskOutcome | None:
        """Remember the heading the turn is counted from."""
        if not math.isfinite(self.target_yaw):
            return self._fail("UNKNOWN", f"target_yaw must be finite, got {self.target_yaw}")
        self._previous_yaw = self.base.pose().yaw
        self._relative_yaw = 0.0
        self.feedback["angular_distance_traveled"] = 0.0
        return None

    def cycle(self, now: float) -> TaskOutcome | None:
        """Accumulate the turn so far and command the next angular speed."""
        p = self.params
        pose = self.base.pose()
        self._relative_yaw += math.remainder(pose.yaw - self._previous_yaw, 2 * math.pi)
        self._previous_yaw = pose.yaw
        self.feedback["angular_distance_traveled"] = self._relative_yaw
        remaining = abs(self.target_yaw) - abs(self._relative_yaw)
        if remaining < 1e-6:
            return self._succeed()
        speed = math.sqrt(2.0 * p.rotational_acc_lim * remaining)
        speed = min(max(speed, p.min_rotational_vel), p.max_rotational_vel)
        angular = math.copysign(speed, self.target_yaw)
        if self._projection_collides(self._turn_ahead(pose, angular, remaining)):
            return self._fail("COLLISION_AHEAD", "Collision Ahead - Exiting Spin")
        self.base.command(0.0, angular)
        return None

    def _turn_ahead(self, pose: Pose2D, angular: float, remaining: float) -> np.ndarray:
        """The poses Nav2 checks: the turn simulated in cycle steps for ``simulate_ahead_time``
        at ``angular`` (rad/s), up to the ``remaining`` angle (rad), from the pose now.

        Turning in place, a circular footprint stays where it is: the pose now is enough.
        """
        p = self.params
        now = np.array([[pose.x, pose.y, pose.yaw]])
        if not self.context.local_costmap().has_polygon:
            return now
        turned = (
            angular * np.arange(int(p.cycle_frequency * p.simulate_ahead_time)) / p.cycle_frequency
        )
        turned = turned[remaining - np.abs(turned) > 0.0]
        return np.column_stack(
            [np.full(len(turned), pose.x), np.full(len(turned), pose.y), pose.yaw + turned]
        )


class DriveOnHeading(Behavior):
    """Drive straight ``distance`` m at ``speed`` m/s (same sign: negative drives backwards).

    The speed ramps within the acceleration limits, is capped so the robot can stop in the
    remaining distance, and never falls below ``minimum_speed``. Success once the straight
    line from the start is at least ``|distance|`` long.
    """

    label = "DriveOnHeading"
    codes: ClassVar[type[IntEnum]] = DriveOnHeadingError

    def __init__(
        self,
        context: BehaviorContext,
        distance: float,
        speed: float,
        time_allowance: float = 10.0,
    ) -> None:
        super().__init__(context, time_allowance)
        self.distance = distance
        self.speed = speed
        self._origin = Pose2D(x=0.0, y=0.0)
        self._last_speed = 0.0

    def start(self, now: float) -> TaskOutcome | None:
        """Reject a distance and speed of different signs (Nav2's INVALID_INPUT)."""
        if not (math.isfinite(self.distance) and math.isfinite(self.speed)):
            return self._fail("INVALID_INPUT", "distance and speed must be finite")
        if (self.distance > 0.0) != (self.speed > 0.0):
            return self._fail("INVALID_INPUT", "Speed and command sign did not match")
        self._begin()
        return None

    def _begin(self) -> None:
        self._origin = self.base.pose()
        self._last_speed = 0.0
        self.feedback["distance_traveled"] = 0.0

    def cycle(self, now: float) -> TaskOutcome | None:
        """Measure the distance so far and command the next speed, if the way is clear."""
        p = self.params
        pose = self.base.pose()
        travelled = math.hypot(pose.x - self._origin.x, pose.y - self._origin.y)
        self.feedback["distance_traveled"] = travelled
        target = abs(self.distance)
        if travelled >= target:
            return self._succeed()
        dt = 1.0 / p.cycle_frequency
        forward = self.speed > 0.0
        current = self._last_speed
        if forward:
            low, high = current + p.deceleration_limit * dt, current + p.acceleration_limit * dt
        else:
            low, high = current - p.acceleration_limit * dt, current - p.deceleration_limit * dt
        speed = min(max(self.speed, low), high)
        remaining = target - travelled
        stop_speed = math.sqrt(-2.0 * p.deceleration_limit * remaining)
        if stop_speed < abs(speed):
            speed = math.copysign(stop_speed, self.speed)
        if abs(speed) < p.minimum_speed:
            speed = math.copysign(p.minimum_speed, self.speed)
        # Nav2 simulates the straight motion ahead in cycle steps, up to the remaining distance.
        steps = int(p.cycle_frequency * p.simulate_ahead_time)
        advance = speed * np.arange(steps) / p.cycle_frequency
        advance = advance[remaining - np.abs(advance) > 0.0]
        poses = np.column_stack(
            [
                pose.x + advance * math.cos(pose.yaw),
                pose.y + advance * math.sin(pose.yaw),
                np.full(len(advance), pose.yaw),
            ]
        )
        if self._projection_collides(poses):
            return self._fail("COLLISION_AHEAD", "Collision Ahead")
        self._last_speed = speed
        self.base.command(speed, 0.0)
        return None


class BackUp(DriveOnHeading):
    """Reverse ``|distance|`` m at ``|speed|`` m/s: Nav2 negates both, whatever their signs."""

    label = "BackUp"
    codes = BackUpError

    def start(self, now: float) -> TaskOutcome | None:
        """Turn the goal into a backwards drive."""
        if not (math.isfinite(self.distance) and math.isfinite(self.speed)):
            return self._fail("INVALID_INPUT", "distance and speed must be finite")
        self.distance = -abs(self.distance)
        self.speed = -abs(self.speed)
        self._begin()
        return None


class Wait(Behavior):
    """Stand by for ``duration`` s of sim time (the robot is not commanded)."""

    label = "Wait"
    codes = WaitError

    def __init__(self, context: BehaviorContext, duration: float) -> None:
        super().__init__(context, 0.0)
        self.duration = duration
        self._end = 0.0

    def start(self, now: float) -> TaskOutcome | None:
        """Set the end time."""
        if not (math.isfinite(self.duration) and self.duration >= 0):
            return self._fail("UNKNOWN", f"duration must be >= 0 s, got {self.duration}")
        self._end = now + self.duration
        return None

    def cycle(self, now: float) -> TaskOutcome | None:
        """Report the time left; succeed when none is."""
        left = self._end - now
        self.feedback["time_left"] = max(left, 0.0)
        if left > 1e-9:
            return None
        return TaskOutcome(TaskStatus.SUCCEEDED)


COSTMAP_CHOICES = ("local", "global", "all")
"""What :class:`ClearCostmaps` accepts."""


class ClearCostmaps:
    """Nav2's ``clear_entirely_{local,global}_costmap`` services: reset the obstacle layers.

    The static layer stays; :meth:`~baobab.nav.server.NavigationServer.clear_costmaps` then
    marks the latest scan again, so what the lidar still sees stays.
    """

    def __init__(self, local: LayeredCostmap, global_: LayeredCostmap) -> None:
        self._costmaps = {"local": (local,), "global": (global_,), "all": (local, global_)}

    def __call__(self, which: str) -> None:
        """Clear the ``local``, ``global`` or ``all`` costmaps.

        Raises:
            ValueError: for any other name.
        """
        if which not in self._costmaps:
            raise ValueError(
                f"clear_costmaps: which must be one of {COSTMAP_CHOICES}, got {which!r}"
            )
        for costmap in self._costmaps[which]:
            costmap.clear()
