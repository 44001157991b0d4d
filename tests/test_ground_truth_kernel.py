"""The compiled ground truth of a base against the Python reference it replaces, bit for bit."""

from __future__ import annotations

import numpy as np

from baobab.robots.diff_drive.ground_truth_kernel import (
    ground_truth,
    ground_truth_reference,
)
from baobab.robots.turtlebot3 import build_turtlebot3_sim


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
