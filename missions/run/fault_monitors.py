"""Fault monitors: what ends a run FAILED when the robot can no longer be trusted to drive.

The run loop asks :meth:`FaultMonitors.check` once per tick (10 Hz). Each monitor reads a few
numbers through the robot's public API and named MuJoCo access, keeps no history beyond a
timestamp, and allocates nothing per call (a scan's roughness is one compiled pass,
:mod:`~baobab.missions.run.scan_roughness_kernel`):

- ``ROBOT_DISPLACED``: the pose moved farther between two checks than the robot can drive
  (a kidnapped robot; a localisation jump on a real one).
- ``SENSOR_TIMEOUT``: no lidar scan for ``scan_timeout`` s (Nav2's "sensor data out of date";
  five of the lidar's scan periods). A shorter dropout is ridden through.
- ``SENSOR_DEGRADED``: the scan has been rough for ``degraded_for`` s: most pairs of
  neighbouring beams differ by more than ``rough_step`` m, which walls, furniture and edges
  do not do but range noise of about 0.1 m and more does. A shorter burst is ridden through.
- ``WHEEL_FAULT``: a wheel's measured speed has stayed away from its commanded speed (the
  velocity actuator's ``ctrl``) for ``wheel_fault_for`` s while the robot touched nothing: a
  dead motor or a jammed wheel. Pushing against an obstacle also holds the wheels back; that
  is a collision, which the tree and the ``no_contact`` expectation judge, not a wheel fault.

A physics divergence is caught by the simulation itself (any robot); the watch's
:meth:`~DivergenceWatch.explain_divergence` adds the joint or actuator that MuJoCo found
non-finite to its message.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from baobab.missions.run.rig import MobileRig, Rig
from baobab.missions.run.scan_roughness_kernel import rough_pairs
from baobab.missions.run.tick_loop import MissionErrorCode
from baobab.robots.catalog import default_mobile_robot
from baobab.robots.diff_drive.robot import MobileRobot
from baobab.robots.tuning import RobotTuning
from baobab.sim.simulation import Simulation

_ROBOT = default_mobile_robot().tuning


@dataclass(frozen=True)
class MonitorParams:
    """Thresholds of the fault monitors (SI units).

    The defaults are the registry's default mobile robot's; :meth:`for_robot` gives a robot's
    (:mod:`baobab.robots.tuning`: three times its limits, at least 2 m/s and 10 rad/s; five
    scan periods).

    Attributes:
        max_plausible_speed: m/s; a pose that moved faster between two checks was displaced.
        max_plausible_turn_rate: rad/s; the same for the heading.
        jump_margin: m and rad added to both bounds, for contact jitter.
        scan_timeout: s without a scan before SENSOR_TIMEOUT.
        rough_step: m; neighbouring beams differing by more are a rough pair.
        rough_fraction: share of rough pairs (of the pairs with two returns) that makes a
            scan degraded.
        min_pairs: fewer pairs with two returns say nothing about noise.
        degraded_for: s of degraded scans before SENSOR_DEGRADED.
        wheel_mismatch: rad/s; a wheel this far from its command mismatches (healthy wheels
            stay within 0.32 rad/s in the bundled missions).
        wheel_mismatch_ratio: ...or this share of its command, whichever is larger.
        wheel_fault_for: s of mismatch before WHEEL_FAULT.
    """

    max_plausible_speed: float = _ROBOT.plausible_speeds[0]
    max_plausible_turn_rate: float = _ROBOT.plausible_speeds[1]
    jump_margin: float = 0.05
    scan_timeout: float = _ROBOT.scan_timeout
    rough_step: float = 0.1
    rough_fraction: float = 0.5
    min_pairs: int = 30
    degraded_for: float = 1.0
    wheel_mismatch: float = 0.5
    wheel_mismatch_ratio: float = 0.05
    wheel_fault_for: float = 0.5

    @classmethod
    def for_robot(cls, tuning: RobotTuning) -> MonitorParams:
        """The thresholds a robot's limits and lidar rate decide; the others as defaulted."""
        speed, turn_rate = tuning.plausible_speeds
        return cls(
            max_plausible_speed=speed,
            max_plausible_turn_rate=turn_rate,
            scan_timeout=tuning.scan_timeout,
        )


Detection = tuple[MissionErrorCode, str]
"""A detected fault: its code and one line for ``error_msg``."""


class DivergenceWatch:
    """Any robot's watch: no monitors, but divergence messages name the culprit.

    Args:
        sim: the run's simulation.
    """

    def __init__(self, sim: Simulation) -> None:
        self.sim = sim

    def check(self, now: float) -> Detection | None:
        """The first fault seen at ``now`` (s of sim time), or None."""
        return None

    def explain_divergence(self, message: str) -> str:
        """A divergence ``message`` with the joint or actuator MuJoCo found non-finite.

        MuJoCo keeps the index of the offending degree of freedom, position or control of
        each warning (``data.warning[kind].lastinfo``); the simulation's message says which
        warnings fired ("bad qvel", "bad qacc", ...).
        """
        model = self.sim.model
        warnings = self.sim.data.warning
        found: list[str] = []
        for field, kind in _INDEXED_WARNINGS:
            if f"bad {field}" not in message:
                continue
            name = _element_name(model, field, int(warnings[int(kind)].lastinfo))
            if name:
                found.append(f"{field} of {name}")
        return f"{message} ({'; '.join(found)})" if found else message


class FaultMonitors(DivergenceWatch):
    """The fault monitors of a mobile robot (see the module docstring).

    Args:
        sim: the run's simulation.
        robot: the robot to watch.
        params: thresholds.
    """

    def __init__(
        self, sim: Simulation, robot: MobileRobot, params: MonitorParams | None = None
    ) -> None:
        super().__init__(sim)
        self.base = robot.base
        self.lidar = robot.lidar
        self.params = params or MonitorParams()
        data = sim.data
        # Views into MjData, taken once: reading them allocates nothing.
        chassis = data.body(robot.names.body)
        self._position = chassis.xpos
        self._rotation_head = chassis.xmat[:4]  # row-major 3x3: R[0,0], R[0,1], R[0,2], R[1,0]
        self._wheel_names = robot.names.wheel_joints
        self._wheels = [  # (commanded, measured) speed of each wheel (rad/s)
            (data.actuator(actuator).ctrl, data.joint(joint).qvel)
            for actuator, joint in zip(
                robot.names.wheel_actuators, robot.names.wheel_joints, strict=True
            )
        ]
        self._last_check: tuple[float, float, float, float] | None = None  # t, x, y, yaw
        self._last_scan_stamp = -math.inf
        self._degraded_since: float | None = None
        self._mismatch_since: list[float | None] = [None, None]
        self._beams = self.lidar.beams

    def check(self, now: float) -> Detection | None:
        """The first fault seen at ``now`` (s of sim time), or None."""
        return (
            self._displacement(now)
            or self._scan_timeout(now)
            or self._scan_quality(now)
            or self._wheel_speeds(now)
        )

    # -- the monitors --------------------------------------------------------------------------

    def _displacement(self, now: float) -> Detection | None:
        x, y, _ = self._position.tolist()
        r00, _, _, r10 = self._rotation_head.tolist()
        yaw = math.atan2(r10, r00)
        last, self._last_check = self._last_check, (now, x, y, yaw)
        if last is None or now <= last[0]:
            return None
        p = self.params
        elapsed = now - last[0]
        moved = math.hypot(x - last[1], y - last[2])
        turned = abs(math.remainder(yaw - last[3], math.tau))
        if moved <= p.max_plausible_speed * elapsed + p.jump_margin and (
            turned <= p.max_plausible_turn_rate * elapsed + p.jump_margin
        ):
            return None
        return (
            MissionErrorCode.ROBOT_DISPLACED,
            f"the robot was displaced: it moved {moved:.2f} m and turned {turned:.2f} rad in "
            f"{elapsed:.2f} s, from ({last[1]:.2f}, {last[2]:.2f}) to ({x:.2f}, {y:.2f}); "
            "more than it can drive",
        )

    def _scan_timeout(self, now: float) -> Detection | None:
        lidar = self.lidar
        latest = lidar.latest
        stamp = 0.0 if latest is None else latest.stamp
        silent = now - stamp
        if silent <= self.params.scan_timeout + 1e-9:
            return None
        return (
            MissionErrorCode.SENSOR_TIMEOUT,
            f"lidar '{lidar.frame_id}' data out of date: no scan for {silent:.2f} s (last at "
            f"t={stamp:.2f} s; limit {self.params.scan_timeout:g} s)",
        )

    def _scan_quality(self, now: float) -> Detection | None:
        scan = self.lidar.latest
        if scan is None or scan.stamp == self._last_scan_stamp:
            return None
        self._last_scan_stamp = scan.stamp
        p = self.params
        share = self._rough_share(scan.ranges)
        if share is None or share < p.rough_fraction:
            self._degraded_since = None
            return None
        if self._degraded_since is None:
            self._degraded_since = scan.stamp
        lasted = scan.stamp - self._degraded_since
        if lasted < p.degraded_for - 1e-9:
            return None
        return (
            MissionErrorCode.SENSOR_DEGRADED,
            f"lidar '{scan.frame_id}' data degraded for {lasted:.2f} s: {share:.0%} of "
            f"neighbouring beams differ by more than {p.rough_step:g} m (range noise)",
        )

    def _rough_share(self, ranges: np.ndarray) -> float | None:
        """Share of neighbouring beam pairs (both with a return) more than rough_step apart."""
        if ranges.shape[0] != self._beams:
            return None
        pairs, rough = rough_pairs(ranges, self.params.rough_step)
        if pairs < self.params.min_pairs:
            return None
        return rough / pairs

    def _wheel_speeds(self, now: float) -> Detection | None:
        p = self.params
        for index, (commanded_view, measured_view) in enumerate(self._wheels):
            (commanded,) = commanded_view.tolist()
            (measured,) = measured_view.tolist()
            limit = max(p.wheel_mismatch, p.wheel_mismatch_ratio * abs(commanded))
            if abs(measured - commanded) <= limit or self.base.robot_contacts():
                self._mismatch_since[index] = None
                continue
            since = self._mismatch_since[index]
            if since is None:
                self._mismatch_since[index] = since = now
            if now - since >= p.wheel_fault_for - 1e-9:
                return (
                    MissionErrorCode.WHEEL_FAULT,
                    f"wheel '{self._wheel_names[index]}' turns at {measured:.2f} rad/s, commanded "
                    f"{commanded:.2f} rad/s, for {now - since:.2f} s (motor or wheel fault)",
                )
        return None


_INDEXED_WARNINGS = (
    ("qpos", mujoco.mjtWarning.mjWARN_BADQPOS),
    ("qvel", mujoco.mjtWarning.mjWARN_BADQVEL),
    ("qacc", mujoco.mjtWarning.mjWARN_BADQACC),
    ("ctrl", mujoco.mjtWarning.mjWARN_BADCTRL),
)


def _element_name(model: mujoco.MjModel, field: str, index: int) -> str:
    """``joint 'robot/root'`` for a qpos/dof index, ``actuator '...'`` for a control index."""
    if field == "ctrl":
        return f"actuator '{model.actuator(index).name}'" if 0 <= index < model.nu else ""
    if field == "qpos":
        if not 0 <= index < model.nq:
            return ""
        joint = int(np.searchsorted(model.jnt_qposadr, index, side="right")) - 1
    else:
        if not 0 <= index < model.nv:
            return ""
        joint = int(model.dof_jntid[index])
    return f"joint '{model.joint(joint).name}'"


def fault_monitors(rig: Rig) -> DivergenceWatch:
    """The watch for ``rig``: every monitor for a mobile robot, divergences for any other."""
    if isinstance(rig, MobileRig):
        return FaultMonitors(rig.sim, rig.robot, MonitorParams.for_robot(rig.info.tuning))
    return DivergenceWatch(rig.sim)
