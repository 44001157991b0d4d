"""Assisted teleop: Nav2's collision projection on the real robot, its endings, the 2 Hz costmap
clearing, the bundled mission.

The rule (reference/nav2.md §5.4): each 10 Hz cycle the teleop twist is integrated ahead in
0.1 s steps up to 1.0 s; a collision at the first step sends zero, at time t the twist is
scaled by t / 1.0 s. The footprint checked is the costmap's inscribed radius (0.105 m) plus
a 0.05 m padding, exactly against lethal cells, so the robot stops with the padding to spare.
All runs are real physics on sim time; contacts are watched every 10 ms.
"""

from __future__ import annotations

import json
import math
from importlib import resources
from pathlib import Path

import numpy as np
import pytest
from navigation_rig import NavRig, make_rig

from baobab.missions.language.loader import load_mission
from baobab.missions.run.runner import run_mission
from baobab.nav.assisted_teleop import AssistedTeleop
from baobab.nav.behaviors import BehaviorContext, BehaviorParams
from baobab.nav.costmap import LETHAL_OBSTACLE, Costmap2D
from baobab.nav.errors import AssistedTeleopError
from baobab.nav.server import NavigationParams, NavigationServer
from baobab.sim.tasks import TaskHandle, TaskStatus
from baobab.sim.world import Pose2D

EAST_FACE = 3.0
"""x (m) of the walls world's outer east wall face, the wall these tests drive at."""
PADDING = BehaviorParams().teleop_footprint_padding
MISSION = Path(str(resources.files("baobab.missions"))) / "assisted_teleop.yaml"


class FakeBase:
    """A base standing still at ``pose``, remembering its last command."""

    def __init__(self, pose: Pose2D) -> None:
        self._pose = pose
        self.sent: tuple[float, float] | None = None

    def pose(self) -> Pose2D:
        return self._pose

    def body_velocity(self) -> tuple[float, float]:
        return (0.0, 0.0)

    def command(self, linear: float, angular: float) -> None:
        self.sent = (linear, angular)

    def stop(self) -> None:
        self.sent = (0.0, 0.0)


def _wall_costmap(face: float) -> Costmap2D:
    """A 4 m x 2 m costmap, lethal for x >= ``face`` (a multiple of the 0.05 m cells)."""
    costmap = Costmap2D(80, 40, 0.05, origin=(0.0, -1.0), inscribed_radius=0.105)
    costmap.data[:, round(face / 0.05) :] = LETHAL_OBSTACLE
    return costmap


@pytest.mark.parametrize(
    ("gap", "linear", "angular", "expected"),
    [
        # gap: distance (m) from the padded footprint's edge to the wall ahead
        (0.50, 0.25, 0.0, 1.0),  # 1.0 s ahead reaches 0.25 m: no collision, full command
        (0.21, 0.25, 0.0, 0.9),  # the first collision is at the 9th step: 0.9 s
        (0.11, 0.25, 0.0, 0.5),  # 5th step
        (0.03, 0.25, 0.0, 0.2),  # 2nd step
        (0.02, 0.25, 0.0, 0.0),  # 1st step: zero
        (0.02, -0.25, 0.0, 1.0),  # backing away
        (0.02, 0.0, 1.2, 1.0),  # turning in place
    ],
)
def test_the_scaling_rule_on_a_known_wall(
    gap: float, linear: float, angular: float, expected: float
) -> None:
    radius = 0.105 + PADDING
    base = FakeBase(Pose2D(x=2.0 - radius - gap, y=0.0, yaw=0.0))
    costmap = _wall_costmap(2.0)
    behavior = AssistedTeleop(BehaviorContext(base, lambda: costmap))
    behavior.context.teleop.linear, behavior.context.teleop.angular = linear, angular
    assert behavior.tick(0.0) is None
    assert behavior.feedback["scaling"] == pytest.approx(expected)
    assert base.sent == pytest.approx((linear * expected, angular * expected))


def _approach(rig: NavRig, handle: TaskHandle, limit: float) -> tuple[float, list[float]]:
    """Step until the robot is stopped by the projection; the least clearance and the scalings."""
    base = rig.robot.base
    least, scalings, still = math.inf, [], 0
    while still < 10:
        assert rig.sim.time < limit, "the robot did not come to rest"
        rig.sim.step_for(0.05)
        least = min(least, base.min_clearance())
        scalings.append(handle.feedback["scaling"])
        still = still + 1 if scalings[-1] == 0.0 and abs(base.body_velocity()[0]) < 1e-3 else 0
    assert handle.status is TaskStatus.RUNNING
    return least, scalings


@pytest.mark.parametrize("speed", [0.1, 0.18, 0.25])
@pytest.mark.parametrize("angle_deg", [0, 30, -30, 60, -60])
def test_head_on_approach_stops_before_the_wall(speed: float, angle_deg: int) -> None:
    start = Pose2D(x=EAST_FACE - 0.45, y=0.8, yaw=math.radians(angle_deg))
    rig = make_rig("walls", start)
    handle = rig.server.assisted_teleop(0.0)
    rig.server.teleop_command(speed, 0.0)
    least, scalings = _approach(rig, handle, limit=15.0)
    pose = rig.pose()
    assert rig.contacts.touched == set()
    assert rig.contacts.checks >= round(rig.sim.time / 0.01)  # every 10 ms all along
    assert least > 0.0
    assert least >= PADDING - 0.005  # the padding, up to the wheel-speed ramp
    final = rig.robot.base.min_clearance()
    assert final < PADDING + 0.03  # it did drive up to the wall
    assert math.hypot(pose.x - start.x, pose.y - start.y) > 0.2
    assert any(0.0 < s < 1.0 for s in scalings)  # slowed down before it stopped
    assert abs(math.remainder(pose.yaw - start.yaw, 2 * math.pi)) < 0.01


@pytest.mark.parametrize(("yaw", "speed"), [(math.pi, 0.25), (0.0, -0.25)])
def test_driving_away_from_a_wall_is_never_slowed(yaw: float, speed: float) -> None:
    rig = make_rig("walls", Pose2D(x=EAST_FACE - 0.25, y=0.8, yaw=yaw))
    handle = rig.server.assisted_teleop(0.0)
    rig.server.teleop_command(speed, 0.0)
    scalings = []
    for _ in range(20):
        rig.sim.step_for(0.1)
        scalings.append(handle.feedback["scaling"])
    assert scalings == [1.0] * 20
    stats = rig.server.teleop_stats
    assert (stats.min_scaling, stats.slowed_cycles, stats.stopped_cycles) == (1.0, 0, 0)
    top = rig.robot.base.facts.max_linear_speed  # 0.22 m/s: the base clips 0.25
    ramp = top**2 / (2 * rig.robot.base.facts.max_linear_accel)
    full = top * 2.0 - ramp  # 2 s at full speed, less the ramp up
    assert EAST_FACE - 0.25 - rig.pose().x == pytest.approx(full, abs=0.005)
    assert rig.contacts.touched == set()


@pytest.mark.parametrize("gap", [0.06, 0.025])
def test_turning_in_place_next_to_a_wall_is_allowed(gap: float) -> None:
    # Facing the wall with ``gap`` m to spare; 0.025 m is inside the padding already.
    rig = make_rig("walls", Pose2D(x=EAST_FACE - 0.105 - gap, y=0.8, yaw=0.0))
    handle = rig.server.assisted_teleop(0.0)
    rig.server.teleop_command(0.2, 0.0)
    rig.sim.step_for(0.3)
    assert handle.feedback["scaling"] == 0.0  # forward: the first 0.1 s step is too close
    rig.server.teleop_command(-0.2, 0.0)
    rig.sim.step_for(0.3)
    assert handle.feedback["scaling"] == 1.0  # backing away is allowed
    rig.server.teleop_command(0.0, 0.0)
    rig.sim.step_for(0.3)
    start = rig.pose()
    assert EAST_FACE - 0.105 - start.x > gap + 0.02
    rig.server.teleop_command(0.0, 1.2)
    rig.sim.step_for(2.0)
    assert handle.feedback["scaling"] == 1.0
    pose = rig.pose()
    turned = 1.2 * 2.0 - 1.2**2 / (2 * rig.robot.base.facts.max_angular_accel)  # less the ramp
    assert abs(math.remainder(pose.yaw - start.yaw - turned, 2 * math.pi)) < 0.02
    assert math.hypot(pose.x - start.x, pose.y - start.y) < 0.01
    assert rig.server.teleop_stats.stopped_cycles == 3  # the forward attempt only
    assert rig.contacts.touched == set()


def test_time_allowance_ends_with_timeout() -> None:
    rig = make_rig("walls", Pose2D(x=-2.0, y=-0.5, yaw=0.0))
    handle = rig.server.assisted_teleop(1.5)
    rig.server.teleop_command(0.1, 0.0)
    elapsed = rig.run(handle, 3.0)
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.FAILED
    assert handle.outcome.error_code == AssistedTeleopError.TIMEOUT == 731
    assert handle.outcome.error_msg == "AssistedTeleop: Exceeded time allowance"
    assert handle.feedback["current_teleop_duration"] == pytest.approx(1.6)  # first cycle past
    assert elapsed == pytest.approx(1.6, abs=0.06)
    assert rig.robot.base.target == (0.0, 0.0)


def test_preempt_ends_with_success_within_a_cycle() -> None:
    rig = make_rig("walls", Pose2D(x=-2.0, y=-0.5, yaw=0.0))
    handle = rig.server.assisted_teleop(0.0)
    rig.server.teleop_command(0.1, 0.5)
    rig.sim.step_for(1.0)
    assert handle.status is TaskStatus.RUNNING and rig.robot.base.target == (0.1, 0.5)
    rig.server.preempt_teleop()
    assert rig.run(handle, 1.0) <= 0.1
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.SUCCEEDED
    assert rig.robot.base.target == (0.0, 0.0)


def test_cancel_ends_canceled_with_the_robot_at_rest_within_one_cycle() -> None:
    rig = make_rig("walls", Pose2D(x=-2.0, y=-0.5, yaw=0.0))
    handle = rig.server.assisted_teleop(0.0)
    rig.server.teleop_command(0.25, 0.0)
    rig.sim.step_for(2.015)  # between two control ticks, at full speed
    base = rig.robot.base
    assert base.body_velocity()[0] == pytest.approx(0.22, abs=0.005)
    rig.server.cancel()
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.CANCELED
    assert base.target == (0.0, 0.0)
    rig.sim.step_for(0.1)  # one 10 Hz behaviour cycle: 0.22 m/s at 2.5 m/s² takes 0.088 s
    assert base.commanded == (0.0, 0.0)
    assert abs(base.body_velocity()[0]) < 0.01
    rig.sim.step_for(0.5)
    assert base.target == (0.0, 0.0)  # the teleop twist no longer reaches the base


def _count_clears(server: NavigationServer) -> dict[str, list[float]]:
    """Record the sim time of each clearing of each costmap."""
    times: dict[str, list[float]] = {"local": [], "global": []}
    for name, layers in (("local", server.local_layers), ("global", server.global_layers)):
        original = layers.clear

        def counted(name: str = name, original=original) -> None:  # type: ignore[no-untyped-def]
            times[name].append(server.sim.time)
            original()

        layers.clear = counted  # type: ignore[method-assign]
    return times


def test_costmaps_are_cleared_at_2_hz_while_active_and_what_the_lidar_sees_stays() -> None:
    rig = make_rig("walls", Pose2D(x=-2.0, y=-0.5, yaw=0.0))
    rig.place_box(0, -1.2, -0.5)  # a 0.3 m cube 0.8 m ahead, seen by the lidar only
    times = _count_clears(rig.server)
    rig.sim.step_for(0.4)
    start = rig.sim.time
    handle = rig.server.assisted_teleop(0.0)
    obstacle = rig.server.local_layers.obstacle_layer.grid.data
    while not times["local"]:
        rig.sim.step_for(rig.sim.physics_dt)
    assert (obstacle == LETHAL_OBSTACLE).sum() > 5  # marked again at once after the clearing
    rig.sim.step_for(3.0)
    handle.cancel()
    canceled = rig.sim.time
    rig.sim.step_for(1.0)
    count = math.floor((canceled - start) / 0.5 + 1e-9)
    expected = [start + 0.5 * k for k in range(1, count + 1)]  # every 0.5 s from the start
    assert count == 7
    assert times["local"] == pytest.approx(expected)
    assert times["global"] == pytest.approx(expected)
    assert rig.server.teleop_stats.costmap_clears == count
    assert np.diff(times["local"]) == pytest.approx([0.5] * (count - 1))


def test_clearing_can_be_switched_off() -> None:
    world_rig = make_rig("walls", Pose2D(x=-2.0, y=-0.5, yaw=0.0))
    params = NavigationParams(behaviors=BehaviorParams(teleop_costmap_clear_frequency=0.0))
    server = NavigationServer(
        world_rig.sim,
        world_rig.robot.base,
        world_rig.world,
        lidar=world_rig.robot.lidar,
        params=params,
    )
    world_rig.server.close()
    times = _count_clears(server)
    server.assisted_teleop(0.0)
    world_rig.sim.step_for(1.5)
    assert times == {"local": [], "global": []}


def test_the_bundled_mission_stops_at_the_wall_turns_and_drives_on() -> None:
    record = run_mission(load_mission(MISSION))
    result = record.result_object()
    assert record.exit_code == 0, result["expectations"]
    assert record.outcome.result == "CANCELED"
    metrics = result["metrics"]
    assert metrics["contacts"] == 0 and metrics["min_clearance"] >= 0.05
    assert metrics["teleop_min_scaling"] == 0.0 and metrics["teleop_slowed_cycles"] >= 10
    assert metrics["teleop_costmap_clears"] == 35  # 2 Hz over 18 s
    records = [json.loads(line) for line in record.trace.lines]
    poses = {r["t"]: r for r in records if r["type"] == "pose"}
    assert poses[0.5]["x"] == 0.0  # nothing moves before the first teleop event
    # commanded 0.22 m/s at the wall until 10.5 s: at rest before it from 7 s on
    stopped = poses[7.0]["x"]
    assert 0.9 < stopped < 1.15 - 0.105 - 0.05
    assert poses[10.0]["x"] == pytest.approx(stopped, abs=1e-4) and poses[10.0]["v"] == 0.0
    assert poses[4.0]["v"] == pytest.approx(0.22, abs=0.005)  # full speed while far
    assert 0.0 < poses[5.0]["v"] < 0.15  # slowed down near the wall
    assert poses[18.0]["x"] < stopped - 0.5  # turned away and drove on
