"""Two identical runs give bitwise identical trajectories: same seed, same physics, same bits."""

from __future__ import annotations

import numpy as np

from baobab.robots.diff_drive import Bug2Controller
from baobab.robots.turtlebot3 import build_turtlebot3_sim


def _trajectory(seed: int) -> tuple[np.ndarray, np.ndarray]:
    """qpos every 0.1 s and every scan of 12 s of a noisy Bug2 run toward goal_behind_wall."""
    sim, robot = build_turtlebot3_sim("walls", seed=seed, lidar_noise_std=0.01)
    bug = Bug2Controller(sim, robot.base, robot.lidar)
    bug.set_goal(2.2, 0.0)
    positions: list[np.ndarray] = []
    scans: list[np.ndarray] = []
    robot.lidar.subscribe(lambda scan: scans.append(scan.ranges))
    sim.every(0.1, lambda _t: positions.append(sim.data.qpos.copy()), name="record")
    sim.step_for(12.0)
    assert robot.base.pose().x > 0.5  # the robot did drive to the wall and along it
    return np.array(positions), np.array(scans)


def test_identical_runs_are_bitwise_identical() -> None:
    first_qpos, first_scans = _trajectory(seed=5)
    second_qpos, second_scans = _trajectory(seed=5)
    assert first_qpos.shape == (120, second_qpos.shape[1])
    np.testing.assert_array_equal(first_qpos, second_qpos)
    np.testing.assert_array_equal(first_scans, second_scans)


def test_the_seed_reaches_the_noise() -> None:
    _, first_scans = _trajectory(seed=5)
    _, other_scans = _trajectory(seed=6)
    finite = np.isfinite(first_scans[0]) & np.isfinite(other_scans[0])
    assert not np.array_equal(first_scans[0][finite], other_scans[0][finite])
