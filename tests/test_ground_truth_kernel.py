"""The compiled ground truth of a base against the Python reference it replaces, bit for bit."""

from __future__ import annotations

import math
import pickle
import random

import numpy as np
import pytest
from pydantic import ValidationError

from baobab.robots.diff_drive.ground_truth_kernel import (
    ground_truth,
    ground_truth_pose,
    ground_truth_reference,
)
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.world import Pose2D


def test_the_kernel_equals_the_python_reference_on_random_states() -> None:
    rng = np.random.default_rng(28)
    state = np.empty(13)  # a free joint's qpos (7) then its qvel (6), as in MjData
    qpos, qvel = state[:7], state[7:]
    for trial in range(3000):
        qpos[:3] = rng.uniform(-50.0, 50.0, 3)
        quaternion = rng.normal(size=4)
        if trial % 3 == 0:
            quaternion[1:3] *= 1e-3  # nearly upright, as a driving base is
        if trial % 2 == 0:
            quaternion /= np.linalg.norm(quaternion)  # a unit quaternion; else MuJoCo's as is
        if trial % 50 == 0:
            quaternion = np.array([1.0, 0.0, 0.0, 0.0])  # MuJoCo's identity shortcut
        qpos[3:] = quaternion
        qvel[:] = rng.normal(scale=rng.choice([1e-6, 0.3, 5.0]), size=6)
        found = ground_truth(qpos.ctypes.data, qvel.ctypes.data)
        assert found == ground_truth_reference(qpos, qvel), trial


def test_the_base_reads_the_kernel_figures_of_its_free_joint() -> None:
    sim, robot = build_turtlebot3_sim("walls")
    root = sim.data.joint(robot.names.root_joint)
    robot.base.command(0.2, 0.8)
    for _ in range(20):
        sim.step_for(0.05)
        x, y, yaw, forward, yaw_rate = ground_truth_reference(root.qpos, root.qvel)
        pose = robot.base.pose()
        assert (pose.x, pose.y, pose.yaw) == (x, y, yaw)
        assert robot.base.body_velocity() == (forward, yaw_rate)
    assert forward > 0.1 and yaw_rate > 0.3


def test_a_ground_truth_pose_is_the_pose_the_constructor_makes() -> None:
    """Equal, hashed, printed, dumped, pickled, copied and frozen alike; non-finite values and
    other types go through the constructor (and fail or convert as it does)."""
    rng = random.Random(28)
    for _ in range(200):
        x, y, yaw = (rng.uniform(-1e3, 1e3) for _ in range(3))
        fast, made = ground_truth_pose(x, y, yaw), Pose2D(x=x, y=y, yaw=yaw)
        assert type(fast) is Pose2D
        assert fast == made and hash(fast) == hash(made) and repr(fast) == repr(made)
        assert fast.__getstate__() == made.__getstate__()
        assert fast.model_dump() == made.model_dump() and pickle.loads(pickle.dumps(fast)) == made
        assert fast.model_copy(update={"x": 1.0}) == made.model_copy(update={"x": 1.0})
    with pytest.raises(ValidationError):
        fast.x = 0.0
    for bad in (math.nan, math.inf, -math.inf):
        with pytest.raises(ValidationError):
            ground_truth_pose(0.0, bad, 0.0)
    assert ground_truth_pose(1, 2, 3) == Pose2D(x=1, y=2, yaw=3)
