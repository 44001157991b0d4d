"""The compiled tracking errors against the Python reference they replace in the control cycle."""

from __future__ import annotations

import numpy as np

from baobab.nav.costmap import Costmap2D
from baobab.nav.feedback import PathTracking, path_tracking
from baobab.nav.path import Path
from baobab.nav.pure_pursuit import RegulatedPurePursuit
from baobab.nav.tracking_kernel import track
from baobab.sim.world import Pose2D


def _random_poses(rng: np.random.Generator, trial: int) -> np.ndarray:
    count = int(rng.integers(0, 8))
    poses = np.column_stack(
        [rng.uniform(-3, 3, count), rng.uniform(-3, 3, count), rng.uniform(-4, 4, count)]
    )
    if count > 2 and trial % 5 == 0:
        poses[1, :2] = poses[0, :2]  # a zero-length segment
    if count > 1 and trial % 7 == 0:
        poses[:, :2] = poses[0, :2]  # all segments zero-length: the pose's own yaw counts
    return poses


def _same(found: PathTracking, expected: PathTracking) -> bool:
    """The same segment and the same errors to the last bits: Python's ``math.hypot`` is
    correctly rounded, the C library's the kernel calls may differ in the last bit."""
    close = np.allclose(
        [found.position_error, found.heading_error],
        [expected.position_error, expected.heading_error],
        rtol=1e-13,
        atol=1e-15,
    )
    return found.index == expected.index and bool(close)


def test_the_kernel_equals_the_python_tracking() -> None:
    rng = np.random.default_rng(28)
    exact = 0
    for trial in range(600):
        poses = _random_poses(rng, trial)
        closest = int(rng.integers(-2, len(poses) + 2))
        x, y, yaw = (float(value) for value in rng.uniform(-4, 4, 3))
        expected = path_tracking(Path(poses), closest, x, y, yaw)
        found = PathTracking(*track(poses, closest, x, y, yaw))
        assert _same(found, expected), (trial, found, expected)
        exact += found == expected
    assert exact > 500  # most agree bit for bit


def test_the_controller_cycle_reports_the_tracking_of_its_closest_pose() -> None:
    rng = np.random.default_rng(5)
    costmap = Costmap2D(80, 80, 0.05, (-2.0, -2.0))
    points = np.column_stack([np.linspace(0, 1.5, 40), 0.3 * np.sin(np.linspace(0, 3, 40))])
    path = Path.from_points(points, 0.0)
    controller = RegulatedPurePursuit()
    for index in (0, 5, 12, 20, 31):
        x, y, yaw = path.poses[index]
        pose = Pose2D(x=x + rng.normal(0, 0.05), y=y + rng.normal(0, 0.05), yaw=yaw + 0.2)
        controller.compute_velocity(pose, (0.1, 0.0), path, costmap)
        closest = controller.closest_index
        assert closest >= index - 2
        expected = path_tracking(path, closest, pose.x, pose.y, pose.yaw)
        assert _same(controller.tracking, expected)
