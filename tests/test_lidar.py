"""The LDS-01 lidar: one mj_multiRay per scan, ranges in the LaserScan conventions."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from baobab.missions.run.event_targets import ObstacleSlots
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim import Simulation
from baobab.sim.builder import world_spec
from baobab.sim.lidar import SCAN, LaserScan, Lidar
from baobab.sim.lidar_kernel import fan_directions
from baobab.sim.records import record
from baobab.sim.world import Box, Cylinder, Floor, Pose2D, World


def _world(boxes: list[Box] | None = None, cylinders: list[Cylinder] | None = None) -> World:
    return World(
        name="lidar_range",
        floor=Floor(size=(14.0, 14.0)),
        boxes=boxes or [],
        cylinders=cylinders or [],
        spawns={"default": Pose2D(x=0.0, y=0.0)},
    )


def _first_scan(
    world: World, start: Pose2D | None = None, *, seed: int = 0, lidar_noise_std: float = 0.0
) -> LaserScan:
    sim, robot = build_turtlebot3_sim(world, start, seed=seed, lidar_noise_std=lidar_noise_std)
    sim.step_for(sim.physics_dt)
    assert robot.lidar.latest is not None
    return robot.lidar.latest


def test_scan_has_the_lds01_shape() -> None:
    scan = _first_scan(_world())
    increment = 2 * math.pi / 360
    assert len(scan.ranges) == 360
    assert scan.angle_min == 0.0
    assert scan.angle_increment == pytest.approx(increment)
    assert scan.angle_max == pytest.approx(359 * increment)
    assert (scan.range_min, scan.range_max) == (0.12, 3.5)
    assert scan.frame_id == "tb3/base_scan"
    assert scan.angles[90] == pytest.approx(math.pi / 2)


def test_the_robot_never_sees_itself() -> None:
    scan = _first_scan(_world())
    assert np.isinf(scan.ranges).all()


@pytest.mark.parametrize("yaw", [0.0, 0.7, -2.0])
def test_a_beam_reads_a_wall_at_a_known_distance(yaw: float) -> None:
    wall = Box(name="wall", center=(2.05, 0.0), size=(0.1, 8.0))
    scan = _first_scan(_world([wall]), Pose2D(x=0.0, y=0.0, yaw=yaw))
    # The beam that points along map +x hits the wall face x = 2.0 square on.
    beam = round(math.remainder(-yaw, 2 * math.pi) / scan.angle_increment) % 360
    assert scan.sensor_pose.yaw == pytest.approx(yaw, abs=1e-6)
    expected = (2.0 - scan.sensor_pose.x) / math.cos(scan.angles[beam] + yaw)
    assert scan.ranges[beam] == pytest.approx(expected, abs=0.01)
    # Beams pointing away from the wall find nothing.
    assert math.isinf(scan.ranges[(beam + 180) % 360])


def test_hits_beyond_range_max_read_inf() -> None:
    # mj_multiRay's cutoff only culls bounding volumes: a wall 3.8 m away comes back from
    # the ray cast and must be clipped by the sensor.
    near = Box(name="near", center=(0.0, 3.3), size=(8.0, 0.1))
    far = Box(name="far", center=(0.0, -3.85), size=(8.0, 0.1))
    scan = _first_scan(_world([near, far]))
    left, right = scan.ranges[90], scan.ranges[270]
    assert left == pytest.approx(3.25, abs=0.01)
    assert math.isinf(right)


def test_returns_closer_than_range_min_read_inf() -> None:
    # A thin post 9 cm ahead of the scanner, clear of the chassis; another 1 m to the left.
    close = Cylinder(name="close", center=(0.06, 0.0), radius=0.005, height=0.5)
    post = Cylinder(name="post", center=(-0.032, 1.0), radius=0.02, height=0.5)
    scan = _first_scan(_world(cylinders=[close, post]))
    assert math.isinf(scan.ranges[0])
    assert scan.ranges[90] == pytest.approx(0.98, abs=0.01)


def test_beams_follow_the_full_orientation_of_the_site() -> None:
    spec = world_spec(_world())
    # A scanner 0.5 m up, pitched 30 degrees nose down: the forward beam meets the floor.
    pitch = math.radians(30.0)
    spec.worldbody.add_site(
        name="tilted", pos=[0.0, 0.0, 0.5], quat=[math.cos(pitch / 2), 0, math.sin(pitch / 2), 0]
    )
    sim = Simulation(spec.compile())
    lidar = Lidar(sim, "tilted")
    scan = lidar.scan()
    assert scan.ranges[0] == pytest.approx(0.5 / math.sin(pitch), abs=1e-6)
    assert math.isinf(scan.ranges[180])  # pointing up and back


def test_scans_run_at_five_hertz_and_reach_subscribers() -> None:
    sim, robot = build_turtlebot3_sim(_world())
    stamps: list[float] = []
    robot.lidar.subscribe(lambda scan: stamps.append(scan.stamp))
    sim.step_for(1.0)
    assert stamps == pytest.approx([0.0, 0.2, 0.4, 0.6, 0.8])  # due in [0, 1) s
    assert robot.lidar.latest is not None and robot.lidar.latest.stamp == pytest.approx(0.8)


def test_each_scan_owns_its_ranges() -> None:
    wall = Box(name="wall", center=(2.05, 0.0), size=(0.1, 8.0))
    sim, robot = build_turtlebot3_sim(_world([wall]))
    scans: list[LaserScan] = []
    robot.lidar.subscribe(scans.append)
    robot.base.command(0.2, 0.0)
    sim.step_for(1.0)
    assert scans[0].ranges is not scans[-1].ranges
    assert scans[-1].ranges[0] < scans[0].ranges[0] - 0.1


def test_a_scan_packs_its_figures_once() -> None:
    # Both costmaps mark each scan: its record is made once, and is the scan's own.
    first = _first_scan(_world(), Pose2D(x=0.5, y=-0.25, yaw=0.75))
    packed = first.pack()
    pose = first.sensor_pose
    assert packed is first.pack()
    assert packed.dtype == SCAN
    assert packed.tolist() == record(SCAN, first, x=pose.x, y=pose.y, yaw=pose.yaw).tolist()
    second = _first_scan(_world(), Pose2D(x=-1.0, y=0.5, yaw=-2.0))
    assert second.pack()[0]["x"] == second.sensor_pose.x != packed[0]["x"]
    assert second.pack()[0]["yaw"] == second.sensor_pose.yaw


def test_noise_is_seeded() -> None:
    wall = Box(name="wall", center=(2.05, 0.0), size=(0.1, 8.0))
    world = _world([wall])
    clean = _first_scan(world)
    noisy = _first_scan(world, seed=7, lidar_noise_std=0.01)
    again = _first_scan(world, seed=7, lidar_noise_std=0.01)
    other = _first_scan(world, seed=8, lidar_noise_std=0.01)
    hits = np.isfinite(clean.ranges)
    np.testing.assert_array_equal(noisy.ranges, again.ranges)
    assert not np.array_equal(noisy.ranges[hits], other.ranges[hits])
    errors = noisy.ranges[hits] - clean.ranges[hits]
    assert 0.005 < float(np.std(errors)) < 0.02
    assert np.array_equal(np.isfinite(noisy.ranges), hits)


def test_rejects_impossible_settings() -> None:
    sim, _ = build_turtlebot3_sim(_world())
    with pytest.raises(ValueError, match="range_min < range_max"):
        Lidar(sim, "tb3/base_scan", range_min=2.0, range_max=1.0)
    with pytest.raises(ValueError, match="no site named 'no_such_site'"):
        Lidar(sim, "no_such_site")


def _multi_ray_ranges(lidar: Lidar) -> tuple[np.ndarray, np.ndarray]:
    """Ranges and geom ids as one plain ``mj_multiRay`` call and the sensor's clipping give,
    for the scanner's own beams."""
    sim = lidar._sim
    origin = sim.data.site(lidar.site_name).xpos.copy()
    directions = np.empty_like(lidar._fan.local)
    fan_directions(sim.data.site(lidar.site_name).xmat, lidar._fan.local, directions)
    geom_ids = np.empty(lidar.beams, dtype=np.int32)
    distances = np.empty(lidar.beams)
    mujoco.mj_multiRay(
        sim.model,
        sim.data,
        origin,
        directions.reshape(-1),
        lidar._fan.geomgroup,
        1,
        -1,
        geom_ids,
        distances,
        None,
        lidar.beams,
        lidar.range_max,
    )
    out = (geom_ids < 0) | (distances > lidar.range_max) | (distances < lidar.range_min)
    distances[out] = math.inf
    return distances, geom_ids


def _no_fallback(lidar: Lidar, monkeypatch: pytest.MonkeyPatch) -> None:
    """Make the scanner fail if it falls back to mj_multiRay: the compiled caster must cast."""

    def refuse() -> None:
        raise AssertionError("the scanner fell back to mj_multiRay")

    monkeypatch.setattr(lidar, "_multi_ray", refuse)


@pytest.mark.parametrize("world", ["cafe", "walls", "farm"])
def test_compiled_caster_equals_mj_multi_ray(world: str, monkeypatch: pytest.MonkeyPatch) -> None:
    # The caster culls (beam, geom) pairs itself: at random poses, some tipped so that beams
    # meet the floor, with the movable boxes set down at a slant next to the robot, every
    # range must be bit for bit what mj_multiRay gives, and the caster casts every scan.
    sim, robot = build_turtlebot3_sim(world)
    _no_fallback(robot.lidar, monkeypatch)
    model, data = sim.model, sim.data
    rng = np.random.default_rng(11)
    low = model.stat.center - 0.5 * model.stat.extent
    high = model.stat.center + 0.5 * model.stat.extent
    root = data.joint(robot.names.root_joint)
    slots = [model.body(f"movable_{i}").mocapid[0] for i in range(2)]
    floor = model.geom("floor").id
    floor_hits = 0
    for trial in range(120):
        x, y = rng.uniform(low[0], high[0]), rng.uniform(low[1], high[1])
        tilt = rng.uniform(0.0, 0.3) if trial % 3 == 0 else 0.0
        roll, pitch = rng.normal(0.0, 1.0, 2) * tilt
        quat = Rotation.from_euler("xyz", [roll, pitch, rng.uniform(-math.pi, math.pi)]).as_quat()
        root.qpos[:3] = [x, y, rng.uniform(0.0, 0.3) if tilt else 0.0]
        root.qpos[3:7] = np.roll(quat, 1)  # MuJoCo's w, x, y, z
        for k, slot in enumerate(slots):
            data.mocap_pos[slot] = [x + rng.uniform(-1, 1), y + rng.uniform(-1, 1), 0.25 * k]
            data.mocap_quat[slot] = np.roll(Rotation.from_rotvec([0, 0.2 * k, trial]).as_quat(), 1)
        mujoco.mj_forward(model, data)
        scan = robot.lidar.scan()
        expected, geom_ids = _multi_ray_ranges(robot.lidar)
        np.testing.assert_array_equal(scan.ranges, expected)
        floor_hits += int(np.count_nonzero(np.isfinite(expected) & (geom_ids == floor)))
    assert floor_hits > 0


def test_beam_directions_are_the_rotated_sensor_frame_beams() -> None:
    local = Lidar(build_turtlebot3_sim(_world())[0], "tb3/base_scan")._fan.local
    rng = np.random.default_rng(2)
    directions = np.empty_like(local)
    for trial in range(300):
        turn = rng.normal(0.0, 1.0, 3) * (rng.uniform(0.0, 3.0) if trial % 2 else 0.0)
        turn[2] = rng.uniform(-4.0, 4.0)
        rotation = Rotation.from_rotvec(turn).as_matrix()
        fan_directions(rotation.reshape(-1), local, directions)
        np.testing.assert_allclose(directions, local @ rotation.T, rtol=0, atol=1e-15)


def test_an_obstacle_resized_at_run_time_reads_as_mj_multi_ray_sees_it() -> None:
    # Events grow an obstacle slot (geom_size, geom_rbound) past the culling volumes
    # mj_multiRay uses; the scanner must still report exactly what mj_multiRay reports.
    sim, robot = build_turtlebot3_sim("walls", Pose2D(x=1.0, y=1.0))
    model, data = sim.model, sim.data
    geom = model.geom("movable_0")
    half = np.array([0.5, 0.5, 0.25])
    geom.size[:] = half
    model.geom_rbound[geom.id] = float(np.linalg.norm(half))
    data.mocap_pos[model.body("movable_0").mocapid[0]] = [2.0, 2.0, 0.25]
    mujoco.mj_forward(model, data)
    scan = robot.lidar.scan()
    expected, geom_ids = _multi_ray_ranges(robot.lidar)
    np.testing.assert_array_equal(scan.ranges, expected)
    assert np.count_nonzero(geom_ids == geom.id) > 0


def test_spawned_obstacles_are_cast_by_the_compiled_caster(monkeypatch: pytest.MonkeyPatch) -> None:
    # Obstacle slots resized by spawn events (with the culling volumes MuJoCo compiles for
    # their size) are whole to the compiled caster: no fallback to mj_multiRay, bit for bit
    # its ranges, at random robot poses among boxes of random sizes and headings.
    sim, robot = build_turtlebot3_sim("walls", Pose2D(x=1.0, y=1.0))
    _no_fallback(robot.lidar, monkeypatch)
    model, data = sim.model, sim.data
    slots = ObstacleSlots(sim)
    rng = np.random.default_rng(5)
    names = [f"crate_{k}" for k in range(4)]
    for k, name in enumerate(names):
        size = rng.uniform([0.1, 0.1, 0.1], [1.5, 1.5, 0.6])
        slots.spawn(name, 1.0 + 0.8 * k, 1.5, rng.uniform(-math.pi, math.pi), size)
    slot_geoms = {model.geom(slots.placed[name].slot).id for name in names}
    root = data.joint(robot.names.root_joint)
    seen = 0
    for _ in range(40):
        for name in names:
            slots.move(name, *rng.uniform([0.0, 0.0], [3.0, 3.0]), rng.uniform(-4.0, 4.0))
        root.qpos[:2] = rng.uniform([0.0, 0.0], [3.0, 3.0])
        root.qpos[3:7] = [math.cos(0.3), 0.0, 0.0, math.sin(0.3)]
        mujoco.mj_forward(model, data)
        scan = robot.lidar.scan()
        expected, geom_ids = _multi_ray_ranges(robot.lidar)
        np.testing.assert_array_equal(scan.ranges, expected)
        seen += int(np.count_nonzero(np.isin(geom_ids, list(slot_geoms)) & np.isfinite(expected)))
    assert seen > 0
