"""Nav2's collision monitor: the last check of every velocity command before the base.

:class:`CollisionMonitor` sits where Nav2's ``collision_monitor`` node sits, on ``cmd_vel``
between whatever drives and the base: its :attr:`~CollisionMonitor.base` is the base the
drivers get (the navigation controller, the recoveries, assisted teleop, the tutorial
controllers, the ROS runtime's ``/cmd_vel``), and each command sent to it is processed once,
as Nav2 processes each incoming message:

1. the points of every enabled observation source (the lidar's latest scan, moved into the
   robot's current frame when ``base_shift_correction``); a source whose data is older than
   its ``source_timeout`` stops the robot, whatever the toggle says;
2. while enabled, each enabled zone in order: ``stop`` (zero), ``slowdown`` (the command times
   ``slowdown_ratio``), ``limit`` (scaled to ``linear_limit`` m/s and ``angular_limit``
   rad/s, curvature kept), ``approach`` (scaled by the time to collision over
   ``time_before_collision``); the safest command wins (the smallest ``vx^2 + vy^2 + w^2``)
   and a stop ends the evaluation;
3. the result goes to the base; once it has been zero for ``stop_pub_timeout`` s, zeros are
   no longer sent (the base holds zero).

``toggle(enable)`` is Nav2's ``collision_monitor/toggle`` service (``nav2_msgs/Toggle``); a
navigation server built on :attr:`CollisionMonitor.base` offers it (:meth:`CollisionMonitor.serve`).
Every change of the monitor's state (action type, zone, enabled) is kept in :attr:`changes`
with its sim time, for traces and recordings.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from baobab.nav.collision_monitor_params import (
    ActionType,
    CollisionMonitorParams,
    SourceParams,
)
from baobab.nav.collision_monitor_zones import Zone
from baobab.nav.interfaces import MobileBase, ScanSource
from baobab.robots.footprint import Footprint
from baobab.sim.lidar import LaserScan
from baobab.sim.simulation import Simulation
from baobab.sim.world import Pose2D

COLLISION_MONITOR_TOGGLE = "collision_monitor/toggle"
"""The toggle service's name (``NavigationServer.services``)."""
INVALID_SOURCE = "invalid source"
"""The ``polygon_name`` Nav2 reports when stale source data stops the robot."""


@dataclass(frozen=True)
class MonitorState:
    """``nav2_msgs/CollisionMonitorState`` and the toggle: what the monitor does now."""

    action_type: ActionType = ActionType.DO_NOTHING
    polygon_name: str = ""
    enabled: bool = True


@dataclass(frozen=True)
class MonitorChange:
    """The monitor's state from ``time`` (s of sim time) on."""

    time: float
    state: MonitorState


class ScanPoints:
    """One ``scan`` source: the latest scan's returns in the map frame, and when it came."""

    def __init__(self, params: SourceParams, timeout: float, base: MobileBase) -> None:
        self.params = params
        self.timeout = timeout
        self._base = base
        self._map_xy = np.empty((0, 2))
        self._stamp: float | None = None
        self._base_then = Pose2D(x=0.0, y=0.0)

    def on_scan(self, scan: LaserScan) -> None:
        """Keep ``scan``'s returns (a lidar subscriber; called when the scan is taken)."""
        ranges = np.asarray(scan.ranges, dtype=float)
        valid = np.isfinite(ranges) & (ranges >= scan.range_min) & (ranges <= scan.range_max)
        sensor = scan.sensor_pose
        angles = sensor.yaw + scan.angles[valid]
        self._map_xy = np.column_stack(
            (sensor.x + ranges[valid] * np.cos(angles), sensor.y + ranges[valid] * np.sin(angles))
        )
        self._stamp = scan.stamp
        self._base_then = self._base.pose()

    def points(self, now: float, shift_correction: bool) -> np.ndarray | None:
        """The returns in the base frame (``(N, 2)``, m), or None when the data is stale: none
        yet, or older than the source timeout (0: never stale).

        With ``shift_correction`` the points are where they are now relative to the robot;
        without, where they were relative to the robot when the scan was taken.
        """
        if self._stamp is None or (self.timeout > 0 and now - self._stamp > self.timeout):
            return None if self.timeout > 0 else np.empty((0, 2))
        frame = self._base.pose() if shift_correction else self._base_then
        cos, sin = math.cos(frame.yaw), math.sin(frame.yaw)
        dx, dy = self._map_xy[:, 0] - frame.x, self._map_xy[:, 1] - frame.y
        return np.column_stack((cos * dx + sin * dy, -sin * dx + cos * dy))


class MonitoredBase:
    """The base as the drivers see it: commands pass the monitor, the rest is the base's."""

    def __init__(self, monitor: CollisionMonitor, base: MobileBase) -> None:
        self._monitor = monitor
        self._base = base

    def pose(self) -> Pose2D:
        """The base's map-frame pose (m, rad)."""
        return self._base.pose()

    def body_velocity(self) -> tuple[float, float]:
        """Forward speed (m/s) and yaw rate (rad/s)."""
        return self._base.body_velocity()

    def command(self, linear: float, angular: float) -> None:
        """``cmd_vel`` (m/s, rad/s) through the monitor.

        Raises:
            ValueError: if either value is not finite.
        """
        if not (math.isfinite(linear) and math.isfinite(angular)):
            raise ValueError(f"cmd_vel must be finite, got ({linear}, {angular})")
        self._monitor.process(linear, angular)

    def stop(self) -> None:
        """A zero command, through the monitor (zero is never unsafe)."""
        self._monitor.process(0.0, 0.0)


class CollisionMonitor:
    """Nav2's collision monitor on one robot (see the module docstring).

    Args:
        sim: the simulation (its clock).
        base: the robot's base; the monitor commands it.
        lidar: the scanner the ``scan`` sources read.
        params: the monitor's parameters.
        footprint: the robot's footprint, for ``approach`` zones without points.
    """

    def __init__(
        self,
        sim: Simulation,
        base: MobileBase,
        lidar: ScanSource,
        params: CollisionMonitorParams,
        footprint: Footprint,
    ) -> None:
        self.params = params
        self._sim = sim
        self._base = base
        self._lidar = lidar
        self.base = MonitoredBase(self, base)
        """The base to give every driver."""
        self.zones = [Zone(polygon, footprint) for polygon in params.polygons]
        self.sources = {
            source.name: ScanPoints(source, params.timeout_of(source), base)
            for source in params.observation_sources
        }
        for source in self.sources.values():
            lidar.subscribe(source.on_scan)
        self.enabled = params.enabled
        self.state = MonitorState(enabled=self.enabled)
        self.changes: list[MonitorChange] = [MonitorChange(sim.time, self.state)]
        """Every state change, in order (the first is the state at construction)."""
        self.stops = 0
        """How often the monitor began to stop the robot."""
        self.acting_time = 0.0
        """Sim seconds during which it changed the commands (any action)."""
        self.last_output: tuple[float, float] | None = None
        """The last command (m/s, rad/s) sent to the base, None before the first."""
        self._last_process: float | None = None
        self._stopped_since = 0.0

    # -- the toggle service -------------------------------------------------------------------

    def serve(self, services: dict[str, Callable[..., Any]]) -> None:
        """Offer :meth:`toggle` in ``services`` (a navigation server's) as Nav2 names it."""
        services[COLLISION_MONITOR_TOGGLE] = self.toggle

    def toggle(self, enable: bool) -> tuple[bool, str]:
        """``collision_monitor/toggle``: zones on (True) or off; ``(success, message)``."""
        self.enabled = bool(enable)
        self._record(self.state.action_type, self.state.polygon_name)
        return True, f"Collision monitor toggled {'on' if self.enabled else 'off'} successfully"

    # -- processing ---------------------------------------------------------------------------

    def process(self, linear: float, angular: float) -> tuple[float, float]:
        """Check the command ``(linear, angular)`` (m/s, rad/s), send the result to the base
        and return it."""
        now = self._sim.time
        points: dict[str, np.ndarray] = {}
        action, name = ActionType.DO_NOTHING, ""
        out = (linear, angular)
        for source_name, source in self.sources.items():
            if not source.params.enabled:
                continue
            data = source.points(now, self.params.base_shift_correction)
            if data is None:
                action, name, out = ActionType.STOP, INVALID_SOURCE, (0.0, 0.0)
                break
            points[source_name] = data
        if action is not ActionType.STOP and self.enabled:
            action, name, out = self._evaluate(points, linear, angular)
        self._account(now, action)
        self._record(action, name)
        self._publish(now, out)
        return out

    def _evaluate(
        self, points: dict[str, np.ndarray], linear: float, angular: float
    ) -> tuple[ActionType, str, tuple[float, float]]:
        """The zones' verdict on the command: action, zone name, safe command."""
        action, name, out = ActionType.DO_NOTHING, "", (linear, angular)
        everything = np.concatenate(list(points.values())) if points else np.empty((0, 2))
        for zone in self.zones:
            params = zone.params
            if not params.enabled:
                continue
            if action is ActionType.STOP:
                break
            zone.update_shape(linear, angular)
            seen = everything
            if params.sources_names is not None:
                chosen = [points[s] for s in params.sources_names if s in points]
                seen = np.concatenate(chosen) if chosen else np.empty((0, 2))
            safe = self._safe_command(zone, seen, linear, angular)
            if safe is None:
                continue
            kind = params.action_type
            if kind is ActionType.STOP or _magnitude(safe) < _magnitude(out):
                action, name, out = kind, params.name, safe
        return action, name, out

    @staticmethod
    def _safe_command(
        zone: Zone, points: np.ndarray, linear: float, angular: float
    ) -> tuple[float, float] | None:
        """What ``zone`` makes of the command, or None when it does not act."""
        params = zone.params
        kind = params.action_type
        if kind is ActionType.APPROACH:
            time = zone.collision_time(points, linear, angular)
            if time is None:
                return None
            ratio = time / params.time_before_collision
            return linear * ratio, angular * ratio
        if not zone.triggered(points) or kind is ActionType.DO_NOTHING:
            return None
        if kind is ActionType.STOP:
            return 0.0, 0.0
        if kind is ActionType.SLOWDOWN:
            ratio = params.slowdown_ratio
        else:  # LIMIT
            ratio = 1.0
            if linear != 0.0:
                ratio = min(ratio, params.linear_limit / abs(linear))
            if angular != 0.0:
                ratio = min(ratio, params.angular_limit / abs(angular))
        return linear * ratio, angular * ratio

    def _publish(self, now: float, out: tuple[float, float]) -> None:
        """Send ``out`` to the base, except zeros once stopped for ``stop_pub_timeout`` s."""
        zero = out == (0.0, 0.0)
        if zero:
            if self.last_output != (0.0, 0.0):
                self._stopped_since = now
            elif now - self._stopped_since > self.params.stop_pub_timeout:
                return
        self.last_output = out
        if zero:
            self._base.stop()
        else:
            self._base.command(*out)

    def _account(self, now: float, action: ActionType) -> None:
        if self._last_process is not None and self.state.action_type is not ActionType.DO_NOTHING:
            self.acting_time += now - self._last_process
        self._last_process = now
        if action is ActionType.STOP and self.state.action_type is not ActionType.STOP:
            self.stops += 1

    def _record(self, action: ActionType, name: str) -> None:
        state = MonitorState(action, name, self.enabled)
        if state != self.state:
            self.state = state
            self.changes.append(MonitorChange(self._sim.time, state))

    def close(self) -> None:
        """Stop reading the lidar."""
        for source in self.sources.values():
            self._lidar.unsubscribe(source.on_scan)


def _magnitude(command: tuple[float, float]) -> float:
    """Nav2's ordering of velocities: ``vx^2 + vy^2 + w^2`` (a base without ``vy``)."""
    linear, angular = command
    return linear * linear + angular * angular
