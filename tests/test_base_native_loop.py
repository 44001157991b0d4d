"""The base's compiled loop inside the physics step, against Python references, on real physics.

The base ticks inside the ``mj_step`` taken from each tick's step, after the Python callbacks
due then. Its ramp, wheel targets and odometry must be what a Python reference computes from
the same state, its contact and position samples what Python callbacks read, and none of it
may depend on how often Python wakes (how the physics is batched).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from map_files import room_pixels, write_map

from baobab.missions.run import mobile_probe
from baobab.missions.run.arm_probes import ContactSampler
from baobab.missions.run.mobile_probe import MobileProbe
from baobab.robots.diff_drive import MobileRobot
from baobab.robots.turtlebot3 import BURGER, build_turtlebot3_sim
from baobab.sim.builder import MAP_WALL_MATERIAL, MOVABLE_GROUP, ROBOT_GROUP, STATIC_GROUP
from baobab.sim.simulation import Simulation
from baobab.sim.world import (
    MAP_GEOM_PREFIX,
    MOVABLE_SLOT_COUNT,
    Box,
    Floor,
    Pose2D,
    World,
    load_world,
)


def _commands(seed: int) -> list[tuple[float, float, float]]:
    """(time s, linear m/s, angular rad/s) commands, at times that are no tick of the base."""
    rng = np.random.default_rng(seed)
    times = np.sort(rng.choice(np.arange(1, 400), size=40, replace=False)) * 0.005
    return [(float(t), float(rng.uniform(-0.3, 0.3)), float(rng.uniform(-3.0, 3.0))) for t in times]


def _drive(robot: MobileRobot, commands: list[tuple[float, float, float]], period: float) -> None:
    """Give each command from a callback every ``period`` (s), at its time or just after."""
    pending = list(commands)

    def commander(now: float) -> None:
        while pending and pending[0][0] <= now + 1e-9:
            _, linear, angular = pending.pop(0)
            robot.base.command(linear, angular)

    robot.sim.every(period, commander, name="commander")


class _ReferenceBase:
    """The base's tick in Python: the ramp, the wheel targets, odometry.

    Registered after the commander, :meth:`check` runs at each tick's step just before the
    compiled tick: it checks the previous tick's results against its prediction, then
    predicts this tick's from the same state and ``cmd_vel`` the compiled tick will read.
    """

    def __init__(self, robot: MobileRobot) -> None:
        self.base = robot.base
        self.facts = BURGER
        self.commanded = (0.0, 0.0)
        data = robot.sim.data
        self.wheels = [data.joint(name).qpos for name in robot.names.wheel_joints]
        self.ctrl = [data.actuator(name).ctrl for name in robot.names.wheel_actuators]
        self.tick = 2 * math.pi / self.facts.encoder_ticks_per_rev
        self.encoders = self._encoders()
        self.odom = (0.0, 0.0, 0.0)
        self.predicted: tuple[object, ...] | None = None
        self.checked = 0

    def _encoders(self) -> tuple[float, float]:
        return tuple(round(float(w[0]) / self.tick) * self.tick for w in self.wheels)  # type: ignore[return-value]

    def check(self, now: float) -> None:
        if self.predicted is not None:
            odometry = self.base.odometry
            pose = (odometry.pose.x, odometry.pose.y, odometry.pose.yaw)
            ctrl = (float(self.ctrl[0][0]), float(self.ctrl[1][0]))
            assert (self.base.commanded, ctrl, pose, odometry.stamp) == self.predicted
            self.checked += 1
        self.predicted = self._predict(now)

    def _predict(self, now: float) -> tuple[object, ...]:
        facts, period = self.facts, 0.01
        (v_target, w_target), (v, w) = self.base.target, self.commanded
        v = min(
            max(v_target, v - facts.max_linear_accel * period), v + facts.max_linear_accel * period
        )
        w = min(
            max(w_target, w - facts.max_angular_accel * period),
            w + facts.max_angular_accel * period,
        )
        self.commanded = (v, w)
        encoders = self._encoders()
        d_left = (encoders[0] - self.encoders[0]) * facts.wheel_radius
        d_right = (encoders[1] - self.encoders[1]) * facts.wheel_radius
        self.encoders = encoders
        distance, turn = (d_left + d_right) / 2, (d_right - d_left) / facts.wheel_separation
        x, y, yaw = self.odom
        heading = yaw + turn / 2
        self.odom = (
            x + distance * math.cos(heading),
            y + distance * math.sin(heading),
            math.remainder(yaw + turn, 2 * math.pi),
        )
        return (v, w), self.base.wheel_speeds(v, w), self.odom, now


def test_compiled_tick_matches_a_python_reference_tick() -> None:
    _, robot = build_turtlebot3_sim("walls")
    _drive(robot, _commands(seed=3), period=0.005)
    reference = _ReferenceBase(robot)
    robot.sim.every(0.01, reference.check, name="reference")
    robot.sim.step_for(2.5)
    assert reference.checked == 249
    assert robot.base.odometry.pose.x != 0.0


def test_the_ticks_do_not_depend_on_how_often_python_wakes() -> None:
    commands = _commands(seed=3)
    _, seldom = build_turtlebot3_sim("walls")  # Python wakes every 50 ms: long batches
    _drive(seldom, commands, period=0.05)
    _, often = build_turtlebot3_sim("walls")  # and at every physics step
    _drive(often, commands, period=0.05)
    often.sim.every(often.sim.physics_dt, lambda _now: None, name="wake every step")
    seldom.sim.step_for(2.5)
    often.sim.step_for(2.5)
    assert np.array_equal(seldom.sim.data.qpos, often.sim.data.qpos)
    assert np.array_equal(seldom.sim.data.ctrl, often.sim.data.ctrl)
    assert seldom.base.odometry == often.base.odometry
    assert seldom.base.odometry.pose.x != 0.0


def test_a_forward_between_steps_runs_no_tick() -> None:
    sim, robot = build_turtlebot3_sim("walls")
    sim.step_for(0.1)
    robot.base.command(0.2, 0.0)
    sim.forward()  # at a tick's step, before Python's turn: the tick waits for the step
    assert robot.base.commanded == (0.0, 0.0)
    assert not sim.data.ctrl.any()
    sim.step_for(0.005)
    assert robot.base.commanded == pytest.approx((0.025, 0.0))


def _arena() -> World:
    return World(
        name="arena",
        floor=Floor(size=(6.0, 6.0)),
        boxes=[Box(name="wall", center=(0.8, 0.0), size=(0.1, 2.0))],
        spawns={"default": Pose2D(x=0.0, y=0.0)},
    )


def _python_contacts(sim: Simulation) -> ContactSampler:
    """Python callbacks that sample the robot's contacts with obstacles every 10 ms, as the
    base's probe does inside the step. data.contact holds the contacts of the state the last
    step started from: a callback one physics step after the kernel's sample reads the
    contacts the kernel read."""
    groups = sim.model.geom_group
    contacts = ContactSampler(
        sim,
        mine=[bool(g == ROBOT_GROUP) for g in groups],
        others=[bool(g in (STATIC_GROUP, MOVABLE_GROUP)) for g in groups],
    )
    sim.every(0.01, contacts.sample, name="python contacts", first_call=sim.physics_dt)
    return contacts


def test_contact_and_position_samples_match_python_callbacks() -> None:
    sim, robot = build_turtlebot3_sim(_arena())
    samples = robot.base.start_probe(pose_period=0.02, contact_period=0.01, drain_period=1.0)
    python_contacts = _python_contacts(sim)
    root = sim.data.joint("tb3/root").qpos
    python_poses: list[tuple[float, float, float]] = []
    sim.every(0.02, lambda now: python_poses.append((now, root[0], root[1])), name="poses")
    drained: list[tuple[float, float, float]] = []
    sim.every(1.0, lambda _now: drained.extend(samples.drain()), name="drain")
    robot.base.command(0.2, 0.05)  # into the wall
    sim.step_for(8.0)
    drained.extend(samples.drain())
    assert python_contacts.samples > 50
    assert samples.contact_samples == python_contacts.samples
    assert samples.touched() == sorted(python_contacts.objects) == ["wall"]
    assert drained == python_poses


def _map_arena(folder: Path) -> World:
    """A 4 m x 4 m room on a map with one box of the world file at (1.0, 3.0)."""
    write_map(folder, room_pixels(80, 80))
    (folder / "world.yaml").write_text(
        "name: arena\nmap: ./map.yaml\nspawns: {default: {x: 1.0, y: 1.0}}\n"
        "boxes: [{name: crate, center: [1.0, 3.0], size: [0.4, 0.4]}]\n"
    )
    return load_world(folder / "world.yaml")


@pytest.mark.parametrize(
    ("yaw", "touched"), [(math.pi / 2, ["crate"]), (-math.pi / 2, [MAP_WALL_MATERIAL])]
)
def test_a_maps_walls_count_as_one_obstacle_with_two_sensors(
    tmp_path: Path, yaw: float, touched: list[str]
) -> None:
    world = _map_arena(tmp_path)
    sim, robot = build_turtlebot3_sim(world, Pose2D(x=1.0, y=1.5, yaw=yaw))
    assert sim.model.nsensor <= 2 + 1 + MOVABLE_SLOT_COUNT + 2  # not one per wall box
    samples = robot.base.start_probe(pose_period=0.02, contact_period=0.01, drain_period=1.0)
    python_contacts = _python_contacts(sim)
    sim.every(1.0, lambda _now: samples.drain(), name="drain")
    robot.base.command(0.2, 0.0)  # north into the crate, or south into the map's wall
    sim.step_for(8.0)
    walls = {name for name in python_contacts.objects if name.startswith(MAP_GEOM_PREFIX)}
    assert python_contacts.samples > 50
    assert samples.contact_samples == python_contacts.samples
    assert samples.touched() == touched
    assert bool(walls) == (touched == [MAP_WALL_MATERIAL])


def test_samples_inside_the_step_equal_samples_when_python_wakes() -> None:
    runs = []
    for wake in (False, True):
        sim, robot = build_turtlebot3_sim(_arena())
        samples = robot.base.start_probe(pose_period=0.02, contact_period=0.01, drain_period=1.0)
        if wake:
            sim.every(0.005, lambda _now: None, name="wake every step")
        robot.base.command(0.2, -0.05)
        poses = []
        for _ in range(7):
            sim.step_for(1.0)
            poses.extend(samples.drain())
        runs.append((poses, samples.contact_samples, samples.touched()))
    assert runs[0] == runs[1]
    assert runs[0][1] > 0


def test_undrained_samples_fail_loudly() -> None:
    sim, robot = build_turtlebot3_sim(_arena())
    samples = robot.base.start_probe(pose_period=0.02, contact_period=0.01, drain_period=0.1)
    sim.step_for(2.0)
    with pytest.raises(Exception, match="overflowed"):
        samples.drain()


def test_probe_visits_equal_a_sample_by_sample_check() -> None:
    sim, robot = build_turtlebot3_sim(_arena())
    rng = np.random.default_rng(5)
    on_circle = [(0.3 * math.sin(a), 0.3 - 0.3 * math.cos(a)) for a in np.linspace(0, 6, 6)]
    elsewhere = rng.uniform(-1.0, 1.0, (6, 2)).tolist()
    locations = {f"p{i}": (x, y) for i, (x, y) in enumerate(on_circle + elsewhere)}
    probe = MobileProbe(sim, robot.base, locations, visit_radius=0.3)
    robot.base.command(0.15, 0.5)  # a circle of 0.3 m radius through some of the points
    sim.step_for(12.0)
    inside = dict.fromkeys(locations, False)
    expected = []
    for t, x, y in zip(probe.times, probe.xs, probe.ys, strict=True):
        for name, (lx, ly) in locations.items():
            now_inside = math.hypot(lx - x, ly - y) <= 0.3
            if now_inside and not inside[name]:
                expected.append((t, name))
            inside[name] = now_inside
    assert len(probe.times) == 600
    assert len(expected) >= 3
    assert probe.visits == expected


def test_probe_path_length_equals_a_sample_by_sample_sum() -> None:
    """Drained in batches of a second, the path length is the sum of the steps between
    consecutive samples added in order (the same float, not merely close)."""
    sim, robot = build_turtlebot3_sim(_arena())
    probe = MobileProbe(sim, robot.base, {}, visit_radius=0.3)
    robot.base.command(0.15, 0.5)
    sim.step_for(3.5)
    robot.base.command(0.1, -0.8)
    sim.step_for(2.0)
    xs, ys = list(probe.xs), list(probe.ys)
    expected = 0.0
    for index in range(1, len(xs)):
        expected += math.hypot(xs[index] - xs[index - 1], ys[index] - ys[index - 1])
    assert len(xs) == 275
    assert probe.path_length == expected > 0.5


def test_probe_figures_do_not_depend_on_the_drain_period(monkeypatch: pytest.MonkeyPatch) -> None:
    Figures = tuple[list[float], list[float], list[float], list[tuple[float, str]], float]

    def drive(drain_period: float) -> Figures:
        monkeypatch.setattr(mobile_probe, "DRAIN_PERIOD", drain_period)
        sim, robot = build_turtlebot3_sim(_arena())
        locations = {"a": (0.3, 0.3), "b": (0.0, 0.6), "c": (0.05, 0.0), "d": (2.0, 2.0)}
        probe = MobileProbe(sim, robot.base, locations, visit_radius=0.3)
        robot.base.command(0.15, 0.5)
        sim.step_for(7.3)
        drained = (list(probe.times), list(probe.xs), list(probe.ys))
        return (*drained, probe.visits, probe.path_length)

    every_second, every_five = drive(1.0), drive(5.0)
    assert len(every_second[3]) >= 3  # visits
    assert every_second == every_five
