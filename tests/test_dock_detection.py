"""The lidar dock detector: the charger's outline fitted to a real scan, never ground truth."""

from __future__ import annotations

import math

import pytest

from baobab.nav.dock_detection import DetectorParams, DockDetector
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.docks import Dock
from baobab.sim.world import Floor, Pose2D, World

DOCK = Dock(pose=(1.5, 0.3, 0.4))


def _world(dock: Dock | None = DOCK) -> World:
    return World(
        name="dock_room",
        floor=Floor(size=(5.0, 4.0)),
        spawns={"default": Pose2D(x=0.0, y=0.0)},
        docks={} if dock is None else {"home": dock},
    )


def _scan_from(world: World, back: float, side: float, turn: float):  # type: ignore[no-untyped-def]
    """A scan taken ``back`` m before the dock, ``side`` m to its left, turned by ``turn``."""
    x, y = DOCK.to_map(-back, side)
    sim, robot = build_turtlebot3_sim(world, Pose2D(x=x, y=y, yaw=DOCK.yaw + turn))
    sim.step_for(0.3)
    return robot.lidar.scan()


@pytest.mark.parametrize(
    ("back", "side", "turn"), [(0.7, 0.0, 0.0), (0.45, 0.08, -0.2), (0.25, -0.03, 0.1)]
)
@pytest.mark.parametrize(
    ("dx", "dy", "dyaw"), [(0.0, 0.0, 0.0), (0.15, -0.1, 0.2), (-0.2, 0.12, -0.3)]
)
def test_the_dock_is_found_within_a_centimetre_from_an_expected_pose_off_by_the_tolerance(
    back: float, side: float, turn: float, dx: float, dy: float, dyaw: float
) -> None:
    scan = _scan_from(_world(), back, side, turn)
    expected = Pose2D(x=DOCK.x + dx, y=DOCK.y + dy, yaw=DOCK.yaw + dyaw)
    found = DockDetector(expected).detect(scan)
    assert found is not None
    assert math.hypot(found.x - DOCK.x, found.y - DOCK.y) < 0.01
    assert abs(math.remainder(found.yaw - DOCK.yaw, math.tau)) < 0.02


def test_a_dock_farther_than_the_stated_tolerance_is_not_found() -> None:
    scan = _scan_from(_world(), 0.7, 0.0, 0.0)
    params = DetectorParams()
    expected = Pose2D(x=DOCK.x, y=DOCK.y + params.search_radius + 0.15, yaw=DOCK.yaw)
    assert DockDetector(expected, params).detect(scan) is None


def test_no_dock_no_detection() -> None:
    scan = _scan_from(_world(None), 0.7, 0.0, 0.0)
    assert DockDetector(Pose2D(x=DOCK.x, y=DOCK.y, yaw=DOCK.yaw)).detect(scan) is None


def test_a_later_scan_refines_the_last_detection() -> None:
    detector = DockDetector(Pose2D(x=DOCK.x + 0.1, y=DOCK.y, yaw=DOCK.yaw))
    assert detector.detect(_scan_from(_world(), 0.7, 0.0, 0.0)) is not None
    again = detector.detect(_scan_from(_world(), 0.3, 0.02, 0.05))
    assert again is not None and math.hypot(again.x - DOCK.x, again.y - DOCK.y) < 0.01
