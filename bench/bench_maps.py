"""Benchmark: a large map_server map as a world (issue 22).

Usage: ``python bench/bench_maps.py [--cells 2000] [--repeats 3] [--output report.json]``

Writes a ``cells`` x ``cells`` warehouse map (0.05 m cells: 100 m a side for 2000) as a PGM
with its YAML: rooms of 10 m with doors, racks in rows, and SLAM-like speckle (single occupied
pixels, 0.05 % of the free cells). Then, best of ``--repeats``:

- load: reading the YAML and the image, the occupancy values, merging the walls into boxes,
  attaching the Burger and compiling the MuJoCo model (s); the map cache is emptied first;
- the model's geom and sensor count, and a bare ``mj_step`` against the cafe's (ratio);
- lidar: wall time of one 360-beam scan at ten free poses of the map, over the same in the cafe
  (ratio; the cafe is measured in the same run);
- navigation: a NavigateToPose run of about 9 m on the map, set-up included (real-time factor);
- the alternative: the map's solid cells as one MuJoCo height field instead of boxes (build
  time, and the scan, which then needs ``mj_multiRay``).
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
from PIL import Image

from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.robots.turtlebot3.model import attach_turtlebot3
from baobab.sim import occupancy_map
from baobab.sim.builder import STATIC_GROUP, world_spec
from baobab.sim.geometry import nearest_obstacle
from baobab.sim.lidar import Lidar
from baobab.sim.simulation import Simulation
from baobab.sim.world import Pose2D, World, load_world

RES = 0.05


def warehouse_pixels(cells: int, seed: int = 0) -> np.ndarray:
    """A warehouse floor plan, ``cells`` x ``cells`` pixels (254 free, 0 occupied, 205 outside)."""
    rng = np.random.default_rng(seed)
    pixels = np.full((cells, cells), 254, dtype=np.uint8)
    room = 200
    for start in range(0, cells, room):
        pixels[start : start + 3, :] = 0
        pixels[:, start : start + 3] = 0
    for start in range(0, cells, room):  # a 1.5 m door in the middle of every wall
        for middle in range(room // 2, cells, room):
            pixels[start : start + 3, middle - 15 : middle + 15] = 254
            pixels[middle - 15 : middle + 15, start : start + 3] = 254
    pixels[-3:, :] = pixels[:, -3:] = 0
    for row in range(40, cells, room):  # two racks (1 m x 6 m) per room
        for col in range(40, cells, room):
            pixels[row : row + 20, col : col + 120] = 0
            pixels[row + 80 : row + 100, col : col + 120] = 0
    free = np.flatnonzero(pixels.ravel() == 254)
    speckle = rng.choice(free, size=len(free) // 2000, replace=False)
    pixels.ravel()[speckle] = 0
    return pixels


def write_map(folder: Path, cells: int) -> Path:
    """The warehouse as ``warehouse.pgm`` + ``warehouse.yaml`` in ``folder``."""
    Image.fromarray(warehouse_pixels(cells)).save(folder / "warehouse.pgm")
    path = folder / "warehouse.yaml"
    path.write_text(
        "image: warehouse.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    return path


def load_and_build(path: Path) -> tuple[float, World, mujoco.MjModel]:
    """Seconds to load the map world and compile it with a Burger at a free pose."""
    occupancy_map._LOADED.clear()
    began = time.perf_counter()
    world = load_world(path)
    spec = world_spec(world)
    attach_turtlebot3(spec, Pose2D(x=5.0, y=5.0))
    model = spec.compile()
    return time.perf_counter() - began, world, model


def free_poses(world: World, count: int, seed: int = 1) -> list[Pose2D]:
    """``count`` poses at least 0.3 m from everything, drawn in the world's bounds."""
    rng = np.random.default_rng(seed)
    x0, y0, x1, y1 = world.bounds
    poses: list[Pose2D] = []
    while len(poses) < count:
        x, y = rng.uniform(x0 + 1, x1 - 1), rng.uniform(y0 + 1, y1 - 1)
        if nearest_obstacle(world, x, y)[1] > 0.3:
            poses.append(Pose2D(x=x, y=y, yaw=float(rng.uniform(-3, 3))))
    return poses


def scan_seconds(world: World, poses: list[Pose2D], scans: int = 50) -> float:
    """Mean wall seconds of one scan, over ``scans`` scans at each pose."""
    total = 0.0
    for pose in poses:
        _sim, robot = build_turtlebot3_sim(world, pose)
        robot.lidar.scan()  # warm
        began = time.perf_counter()
        for _ in range(scans):
            robot.lidar.scan()
        total += time.perf_counter() - began
    return total / (scans * len(poses))


def navigation_rtf(world: World, start: Pose2D, goal: Pose2D) -> dict[str, float]:
    """A NavigateToPose run on the map: sim seconds over wall seconds, set-up included."""
    from baobab.nav import build_navigation
    from baobab.sim.tasks import TaskStatus

    began = time.perf_counter()
    sim, robot = build_turtlebot3_sim(world, start)
    server = build_navigation(sim, robot.base, robot.lidar, world)
    handle = server.navigate_to_pose(goal)
    while handle.status is TaskStatus.RUNNING and sim.time < 300.0:
        sim.step_for(0.5)
    wall = time.perf_counter() - began
    return {
        "sim_s": sim.time,
        "wall_s": wall,
        "rtf": sim.time / wall,
        "ok": float(handle.status is TaskStatus.SUCCEEDED),
    }


def step_us(model: mujoco.MjModel, steps: int = 2000, repeats: int = 3) -> float:
    """Best wall microseconds of one bare ``mj_step`` of ``model`` (the robot at rest)."""
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data, 100)
    best = float("inf")
    for _ in range(repeats):
        began = time.perf_counter()
        mujoco.mj_step(model, data, steps)
        best = min(best, (time.perf_counter() - began) / steps)
    return best * 1e6


def heightfield_figures(world: World, poses: list[Pose2D], scans: int = 20) -> dict[str, float]:
    """Build time and scan time with the solid cells as one height field instead of boxes."""
    grid, solid = world.grid, world.map_solid()
    assert grid is not None and solid is not None
    began = time.perf_counter()
    spec = mujoco.MjSpec()
    spec.option.timestep = 0.005
    spec.worldbody.add_geom(
        name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[0, 0, 0.05], group=0
    )
    field = spec.add_hfield(
        name="map",
        nrow=grid.height,
        ncol=grid.width,
        size=[grid.width * RES / 2, grid.height * RES / 2, 1.0, 0.01],
        userdata=solid.astype(np.float32).ravel().tolist(),
    )
    x0, y0, x1, y1 = grid.bounds
    spec.worldbody.add_geom(
        name="map_field",
        type=mujoco.mjtGeom.mjGEOM_HFIELD,
        hfieldname=field.name,
        pos=[(x0 + x1) / 2, (y0 + y1) / 2, 0.0],
        group=STATIC_GROUP,
    )
    attach_turtlebot3(spec, poses[0])
    model = spec.compile()
    build = time.perf_counter() - began
    sim = Simulation(model)
    lidar = Lidar(sim, "tb3/base_scan", rate=5.0, beams=360, range_min=0.12, range_max=3.5)
    total = 0.0
    lidar.scan()
    began = time.perf_counter()
    for _ in range(scans):
        lidar.scan()
    total = time.perf_counter() - began
    return {"build_s": build, "scan_s": total / scans}


def main() -> None:
    """Measure and print a JSON report."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--output", default=None)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        path = write_map(Path(folder), args.cells)
        timings = []
        for _ in range(args.repeats):
            seconds, world, model = load_and_build(path)
            timings.append(seconds)
        poses = free_poses(world, 10)
        cafe = load_world("cafe")
        cafe_poses = free_poses(cafe, 10)
        cafe_sim, _ = build_turtlebot3_sim(cafe, cafe.spawn)
        map_step, cafe_step = step_us(model), step_us(cafe_sim.model)
        map_scan = min(scan_seconds(world, poses) for _ in range(args.repeats))
        cafe_scan = min(scan_seconds(cafe, cafe_poses) for _ in range(args.repeats))
        report: dict[str, Any] = {
            "cells": args.cells,
            "load_and_build_s": min(timings),
            "geoms": int(model.ngeom),
            "static_boxes": int((model.geom_group == STATIC_GROUP).sum()),
            "scan_map_us": map_scan * 1e6,
            "scan_cafe_us": cafe_scan * 1e6,
            "scan_ratio": map_scan / cafe_scan,
            "sensors": int(model.nsensor),
            "step_map_us": map_step,
            "step_cafe_us": cafe_step,
            "step_ratio": map_step / cafe_step,
            "navigation": navigation_rtf(world, Pose2D(x=1.0, y=3.0), Pose2D(x=9.0, y=7.5)),
            "heightfield": heightfield_figures(world, poses),
        }
    text = json.dumps(report, indent=2)
    print(text)
    if args.output:
        Path(args.output).write_text(text + "\n")


if __name__ == "__main__":
    main()
