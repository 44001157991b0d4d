"""ROS-shaped messages and rclpy time semantics (baobab.nav.msgs, baobab.nav.rostime)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from baobab.nav.msgs import (
    ClockType,
    Costmap,
    Duration,
    DurationMsg,
    Header,
    MessageValueError,
    OccupancyGrid,
    Path,
    Point,
    Pose,
    PoseStamped,
    PoseWithCovarianceStamped,
    Quaternion,
    Time,
    TimeMsg,
    Twist,
    from_pose2d,
    pose_stamped,
    quaternion_from_yaw,
    to_pose2d,
    yaw_from_quaternion,
)
from baobab.nav.rostime import Clock, Infinite
from baobab.sim.world import Pose2D

# --- messages -------------------------------------------------------------------------------


def test_fresh_messages_have_ros_defaults() -> None:
    pose = PoseStamped()
    assert pose.header.frame_id == ""
    assert pose.header.stamp == TimeMsg(sec=0, nanosec=0)
    assert (pose.pose.position.x, pose.pose.position.y, pose.pose.position.z) == (0, 0, 0)
    orientation = pose.pose.orientation
    assert (orientation.x, orientation.y, orientation.z, orientation.w) == (0.0, 0.0, 0.0, 1.0)
    twist = Twist()
    assert (twist.linear.x, twist.angular.z) == (0.0, 0.0)
    assert Path().poses == []
    covariance = PoseWithCovarianceStamped().pose.covariance
    assert covariance.dtype == "float64" and covariance.tolist() == [0.0] * 36
    grid = OccupancyGrid()
    assert (grid.info.width, grid.info.height, grid.info.resolution) == (0, 0, 0.0)
    assert grid.data.typecode == "b" and len(grid.data) == 0
    costmap = Costmap()
    assert (costmap.metadata.size_x, costmap.metadata.size_y) == (0, 0)
    assert costmap.data.typecode == "B"


def test_fresh_messages_do_not_share_nested_fields() -> None:
    first, second = PoseStamped(), PoseStamped()
    first.pose.position.x = 5.0
    first.header.frame_id = "map"
    assert second.pose.position.x == 0.0 and second.header.frame_id == ""
    Path().poses.append(first)
    assert Path().poses == []


def test_messages_are_keyword_only_and_reject_unknown_fields_like_ros() -> None:
    with pytest.raises(TypeError):
        Point(1.0, 2.0)  # type: ignore[call-arg]
    with pytest.raises(AssertionError, match="Invalid arguments passed to constructor: w"):
        Point(w=1.0)  # type: ignore[call-arg]
    pose = Pose()
    with pytest.raises(AttributeError):
        pose.positon = Point()  # type: ignore[attr-defined]
    assert Point(x=1.0, y=2.0) == Point(x=1.0, y=2.0) != Point(x=1.0)


def test_pose_stamped_built_field_by_field_as_the_seed_scripts_do() -> None:
    clock = Clock(clock_type=ClockType.ROS_TIME, source=lambda: 12.25)
    goal_pose = PoseStamped()
    goal_pose.header.frame_id = "map"
    goal_pose.header.stamp = clock.now().to_msg()
    goal_pose.pose.position.x = 1.3
    goal_pose.pose.position.y = 6.0
    goal_pose.pose.position.z = 0.0
    goal_pose.pose.orientation.x = 0.0
    goal_pose.pose.orientation.y = 0.0
    goal_pose.pose.orientation.z = 0.23
    goal_pose.pose.orientation.w = 0.97
    assert goal_pose.header == Header(stamp=TimeMsg(sec=12, nanosec=250_000_000), frame_id="map")
    assert goal_pose.pose.position == Point(x=1.3, y=6.0, z=0.0)
    assert goal_pose.pose.orientation == Quaternion(z=0.23, w=0.97)


def test_pose_stamped_assembled_from_parts_as_the_generator_seed_does() -> None:
    clock = Clock(clock_type=ClockType.ROS_TIME, source=lambda: 3.5)
    header = Header()
    header.frame_id = "map"
    now = clock.now()
    header.stamp = TimeMsg(sec=now.seconds_nanoseconds()[0], nanosec=now.seconds_nanoseconds()[1])
    pose = Pose()
    pose.position = Point(x=1.0, y=2.0)
    pose.orientation = Quaternion(z=1.0, w=0.0)
    pose_stamped_msg = PoseStamped()
    pose_stamped_msg.header = header
    pose_stamped_msg.pose = pose
    assert pose_stamped_msg.header.stamp == TimeMsg(sec=3, nanosec=500_000_000)
    assert to_pose2d(pose_stamped_msg).yaw == pytest.approx(math.pi)


def test_grid_data_is_a_flat_int8_buffer_numpy_can_view() -> None:
    grid = OccupancyGrid()
    grid.info.width, grid.info.height = 3, 2
    grid.data.extend([0, 100, -1, 0, 50, 0])
    cells = np.frombuffer(grid.data, dtype=np.int8).reshape(grid.info.height, grid.info.width)
    assert cells[0, 2] == -1 and cells[1, 1] == 50
    with pytest.raises(OverflowError):
        grid.data.append(200)


# --- Duration -------------------------------------------------------------------------------


def test_duration_stores_integer_nanoseconds() -> None:
    assert Duration(seconds=1.5).nanoseconds == 1_500_000_000
    assert Duration(seconds=2, nanoseconds=7).nanoseconds == 2_000_000_007
    assert Duration(nanoseconds=2.9).nanoseconds == 2
    assert Duration(seconds=-0.25).nanoseconds == -250_000_000
    assert repr(Duration(seconds=1)) == "Duration(nanoseconds=1000000000)"
    assert str(Infinite) == "Infinite"
    with pytest.raises(OverflowError):
        Duration(seconds=1e10)


def test_duration_message_round_trip_including_negative_spans() -> None:
    assert Duration(seconds=2.5).to_msg() == DurationMsg(sec=2, nanosec=500_000_000)
    assert Duration(seconds=-1.5).to_msg() == DurationMsg(sec=-2, nanosec=500_000_000)
    for nanoseconds in (0, 1, 999_999_999, -1, -3_000_000_001, 123_456_789_012):
        duration = Duration(nanoseconds=nanoseconds)
        assert Duration.from_msg(duration.to_msg()) == duration


def test_duration_from_msg_accepts_only_the_builtin_interfaces_message() -> None:
    with pytest.raises(TypeError, match=r"builtin_interfaces\.msg\.Duration"):
        Duration.from_msg(Duration(seconds=1))  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        Duration.from_msg(TimeMsg(sec=1))  # type: ignore[arg-type]


def test_duration_comparisons_and_arithmetic_follow_rclpy() -> None:
    one, two = Duration(seconds=1), Duration(seconds=2)
    assert one < two <= two and two > one >= one and one != two
    assert one + one == two and two - one == one and one - two == Duration(seconds=-1)
    assert one * 3 == Duration(seconds=3) and one * 0.5 == Duration(seconds=0.5)
    assert (one * math.inf) is Infinite
    assert (one == 1) is False  # rclpy returns NotImplemented, so == falls back to identity
    with pytest.raises(TypeError):
        _ = one < 1  # type: ignore[operator]
    with pytest.raises(TypeError):
        _ = one + 1  # type: ignore[operator]
    with pytest.raises(TypeError):
        _ = 3 * one  # type: ignore[operator]
    with pytest.raises(ValueError):
        _ = one * math.nan
    with pytest.raises(TypeError):
        hash(one)


def test_seed_idiom_feedback_navigation_time_against_a_timeout() -> None:
    @dataclass
    class Feedback:
        navigation_time: DurationMsg
        distance_remaining: float

    feedback = Feedback(Duration(seconds=600.1).to_msg(), 3.0)
    assert Duration.from_msg(feedback.navigation_time) > Duration(seconds=600.0)
    assert Duration.from_msg(feedback.navigation_time) > Duration(seconds=120.0)
    feedback.navigation_time = Duration(seconds=119.9).to_msg()
    assert not Duration.from_msg(feedback.navigation_time) > Duration(seconds=120.0)
    eta = Duration.from_msg(DurationMsg(sec=42, nanosec=600_000_000)).nanoseconds / 1e9
    assert f"{eta:.0f}" == "43"


# --- Time -----------------------------------------------------------------------------------


def test_time_points_are_non_negative_with_a_clock_type() -> None:
    stamp = Time(seconds=3, nanoseconds=250)
    assert stamp.nanoseconds == 3_000_000_250 and stamp.clock_type is ClockType.SYSTEM_TIME
    assert stamp.seconds_nanoseconds() == (3, 250)
    assert repr(stamp) == "Time(nanoseconds=3000000250, clock_type=SYSTEM_TIME)"
    with pytest.raises(ValueError):
        Time(seconds=-1)
    with pytest.raises(ValueError):
        Time(nanoseconds=-1)
    with pytest.raises(TypeError):
        Time(clock_type=1)  # type: ignore[arg-type]


def test_time_message_round_trip_defaults_to_ros_time() -> None:
    stamp = Time(seconds=12.5, clock_type=ClockType.ROS_TIME)
    assert stamp.to_msg() == TimeMsg(sec=12, nanosec=500_000_000)
    assert Time.from_msg(stamp.to_msg()) == stamp
    assert Time.from_msg(stamp.to_msg()).clock_type is ClockType.ROS_TIME
    steady = Time.from_msg(TimeMsg(sec=1), clock_type=ClockType.STEADY_TIME)
    assert steady.clock_type is ClockType.STEADY_TIME
    with pytest.raises(TypeError, match=r"builtin_interfaces\.msg\.Time"):
        Time.from_msg(stamp)  # type: ignore[arg-type]


def test_time_and_duration_arithmetic_follow_rclpy() -> None:
    start = Time(seconds=10, clock_type=ClockType.ROS_TIME)
    later = Time(seconds=12.5, clock_type=ClockType.ROS_TIME)
    assert later - start == Duration(seconds=2.5)
    assert start - later == Duration(seconds=-2.5)
    assert start + Duration(seconds=2.5) == later == Duration(seconds=2.5) + start
    assert later - Duration(seconds=2.5) == start
    assert (start + Duration(seconds=1)).clock_type is ClockType.ROS_TIME
    assert start < later and later >= start and start != later
    with pytest.raises(ValueError, match="negative time"):
        _ = start - Duration(seconds=11)
    with pytest.raises(TypeError):
        _ = start + later  # type: ignore[operator]
    with pytest.raises(TypeError):
        _ = start - 1  # type: ignore[operator]
    with pytest.raises(TypeError):
        _ = start < Duration(seconds=1)  # type: ignore[operator]
    assert (start == Duration(seconds=10)) is False


def test_times_of_different_clocks_neither_compare_nor_subtract() -> None:
    ros = Time(seconds=1, clock_type=ClockType.ROS_TIME)
    system = Time(seconds=1, clock_type=ClockType.SYSTEM_TIME)
    with pytest.raises(TypeError, match="different clock types"):
        _ = ros == system
    with pytest.raises(TypeError, match="different clock types"):
        _ = ros < system
    with pytest.raises(TypeError, match="different clock types"):
        _ = ros - system


def test_seed_idiom_clock_now_to_msg_and_elapsed_time() -> None:
    sim_time = [0.0]
    clock = Clock(clock_type=ClockType.ROS_TIME, source=lambda: sim_time[0])
    nav_start = clock.now()
    sim_time[0] = 100.2
    now = clock.now()
    assert now.to_msg() == TimeMsg(sec=100, nanosec=200_000_000)
    assert now - nav_start > Duration(seconds=100.0)
    assert not now - nav_start > Duration(seconds=500000.0)
    assert clock.clock_type is ClockType.ROS_TIME and now.clock_type is ClockType.ROS_TIME
    assert Clock().now().clock_type is ClockType.SYSTEM_TIME


# --- pose helpers ---------------------------------------------------------------------------


def test_pose_stamped_helper_fills_every_field() -> None:
    stamp = Time(seconds=4.5, clock_type=ClockType.ROS_TIME)
    goal = pose_stamped(1.0, -2.0, math.pi / 2, frame_id="odom", stamp=stamp)
    assert goal.header == Header(stamp=TimeMsg(sec=4, nanosec=500_000_000), frame_id="odom")
    assert goal.pose.position == Point(x=1.0, y=-2.0, z=0.0)
    q = goal.pose.orientation
    assert (q.x, q.y) == (0.0, 0.0)
    assert (q.z, q.w) == pytest.approx((math.sqrt(0.5), math.sqrt(0.5)))
    assert pose_stamped(0, 0).header == Header(frame_id="map")


@pytest.mark.parametrize("yaw", [0.0, 0.3, -1.2, math.pi / 2, 3.0, -3.0])
def test_pose2d_round_trip(yaw: float) -> None:
    pose = Pose2D(x=1.25, y=-0.5, yaw=yaw)
    stamped = from_pose2d(pose, frame_id="map", stamp=TimeMsg(sec=2))
    assert stamped.header == Header(stamp=TimeMsg(sec=2), frame_id="map")
    back = to_pose2d(stamped)
    assert (back.x, back.y) == (1.25, -0.5)
    assert back.yaw == pytest.approx(yaw, abs=1e-12)
    assert to_pose2d(stamped.pose) == back


def test_yaw_is_wrapped_and_quaternion_sign_does_not_matter() -> None:
    assert to_pose2d(pose_stamped(0, 0, 3 * math.pi / 2)).yaw == pytest.approx(-math.pi / 2)
    q = quaternion_from_yaw(0.7)
    negated = Quaternion(x=-q.x, y=-q.y, z=-q.z, w=-q.w)
    assert yaw_from_quaternion(negated) == pytest.approx(0.7)


@pytest.mark.parametrize(
    ("z", "w", "yaw"),
    [
        (0.23, 0.97, 2 * math.atan2(0.23, 0.97)),
        (0.707, -0.707, -math.pi / 2),
        (0.92, -0.38, 2 * math.atan2(-0.92, 0.38)),
        (1.0, 0.0, math.pi),
        (0.0, 2.0, 0.0),
    ],
)
def test_seed_quaternions_that_are_not_unit_length_are_normalised(
    z: float, w: float, yaw: float
) -> None:
    pose = Pose(orientation=Quaternion(z=z, w=w))
    assert abs(to_pose2d(pose).yaw) == pytest.approx(abs(yaw), abs=1e-12)
    assert math.cos(to_pose2d(pose).yaw - yaw) == pytest.approx(1.0)


def test_meaningless_poses_raise_message_value_errors() -> None:
    with pytest.raises(MessageValueError, match="zero norm"):
        to_pose2d(Pose(orientation=Quaternion(w=0.0)))
    with pytest.raises(MessageValueError, match="non-finite"):
        to_pose2d(Pose(orientation=Quaternion(z=math.nan)))
    with pytest.raises(MessageValueError, match="not finite"):
        to_pose2d(Pose(position=Point(x=math.inf)))
    assert issubclass(MessageValueError, ValueError)
