"""Nav2's collision monitor on its own: each action's command, min_points, the debounce, the
safest-wins rule, the toggle, stale sources and stop_pub_timeout (a scripted scan and base,
no physics; the sim-time figures are exact)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import pytest

from baobab.nav.collision_monitor import INVALID_SOURCE, CollisionMonitor
from baobab.nav.collision_monitor_config import parse_collision_monitor
from baobab.nav.collision_monitor_params import ActionType
from baobab.robots.footprint import Footprint
from baobab.sim.lidar import LaserScan
from baobab.sim.world import Pose2D

BEAMS = 720
"""Beams of the scripted scan (0.5 degree apart)."""
FOOTPRINT = Footprint.circle(0.105)
STOP_AHEAD = {"type": "polygon", "points": "[[0.4, 0.2], [0.4, -0.2], [0.0, -0.2], [0.0, 0.2]]"}
SLOW_AHEAD = {"type": "polygon", "points": "[[0.8, 0.3], [0.8, -0.3], [0.0, -0.3], [0.0, 0.3]]"}


class Clock:
    """The monitor's simulation: only its time (s) is read."""

    time = 0.0


class Base:
    """A base that records what reaches it."""

    def __init__(self) -> None:
        self.at = Pose2D(x=0.0, y=0.0)
        self.sent: list[tuple[float, float]] = []

    def pose(self) -> Pose2D:
        return self.at

    def body_velocity(self) -> tuple[float, float]:
        return (0.0, 0.0)

    def command(self, linear: float, angular: float) -> None:
        self.sent.append((linear, angular))

    def stop(self) -> None:
        self.sent.append((0.0, 0.0))


class Lidar:
    """A scanner that publishes what the test gives it, from the base's pose."""

    def __init__(self, base: Base, clock: Clock) -> None:
        self.subscribers: list[Any] = []
        self._base, self._clock = base, clock

    def subscribe(self, subscriber: Any) -> None:
        self.subscribers.append(subscriber)

    def unsubscribe(self, subscriber: Any) -> None:
        self.subscribers.remove(subscriber)

    def publish(self, points: Sequence[tuple[float, float]]) -> None:
        """A scan that returns at ``points`` (m, base frame; at most one per beam)."""
        ranges = np.full(BEAMS, np.inf)
        increment = 2 * math.pi / BEAMS
        for x, y in points:
            beam = round((math.atan2(y, x) + math.pi) / increment) % BEAMS
            assert math.isinf(ranges[beam]), "two points on one beam"
            angle = -math.pi + beam * increment
            distance = math.hypot(x, y)
            ranges[beam] = distance
            assert abs(angle - math.atan2(y, x)) < 1e-9 or distance < 1e-9, (x, y)
        scan = LaserScan(
            stamp=self._clock.time,
            frame_id="base_scan",
            angle_min=-math.pi,
            angle_max=math.pi - increment,
            angle_increment=increment,
            range_min=0.05,
            range_max=3.5,
            ranges=ranges,
            sensor_pose=self._base.at,
        )
        for subscriber in self.subscribers:
            subscriber(scan)


def on_beams(x: float, y_values: Sequence[float]) -> list[tuple[float, float]]:
    """Points at ``x`` whose bearings are whole beams (the nearest beam to each ``y``)."""
    increment = 2 * math.pi / BEAMS
    points = []
    for y in y_values:
        angle = round(math.atan2(y, x) / increment) * increment
        points.append((x, x * math.tan(angle)))
    return points


def wall_at(x: float, count: int = 8, half_width: float = 0.05) -> list[tuple[float, float]]:
    """``count`` returns across ``2 * half_width`` m at ``x`` m ahead."""
    return on_beams(x, np.linspace(-half_width, half_width, count).tolist())


def monitor(polygons: dict[str, dict[str, Any]], **node: Any) -> tuple[CollisionMonitor, Any]:
    block = {
        "polygons": list(polygons),
        **polygons,
        "observation_sources": ["scan"],
        "scan": {"type": "scan", "topic": "/scan"},
        **node,
    }
    clock, base = Clock(), Base()
    lidar = Lidar(base, clock)
    built = CollisionMonitor(
        clock,  # type: ignore[arg-type]
        base,
        lidar,
        parse_collision_monitor(block),
        FOOTPRINT,
    )
    return built, (clock, base, lidar)


def test_a_stop_zone_zeroes_commands_while_min_points_are_inside() -> None:
    cm, (_, base, lidar) = monitor({"PolygonStop": {**STOP_AHEAD, "action_type": "stop"}})
    lidar.publish(wall_at(1.0))
    assert cm.base.command(0.2, 0.1) is None and base.sent == [(0.2, 0.1)]
    lidar.publish(wall_at(0.3))
    cm.base.command(0.2, 0.1)
    assert base.sent[-1] == (0.0, 0.0)
    assert (cm.state.action_type, cm.state.polygon_name) == (ActionType.STOP, "PolygonStop")
    assert cm.stops == 1
    lidar.publish(wall_at(1.0))
    cm.base.command(0.2, 0.1)
    assert base.sent[-1] == (0.2, 0.1) and cm.state.action_type is ActionType.DO_NOTHING


@pytest.mark.parametrize(("inside", "min_points", "stops"), [(3, 4, False), (4, 4, True)])
def test_min_points_decides(inside: int, min_points: int, stops: bool) -> None:
    zone = {**STOP_AHEAD, "action_type": "stop", "min_points": min_points}
    cm, (_, base, lidar) = monitor({"PolygonStop": zone})
    beside = on_beams(0.3, np.linspace(0.3, 0.9, 10).tolist())  # outside the zone
    lidar.publish(wall_at(0.3, count=inside) + beside)
    cm.base.command(0.2, 0.0)
    assert (base.sent[-1] == (0.0, 0.0)) is stops


def test_humbles_max_points_is_min_points_minus_one() -> None:
    zone = {**STOP_AHEAD, "action_type": "stop", "max_points": 2}
    cm, (_, base, lidar) = monitor({"PolygonStop": zone})
    lidar.publish(wall_at(0.3, count=3))
    cm.base.command(0.2, 0.0)
    assert base.sent[-1] == (0.0, 0.0)
    assert cm.params.polygons[0].min_points == 3


@pytest.mark.parametrize("ratio", [0.3, 0.5, 0.75])
def test_slowdown_scales_the_command_by_slowdown_ratio(ratio: float) -> None:
    zone = {**SLOW_AHEAD, "action_type": "slowdown", "slowdown_ratio": ratio}
    cm, (_, base, lidar) = monitor({"PolygonSlow": zone})
    lidar.publish(wall_at(0.6))
    cm.base.command(0.2, -0.4)
    assert base.sent[-1] == pytest.approx((0.2 * ratio, -0.4 * ratio), abs=1e-12)
    assert cm.state.action_type is ActionType.SLOWDOWN


def test_limit_caps_speeds_and_keeps_the_curvature() -> None:
    zone = {**SLOW_AHEAD, "action_type": "limit", "linear_limit": 0.1, "angular_limit": 0.5}
    cm, (_, base, lidar) = monitor({"PolygonLimit": zone})
    lidar.publish(wall_at(0.6))
    cm.base.command(0.2, 0.2)  # linear bounds: ratio 0.5
    assert base.sent[-1] == pytest.approx((0.1, 0.1))
    cm.base.command(0.05, 1.0)  # angular bounds: ratio 0.5
    assert base.sent[-1] == pytest.approx((0.025, 0.5))
    cm.base.command(0.05, 0.1)  # within both: unchanged, and not acting
    assert base.sent[-1] == (0.05, 0.1)


def test_approach_scales_by_the_time_to_collision() -> None:
    zone = {"type": "polygon", "action_type": "approach", "time_before_collision": 2.0}
    cm, (_, base, lidar) = monitor({"FootprintApproach": zone})
    # a wall 0.31 m ahead: at 0.2 m/s the footprint (radius 0.105) holds it after the 11th
    # step of 0.1 s; as Nav2, the time before the collision is that step's start, 1.0 s
    lidar.publish(wall_at(0.31, count=8, half_width=0.02))
    cm.base.command(0.2, 0.0)
    assert base.sent[-1] == pytest.approx((0.2 * 1.0 / 2.0, 0.0))
    assert cm.state.action_type is ActionType.APPROACH
    cm.base.command(0.05, 0.0)  # slow enough: no collision within 2 s
    assert base.sent[-1] == (0.05, 0.0)
    lidar.publish(wall_at(0.1, count=8, half_width=0.02))  # inside the footprint: stop
    cm.base.command(0.05, 0.0)
    assert base.sent[-1] == (0.0, 0.0)
    cm.base.command(-0.05, 0.0)  # backing away from it: the first step is clear, as in Nav2
    assert base.sent[-1] == (-0.05, 0.0)


def test_approach_follows_a_turning_command() -> None:
    zone = {"type": "circle", "radius": 0.105, "action_type": "approach"}
    cm, (_, base, lidar) = monitor({"FootprintApproach": zone})
    lidar.publish(wall_at(0.45, count=8, half_width=0.02))
    cm.base.command(0.2, 0.0)  # straight at the wall: it comes within 2 s
    assert base.sent[-1][0] < 0.2
    cm.base.command(0.2, 1.5)  # turning away on a 0.13 m radius: it never comes
    assert base.sent[-1] == (0.2, 1.5)


def test_the_safest_command_wins_and_a_stop_ends_the_evaluation() -> None:
    polygons = {
        "PolygonSlow": {**SLOW_AHEAD, "action_type": "slowdown", "slowdown_ratio": 0.5},
        "PolygonLimit": {**SLOW_AHEAD, "action_type": "limit", "linear_limit": 0.05},
        "PolygonStop": {**STOP_AHEAD, "action_type": "stop"},
    }
    cm, (_, base, lidar) = monitor(polygons)
    lidar.publish(wall_at(0.6))
    cm.base.command(0.2, 0.0)
    assert base.sent[-1] == pytest.approx((0.05, 0.0))
    assert cm.state.polygon_name == "PolygonLimit"
    lidar.publish(wall_at(0.3))
    cm.base.command(0.2, 0.0)
    assert base.sent[-1] == (0.0, 0.0) and cm.state.polygon_name == "PolygonStop"


def test_consecutive_points_debounce_trigger_and_release() -> None:
    zone = {
        **STOP_AHEAD,
        "action_type": "stop",
        "trigger_consecutive_points": 2,
        "release_consecutive_points": 3,
    }
    cm, (_, _, lidar) = monitor({"PolygonStop": zone})
    lidar.publish(wall_at(0.3))
    outputs = []
    for step in range(6):
        if step == 2:
            lidar.publish(wall_at(1.0))
        outputs.append(cm.process(0.2, 0.0))
    assert outputs == [(0.2, 0.0), (0.0, 0.0), (0.0, 0.0), (0.0, 0.0), (0.2, 0.0), (0.2, 0.0)]


def test_toggled_off_commands_pass_and_on_again_the_zones_act() -> None:
    cm, (_, base, lidar) = monitor({"PolygonStop": {**STOP_AHEAD, "action_type": "stop"}})
    lidar.publish(wall_at(0.3))
    assert cm.toggle(False) == (True, "Collision monitor toggled off successfully")
    cm.base.command(0.2, 0.1)
    assert base.sent[-1] == (0.2, 0.1)
    assert cm.state.enabled is False and cm.state.action_type is ActionType.DO_NOTHING
    assert cm.toggle(True)[0]
    cm.base.command(0.2, 0.1)
    assert base.sent[-1] == (0.0, 0.0)


def test_enabled_false_starts_it_off() -> None:
    cm, (_, base, lidar) = monitor(
        {"PolygonStop": {**STOP_AHEAD, "action_type": "stop"}}, enabled=False
    )
    lidar.publish(wall_at(0.3))
    cm.base.command(0.2, 0.0)
    assert base.sent[-1] == (0.2, 0.0)


def test_stale_or_missing_data_stops_the_robot_even_toggled_off() -> None:
    cm, (clock, base, lidar) = monitor(
        {"PolygonStop": {**STOP_AHEAD, "action_type": "stop"}}, source_timeout=0.5
    )
    cm.toggle(False)
    cm.base.command(0.2, 0.0)  # no scan yet
    assert base.sent[-1] == (0.0, 0.0) and cm.state.polygon_name == INVALID_SOURCE
    lidar.publish(wall_at(2.0, half_width=0.3))
    clock.time = 0.5
    cm.base.command(0.2, 0.0)
    assert base.sent[-1] == (0.2, 0.0)
    clock.time = 0.51
    cm.base.command(0.2, 0.0)
    assert base.sent[-1] == (0.0, 0.0)


def test_zeros_stop_being_sent_after_stop_pub_timeout() -> None:
    cm, (clock, base, lidar) = monitor(
        {"PolygonStop": {**STOP_AHEAD, "action_type": "stop"}},
        stop_pub_timeout=0.2,
        source_timeout=0.0,
    )
    lidar.publish(wall_at(0.3))
    for step in range(6):
        clock.time = 0.1 * step
        cm.base.command(0.2, 0.0)
    assert base.sent == [(0.0, 0.0)] * 3  # at 0.0, 0.1 and 0.2 s; not after


def test_zones_see_only_their_sources_names_and_disabled_sources_are_skipped() -> None:
    block = {
        "polygons": ["PolygonStop", "PolygonSlow"],
        "PolygonStop": {**STOP_AHEAD, "action_type": "stop", "sources_names": ["spare"]},
        "PolygonSlow": {**SLOW_AHEAD, "action_type": "slowdown", "sources_names": ["scan"]},
        "observation_sources": ["scan", "spare"],
        "scan": {"type": "scan"},
        "spare": {"type": "scan", "topic": "scan", "enabled": False},
    }
    clock, base = Clock(), Base()
    lidar = Lidar(base, clock)
    cm = CollisionMonitor(clock, base, lidar, parse_collision_monitor(block), FOOTPRINT)  # type: ignore[arg-type]
    lidar.publish(wall_at(0.3))
    cm.base.command(0.2, 0.0)
    assert base.sent[-1] == pytest.approx((0.1, 0.0))  # the stop zone sees no source


def test_base_shift_correction_moves_old_points_with_the_robot() -> None:
    zone = {**STOP_AHEAD, "action_type": "stop"}
    shifted, (_, base, lidar) = monitor({"PolygonStop": zone})
    kept, (_, kept_base, kept_lidar) = monitor({"PolygonStop": zone}, base_shift_correction=False)
    for one_base, one_lidar in ((base, lidar), (kept_base, kept_lidar)):
        one_lidar.publish(wall_at(0.6))
        one_base.at = Pose2D(x=0.3, y=0.0)  # the robot drove 0.3 m since the scan
    shifted.base.command(0.2, 0.0)
    kept.base.command(0.2, 0.0)
    assert base.sent[-1] == (0.0, 0.0)  # the wall is 0.3 m ahead now
    assert kept_base.sent[-1] == (0.2, 0.0)  # as scanned: 0.6 m ahead


def test_state_changes_are_kept_with_their_sim_time() -> None:
    cm, (clock, _, lidar) = monitor({"PolygonStop": {**STOP_AHEAD, "action_type": "stop"}})
    lidar.publish(wall_at(0.3))
    clock.time = 1.5
    cm.base.command(0.2, 0.0)
    clock.time = 2.0
    cm.toggle(False)
    states = [
        (c.time, c.state.action_type, c.state.polygon_name, c.state.enabled) for c in cm.changes
    ]
    assert states == [
        (0.0, ActionType.DO_NOTHING, "", True),
        (1.5, ActionType.STOP, "PolygonStop", True),
        (2.0, ActionType.STOP, "PolygonStop", False),
    ]
    cm.close()
    assert lidar.subscribers == []


def test_a_velocity_polygon_takes_the_sub_polygon_the_command_falls_in() -> None:
    zone = {
        "type": "velocity_polygon",
        "action_type": "stop",
        "velocity_polygons": ["rotation", "forward"],
        "rotation": {
            "points": "[[0.15, 0.15], [0.15, -0.15], [-0.15, -0.15], [-0.15, 0.15]]",
            "linear_min": 0.0,
            "linear_max": 0.05,
            "theta_min": -1.0,
            "theta_max": 1.0,
        },
        "forward": {
            "points": "[[0.5, 0.2], [0.5, -0.2], [0.0, -0.2], [0.0, 0.2]]",
            "linear_min": 0.05,
            "linear_max": 0.3,
            "theta_min": -1.0,
            "theta_max": 1.0,
        },
    }
    cm, (_, base, lidar) = monitor({"VelocityPolygonStop": zone})
    lidar.publish(wall_at(0.4))
    cm.base.command(0.02, 0.5)  # turning: the small square, the wall is outside
    assert base.sent[-1] == (0.02, 0.5)
    cm.base.command(0.2, 0.0)  # driving: the long box ahead holds the wall
    assert base.sent[-1] == (0.0, 0.0)
    cm.base.command(0.5, 0.0)  # in no range: the last one chosen stays
    assert base.sent[-1] == (0.0, 0.0)
