"""Paths as ``nav_msgs/Path``: vectorised quaternions checked against scipy, and poses made only
when read (baobab.nav.msgs, baobab.nav.navigator_messages, baobab.nav.rosmsg)."""

from __future__ import annotations

import copy
import pickle

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from baobab.nav import msgs
from baobab.nav.errors import GoalRejectedError
from baobab.nav.navigator_messages import path_from_message, path_message
from baobab.nav.path import Path
from baobab.nav.rosmsg import deferred_source

STAMP = msgs.TimeMsg(sec=12, nanosec=500)


def _random_path(count: int = 200, seed: int = 0) -> Path:
    rng = np.random.default_rng(seed)
    poses = np.column_stack(
        [rng.uniform(-8, 8, count), rng.uniform(-8, 8, count), rng.uniform(-7, 7, count)]
    )
    return Path(poses)


def _scipy_pose_stamped(x: float, y: float, yaw: float, stamp: msgs.TimeMsg) -> msgs.PoseStamped:
    """The reference: each quaternion from scipy's Rotation, every field set through its check."""
    qx, qy, qz, qw = (float(v) for v in Rotation.from_euler("z", yaw).as_quat())
    return msgs.PoseStamped(
        header=msgs.Header(
            stamp=msgs.TimeMsg(sec=stamp.sec, nanosec=stamp.nanosec), frame_id="map"
        ),
        pose=msgs.Pose(
            position=msgs.Point(x=x, y=y),
            orientation=msgs.Quaternion(x=qx, y=qy, z=qz, w=qw),
        ),
    )


def _components(pose: msgs.PoseStamped) -> list[float]:
    p, q = pose.pose.position, pose.pose.orientation
    return [p.x, p.y, p.z, q.x, q.y, q.z, q.w]


@pytest.mark.parametrize("yaw", [0.0, 0.3, -1.2, np.pi, -np.pi, 3.5, -6.0, 12.0])
def test_quaternion_from_yaw_matches_scipy(yaw: float) -> None:
    reference = Rotation.from_euler("z", yaw).as_quat()
    q = msgs.quaternion_from_yaw(yaw)
    assert [q.x, q.y, q.z, q.w] == pytest.approx(reference.tolist(), abs=1e-15)


def test_stamped_poses_match_scipy_built_messages_field_for_field() -> None:
    path = _random_path()
    built = msgs.stamped_poses(path.poses, "map", STAMP)
    reference = [_scipy_pose_stamped(x, y, yaw, STAMP) for x, y, yaw in path.poses.tolist()]
    assert len(built) == len(reference)
    for mine, theirs in zip(built, reference, strict=True):
        assert _components(mine) == pytest.approx(_components(theirs), abs=1e-15)
        assert mine.header == theirs.header
        assert type(mine.pose.position.x) is float


def test_stamped_poses_are_separate_mutable_messages() -> None:
    first, second = msgs.stamped_poses(np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]))
    first.header.stamp.sec = 5
    first.pose.position.x = 2.0
    assert second.header.stamp.sec == 0
    assert second.pose.position.x == 1.0
    with pytest.raises(AssertionError):
        first.pose.position.y = 1  # the setters still check values: an int is no double


def test_stamped_poses_refuse_non_finite_values() -> None:
    with pytest.raises(msgs.MessageValueError, match="finite"):
        msgs.stamped_poses(np.array([[0.0, np.nan, 0.0]]))


def test_yaws_from_quaternions_match_scipy_one_by_one() -> None:
    rng = np.random.default_rng(1)
    quaternions = rng.normal(size=(300, 4)) * rng.uniform(0.1, 3.0, size=(300, 1))
    yaws = msgs.yaws_from_quaternions(quaternions)
    for q, yaw in zip(quaternions.tolist(), yaws.tolist(), strict=True):
        reference = float(Rotation.from_quat(q).as_euler("ZYX")[0])
        assert yaw == pytest.approx(reference, abs=1e-12)


def test_yaws_from_quaternions_refuse_a_zero_quaternion() -> None:
    with pytest.raises(msgs.MessageValueError, match="zero norm"):
        msgs.yaws_from_quaternions(np.array([[0.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0, 0.0]]))


def test_path_message_makes_its_poses_only_when_read() -> None:
    path = _random_path()
    message = path_message(path, STAMP)
    assert deferred_source(message, "poses") is path
    assert message.header.frame_id == "map"
    assert len(message.poses) == len(path)
    assert deferred_source(message, "poses") is None
    reference = [_scipy_pose_stamped(x, y, yaw, STAMP) for x, y, yaw in path.poses.tolist()]
    for mine, theirs in zip(message.poses, reference, strict=True):
        assert _components(mine) == pytest.approx(_components(theirs), abs=1e-15)


def test_an_unread_path_message_goes_back_to_its_planner_path_unconverted() -> None:
    path = _random_path()
    assert path_from_message(path_message(path, STAMP)) is path


def test_a_read_path_message_converts_back_with_scipy_yaws() -> None:
    path = _random_path()
    message = path_message(path, STAMP)
    message.poses[3].pose.position.x = 42.0
    back = path_from_message(message)
    assert back is not path
    assert back.poses[3, 0] == 42.0
    yaws = [float(Rotation.from_euler("z", yaw).as_euler("ZYX")[0]) for yaw in path.poses[:, 2]]
    assert back.poses[:, 2] == pytest.approx(yaws, abs=1e-12)


def test_a_bad_pose_in_a_read_path_is_named_by_its_index() -> None:
    message = path_message(_random_path(20), STAMP)
    message.poses[7].pose.orientation = msgs.Quaternion(w=0.0)
    with pytest.raises(GoalRejectedError, match=r"path pose 7 is invalid: .*zero norm"):
        path_from_message(message)
    message.poses[7].pose.orientation = msgs.Quaternion()
    message.poses[4].header.frame_id = "odom"
    with pytest.raises(GoalRejectedError, match="path pose 4 is in frame 'odom'"):
        path_from_message(message)


def test_lazy_path_messages_copy_compare_and_pickle_as_built_ones() -> None:
    path = _random_path(30)
    eager = msgs.Path(
        header=msgs.Header(stamp=msgs.TimeMsg(sec=12, nanosec=500), frame_id="map"),
        poses=[_scipy_pose_stamped(x, y, yaw, STAMP) for x, y, yaw in path.poses.tolist()],
    )
    copied = copy.deepcopy(path_message(path, STAMP))
    assert deferred_source(copied, "poses") is path  # a copy stays unbuilt
    assert pickle.loads(pickle.dumps(path_message(path, STAMP))) == path_message(path, STAMP)
    lazy = path_message(path, STAMP)
    assert lazy.header == eager.header
    for mine, theirs in zip(lazy.poses, eager.poses, strict=True):
        assert _components(mine) == pytest.approx(_components(theirs), abs=1e-15)


def test_unchecked_messages_need_every_field() -> None:
    with pytest.raises(TypeError, match="exactly the fields"):
        msgs.Point.unchecked(x=1.0, y=2.0)
    assert msgs.Point.unchecked(x=1.0, y=2.0, z=0.0) == msgs.Point(x=1.0, y=2.0)
