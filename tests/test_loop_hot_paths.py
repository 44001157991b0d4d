"""Code on the run loop's 20 Hz path, rewritten for speed, against the code it replaced."""

from __future__ import annotations

import math
from collections import deque
from typing import Any

import numpy as np
import py_trees

from baobab.nav.bt import Condition, RecoveryNode, tick_child
from baobab.nav.controller_server import PathFollower
from baobab.nav.costmap import Costmap2D
from baobab.nav.feedback import PathTracking, SpeedFilter, path_tracking
from baobab.nav.path import Path, wrap_angle
from baobab.sim.world import Pose2D

Status = py_trees.common.Status


def _path_tracking_reference(
    path: Path, closest: int, x: float, y: float, yaw: float
) -> PathTracking:
    """``path_tracking`` as it was before issue 28 (numpy scalars read one by one)."""
    poses = path.poses
    count = len(poses)
    if count == 0:
        return PathTracking(0.0, 0.0, 0)
    closest = min(max(closest, 0), count - 1)
    candidates = [i for i in (closest - 1, closest) if i >= 0 and i + 1 < count]
    best: tuple[float, float, int] | None = None
    for start in candidates:
        ax, ay = float(poses[start, 0]), float(poses[start, 1])
        dx, dy = float(poses[start + 1, 0]) - ax, float(poses[start + 1, 1]) - ay
        length = math.hypot(dx, dy)
        if length < 1e-9:
            continue
        along = min(max(((x - ax) * dx + (y - ay) * dy) / length, 0.0), length)
        gap = math.hypot(x - (ax + dx * along / length), y - (ay + dy * along / length))
        if best is None or gap < best[0]:
            cross = (dx * (y - ay) - dy * (x - ax)) / length
            best = (gap, cross, start)
    if best is None:
        ax, ay, heading = (float(value) for value in poses[closest])
        cross = math.cos(heading) * (y - ay) - math.sin(heading) * (x - ax)
        return PathTracking(cross, wrap_angle(heading - yaw), closest)
    _, cross, start = best
    heading = math.atan2(
        float(poses[start + 1, 1] - poses[start, 1]), float(poses[start + 1, 0] - poses[start, 0])
    )
    return PathTracking(cross, wrap_angle(heading - yaw), start)


def test_path_tracking_equals_the_replaced_code_bit_for_bit() -> None:
    rng = np.random.default_rng(3)
    for trial in range(400):
        count = int(rng.integers(0, 8))
        poses = np.column_stack(
            [rng.uniform(-3, 3, count), rng.uniform(-3, 3, count), rng.uniform(-4, 4, count)]
        )
        if count > 2 and trial % 5 == 0:
            poses[1, :2] = poses[0, :2]  # a zero-length segment
        path = Path(poses)
        closest = int(rng.integers(-2, count + 2))
        x, y, yaw = rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-4, 4)
        assert path_tracking(path, closest, x, y, yaw) == _path_tracking_reference(
            path, closest, x, y, yaw
        )


class _SpeedFilterReference:
    """``SpeedFilter`` as it was before (one deque of (time, speed) pairs, a generator sum)."""

    def __init__(self, filter_duration: float) -> None:
        self.filter_duration = filter_duration
        self._samples: deque[tuple[float, float]] = deque()

    def add(self, now: float, speed: float) -> float:
        samples = self._samples
        samples.append((now, speed))
        while samples and samples[0][0] < now - self.filter_duration - 1e-9:
            samples.popleft()
        return sum(value for _, value in samples) / len(samples)


def test_speed_filter_equals_the_replaced_code_bit_for_bit() -> None:
    rng = np.random.default_rng(11)
    for _ in range(20):
        duration = float(rng.choice([0.0, 0.05, 0.3, 1.0]))
        new, old = SpeedFilter(duration), _SpeedFilterReference(duration)
        now = 0.0
        for _ in range(200):
            now += float(rng.choice([0.05, 0.1, 0.0]))
            speed = float(rng.uniform(-0.3, 0.3))
            assert new.add(now, speed) == old.add(now, speed)


class _Base:
    """A base that stays where it is told (the controller's commands are recorded)."""

    def __init__(self, pose: Pose2D, speed: float) -> None:
        self.at, self.speed = pose, speed
        self.commands: list[tuple[float, float]] = []

    def pose(self) -> Pose2D:
        return self.at

    def body_velocity(self) -> tuple[float, float]:
        return (self.speed, 0.0)

    def command(self, linear: float, angular: float) -> None:
        self.commands.append((linear, angular))

    def stop(self) -> None:
        self.commands.append((0.0, 0.0))


def _tracking_reference(follower: PathFollower, path: Path, pose: Pose2D) -> dict[str, Any]:
    """The controller's tracking feedback as it was built before (a dict every cycle)."""
    tracking = follower.controller.tracking
    goal, remaining = path.goal, follower.remaining_length()
    return {
        "position_tracking_error": tracking.position_error,
        "heading_tracking_error": tracking.heading_error,
        "current_path_index": tracking.index,
        "robot_pose": pose,
        "distance_to_goal": math.hypot(goal.x - pose.x, goal.y - pose.y),
        "speed": follower.base.body_velocity()[0],
        "remaining_path_length": remaining,
    }


def test_the_controllers_tracking_feedback_is_its_own_cycles_when_read_later() -> None:
    costmap = Costmap2D(60, 60, 0.05, (-1.5, -1.5))
    xs = np.linspace(0.0, 4.0, 81)
    path = Path(np.column_stack([xs, 0.1 * np.sin(xs), np.zeros_like(xs)]))
    base = _Base(Pose2D(x=0.0, y=0.05, yaw=0.1), 0.1)
    follower = PathFollower(base, lambda: costmap)
    follower.start(path, 0.0)
    expected, kept = [], []
    for cycle in range(5):
        base.at = Pose2D(x=0.1 * cycle, y=0.05 - 0.01 * cycle, yaw=0.1 - 0.03 * cycle)
        base.speed = 0.05 * cycle
        assert follower.cycle(0.05 * cycle) is None
        expected.append(_tracking_reference(follower, path, base.at))
        kept.append(follower.feedback["tracking_feedback"])
    # Read only now, after later cycles: each holds its own cycle's fields, in Nav2's order.
    for tracking, fields in zip(kept, expected, strict=True):
        assert isinstance(tracking, dict)
        assert list(tracking.items()) == list(fields.items())
        assert dict(tracking) == fields and tracking == fields


def test_the_direct_tick_reaches_py_trees_own_nodes_through_their_generators() -> None:
    """A RecoveryNode (baobab's, ticked directly) over a py_trees Sequence of conditions."""
    answers = {"action": False, "fix": True}
    action = py_trees.composites.Sequence(
        "Action", memory=True, children=[Condition("A", lambda: answers["action"])]
    )
    root = RecoveryNode("Root", 1, [action, Condition("Fix", lambda: answers["fix"])])
    assert tick_child(root) is Status.FAILURE  # the action failed, was fixed, failed again
    assert root.retry_count == 1
    answers["action"] = True
    assert tick_child(root) is Status.SUCCESS
    root.tick_once()  # py_trees' generator form gives the same
    assert root.status is Status.SUCCESS
