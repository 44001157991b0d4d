"""The collision monitor on a TurtleBot3 in MuJoCo: a box spawned in the stop zone stops the
robot within one control period of the first scan that sees it, without contact; a slowdown
zone scales the speed the robot reaches; toggled off, a navigation run is the controller's
alone (sim time, real physics)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from navigation_rig import ContactWatch

from baobab.missions.language.loader import load_mission
from baobab.missions.run.event_targets import ObstacleSlots
from baobab.missions.run.runner import RunRecord, run_mission
from baobab.nav.collision_monitor import CollisionMonitor
from baobab.nav.collision_monitor_config import parse_collision_monitor
from baobab.robots.footprint import Footprint
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.lidar import LaserScan
from baobab.sim.world import Floor, Pose2D, World

CONTROL_PERIOD = 0.05
"""The driver's period (s): Nav2's controller_frequency 20 Hz."""
SPEED = 0.2
"""What the driver commands (m/s)."""
OPEN_FLOOR = World(
    name="open", floor=Floor(size=(8.0, 8.0)), spawns={"default": Pose2D(x=-2.0, y=0.0)}
)


class RecordingBase:
    """The robot's base, remembering each command that reaches it with its sim time."""

    def __init__(self, base: Any, clock: Any) -> None:
        self._base, self._clock = base, clock
        self.sent: list[tuple[float, float, float]] = []

    def pose(self) -> Pose2D:
        return self._base.pose()

    def body_velocity(self) -> tuple[float, float]:
        return self._base.body_velocity()

    def command(self, linear: float, angular: float) -> None:
        self.sent.append((self._clock.time, linear, angular))
        self._base.command(linear, angular)

    def stop(self) -> None:
        self.sent.append((self._clock.time, 0.0, 0.0))
        self._base.stop()


class Drive:
    """A robot on the open floor that a driver commands at 20 Hz through its monitor."""

    def __init__(self, polygons: dict[str, dict[str, Any]]) -> None:
        block = {
            "polygons": list(polygons),
            **polygons,
            "observation_sources": ["scan"],
            "scan": {"type": "scan", "topic": "/scan"},
        }
        self.sim, self.robot = build_turtlebot3_sim(OPEN_FLOOR)
        self.base = RecordingBase(self.robot.base, self.sim)
        self.monitor = CollisionMonitor(
            self.sim,
            self.base,
            self.robot.lidar,
            parse_collision_monitor(block),
            Footprint.circle(0.105),
        )
        self.scans: list[float] = []
        self.robot.lidar.subscribe(self._on_scan)
        self.contacts = ContactWatch(self.sim, self.robot.names.body)
        self.obstacles = ObstacleSlots(self.sim)
        self.sim.every(CONTROL_PERIOD, self._drive, name="driver")

    def _drive(self, _now: float) -> None:
        self.monitor.base.command(SPEED, 0.0)

    def _on_scan(self, scan: LaserScan) -> None:
        self.scans.append(scan.stamp)

    def box_ahead(self, gap: float, size: float = 0.1) -> float:
        """Spawn a ``size`` m box whose near face is ``gap`` m ahead of the robot's front;
        the x (m) of that face."""
        pose = self.robot.base.pose()
        face = pose.x + 0.105 + gap
        self.obstacles.spawn("box", face + size / 2, pose.y, 0.0, (size, size, 0.3))
        return face


def test_a_box_spawned_in_the_stop_zone_stops_the_robot_within_a_control_period() -> None:
    drive = Drive({"PolygonStop": {"type": "circle", "radius": 0.35, "action_type": "stop"}})
    drive.sim.step_for(3.03)  # up to speed, between two scans
    spawned = drive.sim.time
    face = drive.box_ahead(gap=0.15)
    drive.sim.step_for(3.0)
    seen = min(stamp for stamp in drive.scans if stamp >= spawned)
    zeros = [t for t, linear, angular in drive.base.sent if t >= spawned and linear == 0.0]
    assert zeros and zeros[0] - seen <= CONTROL_PERIOD + 1e-9
    after = [(linear, angular) for t, linear, angular in drive.base.sent if t >= zeros[0]]
    assert set(after) == {(0.0, 0.0)}
    assert drive.monitor.stops == 1
    assert drive.contacts.touched == set()
    linear, _ = drive.robot.base.body_velocity()
    assert abs(linear) < 1e-3
    assert face - (drive.robot.base.pose().x + 0.105) > 0.05


@pytest.mark.parametrize("ratio", [0.3, 0.6])
def test_a_slowdown_zone_scales_the_speed_the_robot_reaches(ratio: float) -> None:
    zone = {
        "type": "polygon",
        "points": "[[1.5, 0.4], [1.5, -0.4], [0.0, -0.4], [0.0, 0.4]]",
        "action_type": "slowdown",
        "slowdown_ratio": ratio,
    }
    drive = Drive({"PolygonSlow": zone})
    drive.box_ahead(gap=1.0, size=0.3)
    drive.sim.step_for(2.0)
    sent = [linear for t, linear, _ in drive.base.sent if t > 0.0]
    assert sent == pytest.approx([SPEED * ratio] * len(sent))
    speeds = []
    for _ in range(20):
        drive.sim.step_for(0.05)
        speeds.append(drive.robot.base.body_velocity()[0])
    assert sum(speeds) / len(speeds) == pytest.approx(SPEED * ratio, rel=0.03)
    assert drive.contacts.touched == set()


# --- toggled off, the controller's own checks act alone (a mission run) ----------------------
# A box drops 0.15 m ahead of the robot while it navigates. Without a monitor, the controller's
# costmap checks steer it round the box; with the monitor toggled off the run is the same, pose
# for pose; on, the stop circle holds the robot where it is.

MISSION = """
mission: guarded_corridor
world: walls
robot: turtlebot3
start: {x: -1.0, y: -0.5, yaw: 0.0}
seed: 5
tree:
  sequence:
    - TOGGLE
    - navigate_to_pose: {x: 0.7, y: -0.5}
events:
  - {at: 2.0, spawn_obstacle: {name: box1, x: -0.3, y: -0.5, size: [0.2, 0.2, 0.4]}}
timeout: 60
"""
MONITOR = """
collision_monitor:
  polygons: [PolygonStop]
  PolygonStop: {type: circle, radius: 0.3, action_type: stop}
  observation_sources: [scan]
  scan: {type: scan, topic: /scan}
"""


def _run(tmp_path: Path, name: str, toggle: str, monitor: bool) -> tuple[list[str], RunRecord]:
    """The pose records of the mission run with ``toggle`` first, with or without a monitor."""
    body = MISSION.replace("- TOGGLE", toggle) + (MONITOR if monitor else "")
    path = tmp_path / f"{name}.yaml"
    path.write_text(body, encoding="utf-8")
    record = run_mission(load_mission(path))
    return [line for line in record.trace.lines if '"type":"pose"' in line], record


def test_toggled_off_the_run_is_the_controllers_alone(tmp_path: Path) -> None:
    alone, alone_record = _run(tmp_path, "alone", "- always_success: {}", monitor=False)
    off, off_record = _run(tmp_path, "off", "- toggle_collision_monitor: false", monitor=True)
    on, on_record = _run(tmp_path, "on", "- toggle_collision_monitor: true", monitor=True)
    assert off == alone  # the monitor passed every command unchanged
    assert off_record.metrics["collision_monitor_stops"] == 0
    assert off_record.outcome.result == alone_record.outcome.result == "SUCCEEDED"
    assert on != alone and on_record.metrics["collision_monitor_stops"] >= 1
