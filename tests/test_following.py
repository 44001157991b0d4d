"""Nav2's following server over the sim: desired distance kept, stops, lost objects, limits.

The stated band: once the robot has closed in, it stays between ``desired_distance - 0.15`` m
(the linear tolerance) and ``desired_distance + 0.30`` m from the object: it stops within 0.15
m of the point ``desired_distance`` before the filtered pose, which lags a walking object by
the filter's 0.5 s time constant and the 5 Hz scans (8 cm at 0.15 m/s).
"""

from __future__ import annotations

import math

import pytest
from navigation_rig import NavRig, feedback_states, make_rig

from baobab.nav.errors import FollowObjectError
from baobab.nav.following import FollowingParams, FollowState
from baobab.nav.interfaces import FEEDBACK_KEY, RESULT_KEY
from baobab.sim.moving_object_motion import moving_object_pose, start_moving_objects
from baobab.sim.moving_objects import MovingObject, StartPose, VelocityStep, Waypoint
from baobab.sim.tasks import TaskHandle, TaskStatus
from baobab.sim.world import Box, Floor, Pose2D, World

DESIRED = FollowingParams().desired_distance
BAND = (DESIRED - 0.15, DESIRED + 0.30)
"""m: the distance kept from a walking object (module docstring)."""


def _rig(walker: MovingObject, start: Pose2D, boxes: list[Box] | None = None) -> NavRig:
    world = World(
        name="hall",
        floor=Floor(size=(10.0, 8.0)),
        boxes=boxes or [],
        spawns={"default": start},
        moving_objects=[walker],
    )
    rig = make_rig(world)
    start_moving_objects(rig.sim, world)
    return rig


def _distance(rig: NavRig) -> float:
    here, there = rig.pose(), moving_object_pose(rig.sim, "person")
    return math.hypot(there.x - here.x, there.y - here.y)


def _state(handle: TaskHandle) -> int | None:
    feedback = handle.feedback.get(FEEDBACK_KEY)
    return None if feedback is None else int(feedback.state)


def _follow(rig: NavRig, handle: TaskHandle, settle: float, limit: float) -> list[float]:
    """Distances (m) every 0.1 s after ``settle`` s, until ``handle`` ends."""
    seen: list[float] = []
    start = rig.sim.time
    while handle.status is TaskStatus.RUNNING:
        rig.sim.step_for(0.1)
        assert rig.sim.time - start < limit
        if rig.sim.time - start > settle:
            seen.append(_distance(rig))
    return seen


STRAIGHT = MovingObject(
    name="person",
    start_time=1.0,
    speed=0.15,
    waypoints=[Waypoint(x=-2.5, y=0.0), Waypoint(x=1.0, y=0.0, wait=1.0)],
)
CURVED = MovingObject(
    name="person",
    start_time=1.0,
    start=StartPose(x=-2.0, y=-1.5, yaw=0.0),
    velocity_profile=[VelocityStep(duration=22.0, linear=0.15, angular=0.1)],
)


@pytest.mark.parametrize(
    ("walker", "start"),
    [(STRAIGHT, Pose2D(x=-3.5, y=0.0, yaw=0.0)), (CURVED, Pose2D(x=-3.0, y=-1.5, yaw=0.0))],
    ids=["straight", "curved"],
)
def test_the_distance_stays_in_the_band_and_the_robot_stops_when_the_object_does(
    walker: MovingObject, start: Pose2D
) -> None:
    rig = _rig(walker, start)
    handle = rig.server.follow_object(walker.pose_topic, "", 28.0)
    distances = _follow(rig, handle, 4.0, 40.0)
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.SUCCEEDED
    assert BAND[0] <= min(distances) and max(distances) <= BAND[1], (min(distances), max(distances))
    result = handle.feedback[RESULT_KEY]
    assert result.total_elapsed_time.sec == 28 and result.error_code == 0
    assert not rig.contacts.touched


def test_a_stopped_object_stops_the_robot_within_the_tolerance() -> None:
    rig = _rig(STRAIGHT, Pose2D(x=-3.5, y=0.0, yaw=0.0))
    handle = rig.server.follow_object("", "person", 0.0)  # by its TF frame, no time limit
    rig.sim.step_for(30.0)
    assert _state(handle) == FollowState.STOPPING
    v, w = rig.robot.base.body_velocity()
    assert abs(v) < 0.01 and abs(w) < 0.05
    assert abs(_distance(rig) - DESIRED) <= FollowingParams().linear_tolerance + 0.01
    handle.cancel()
    assert handle.status is TaskStatus.CANCELED


# The person turns the corner of a wall and walks on behind it: the lidar loses it.
WALL = Box(name="wall", center=(0.7, 1.8), size=(0.2, 3.0))
HIDING = MovingObject(
    name="person",
    start_time=1.0,
    speed=0.15,
    waypoints=[Waypoint(x=-1.5, y=0.0), Waypoint(x=1.1, y=0.0), Waypoint(x=1.1, y=2.5)],
)


def test_a_lost_object_is_searched_for_the_detection_timeout_then_fails() -> None:
    rig = _rig(HIDING, Pose2D(x=-2.5, y=0.0, yaw=0.0), [WALL])
    handle = rig.server.follow_object("/person/pose", "", 0.0)
    _follow(rig, handle, 0.0, 60.0)
    assert handle.outcome is not None
    assert handle.outcome.error_code == FollowObjectError.FAILED_TO_DETECT_OBJECT
    result = handle.feedback[RESULT_KEY]
    assert result.num_retries == FollowingParams().max_retries + 1
    rig.sim.step_for(1.0)
    v, w = rig.robot.base.body_velocity()
    assert abs(v) < 0.01 and abs(w) < 0.05
    assert not rig.contacts.touched


def test_by_frame_the_object_is_never_lost() -> None:
    rig = _rig(HIDING, Pose2D(x=-2.5, y=0.0, yaw=0.0), [WALL])
    handle = rig.server.follow_object("", "person", 30.0)
    _follow(rig, handle, 0.0, 40.0)
    assert handle.outcome is not None and handle.outcome.status is TaskStatus.SUCCEEDED


def test_searching_by_rotating_turns_both_ways_then_fails_to_control() -> None:
    rig = _rig(HIDING, Pose2D(x=-2.5, y=0.0, yaw=0.0), [WALL])
    rig.server.following.params = FollowingParams(search_by_rotating=True)
    handle = rig.server.follow_object("/person/pose", "", 0.0)
    states: set[int] = set()
    while handle.status is TaskStatus.RUNNING:
        rig.sim.step_for(0.1)
        states.add(_state(handle) or 0)
        assert rig.sim.time < 80.0
    assert FollowState.RETRY in states
    assert handle.outcome is not None
    assert handle.outcome.error_code == FollowObjectError.FAILED_TO_CONTROL


def test_no_topic_and_no_frame_fails_at_once() -> None:
    rig = _rig(STRAIGHT, Pose2D(x=-3.5, y=0.0, yaw=0.0))
    handle = rig.server.follow_object("", "", 0.0)
    rig.sim.step_for(0.2)
    assert handle.outcome is not None
    assert handle.outcome.error_code == FollowObjectError.FAILED_TO_DETECT_OBJECT


def test_the_simple_commander_follows_by_topic_and_by_frame() -> None:
    from baobab.nav.navigator import BasicNavigator, TaskResult
    from baobab.nav.ros.nav2_msgs import action

    world = World(
        name="hall",
        floor=Floor(size=(10.0, 8.0)),
        spawns={"default": Pose2D(x=-3.5, y=0.0, yaw=0.0)},
        moving_objects=[STRAIGHT],
    )
    navigator = BasicNavigator(world=world)
    try:
        assert navigator.followObjectByTopic("/person/pose", max_duration=5) is not None
        states = feedback_states(navigator)
        assert navigator.getResult() is TaskResult.SUCCEEDED
        assert action.FollowObject.Feedback.CONTROLLING in states
        assert navigator.result_future is not None
        assert navigator.result_future.result().result.total_elapsed_time.sec == 5
        assert navigator.followObjectByFrame("nobody", max_duration=20) is not None
        while not navigator.isTaskComplete():
            pass
        assert navigator.getTaskError()[0] == action.FollowObject.Result.FAILED_TO_DETECT_OBJECT
    finally:
        navigator.destroyNode()
