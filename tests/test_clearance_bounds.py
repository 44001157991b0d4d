"""The compiled clearance search: its bounds never exceed the exact distances, and its answer
is the exhaustive search's, bit for bit, whatever the robot's and the obstacles' poses."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from baobab.robots.catalog import ROBOTS
from baobab.robots.diff_drive.clearance_bounds import ClearanceBounds
from baobab.sim.builder import MOVABLE_GROUP, STATIC_GROUP


@pytest.mark.parametrize(
    ("world", "robot_name"),
    [("cafe", "turtlebot3"), ("walls", "turtlebot3"), ("walls", "turtlebot3_waffle")],
)
def test_bounds_hold_and_the_search_equals_the_exhaustive_one(world: str, robot_name: str) -> None:
    sim, robot = ROBOTS[robot_name].build_sim(world)  # a polygon's footprint is a prism
    model, data = sim.model, sim.data
    footprint = model.geom(robot.names.footprint_geom).id
    static = np.flatnonzero(model.geom_group == STATIC_GROUP)
    movable = np.flatnonzero(model.geom_group == MOVABLE_GROUP)
    obstacles = np.concatenate((static, movable)).tolist()
    clearance = ClearanceBounds(model, data, footprint, np.array(obstacles))
    root = data.joint(robot.names.root_joint)
    slots = [model.body(f"movable_{i}").mocapid[0] for i in range(len(movable))]
    rng = np.random.default_rng(5)
    low = model.stat.center - 0.5 * model.stat.extent
    high = model.stat.center + 0.5 * model.stat.extent
    in_range = tight = skipped = 0
    for trial in range(150):
        x, y = rng.uniform(low[0], high[0]), rng.uniform(low[1], high[1])
        # Mostly level; every third pose tipped a little, as braking and bumps do.
        tilt = rng.uniform(0.0, 0.05) if trial % 3 == 0 else 0.0
        roll, pitch = rng.normal(0.0, 1.0, 2) * tilt
        quat = Rotation.from_euler("xyz", [roll, pitch, rng.uniform(-math.pi, math.pi)]).as_quat()
        root.qpos[:3] = [x, y, 0.0]
        root.qpos[3:7] = np.roll(quat, 1)  # MuJoCo's w, x, y, z
        for k, slot in enumerate(slots):
            # Upright at a slant, or tipped over, next to the robot.
            lean = 0.0 if k % 2 == 0 else rng.uniform(0.0, 1.0)
            data.mocap_pos[slot] = [x + rng.uniform(-1, 1), y + rng.uniform(-1, 1), 0.2]
            turn = Rotation.from_euler("zx", [rng.uniform(-math.pi, math.pi), lean])
            data.mocap_quat[slot] = np.roll(turn.as_quat(), 1)
        mujoco.mj_forward(model, data)
        exact = {
            geom: mujoco.mj_geomDistance(model, data, footprint, geom, 30.0, None)
            for geom in obstacles
        }
        for bound, geom in clearance.sorted_bounds():
            assert bound <= exact[geom] or exact[geom] == 30.0
            tight += exact[geom] - bound < 1e-3
        for limit in (0.5, 2.0):
            exhaustive = min(
                mujoco.mj_geomDistance(model, data, footprint, geom, limit, None)
                for geom in obstacles
            )
            expected = exhaustive if exhaustive < limit else math.inf
            assert clearance.min_clearance(limit) == expected
            in_range += math.isfinite(expected)
            for below in (0.05, 0.3, 1.0):
                found = clearance.min_clearance(limit, below=below)
                assert found == (expected if expected < below else math.inf)
                skipped += math.isfinite(expected) and expected >= below
    assert in_range > 50 and skipped > 50
    if robot_name == "turtlebot3":
        assert tight > 100  # the planar bounds are nearly exact for upright shapes
