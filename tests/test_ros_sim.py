"""Nodes written as the seed's exercises, run unmodified against the simulation on its ROS
topics (baobab.nav.ros.bringup, sim_topics): they meet the exercises' expectations."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from ros_harness import BUNDLED_NODES, ROS_NODES, run_node_files, write_nodes

from baobab.nav.ros.bringup import Bringup, bring_up
from baobab.nav.ros.runtime import RosRuntime, RunEnd

POINT2POINT = BUNDLED_NODES / "point2point_nav.py"


def goal(x: float, y: float) -> Any:
    from geometry_msgs.msg import PoseStamped

    message = PoseStamped()
    message.header.frame_id = "odom"
    message.pose.position.x, message.pose.position.y = x, y
    return message


def drive(node: Path, target: tuple[float, float], duration: float) -> tuple[Bringup, RunEnd, Any]:
    """Run ``node`` in the walls world, send it ``target`` on /goal at 1 s."""
    bringup = bring_up("turtlebot3", "walls")
    assert bringup.mobile is not None
    probe = bringup.mobile.base.start_probe(
        pose_period=0.1, contact_period=0.01, drain_period=duration + 1
    )
    end = run_node_files(
        bringup.runtime,
        [node],
        duration,
        before=lambda runtime: runtime.publish_at(1.0, "/goal", goal(*target)),
    )
    return bringup, end, probe


def test_point2point_reaches_the_goal_within_tolerance_without_contact(
    capsys: pytest.CaptureFixture[str],
) -> None:
    bringup, end, probe = drive(POINT2POINT, (2.0, 2.0), 25.0)
    assert end.failures == [] and probe.touched() == []
    assert bringup.mobile is not None
    truth = bringup.mobile.base.pose()
    # The node stops within its 0.05 m goal_tolerance by wheel odometry; odometry drifts a
    # few centimetres over the 2.8 m drive.
    assert math.hypot(truth.x - 2.0, truth.y - 2.0) < 0.08
    err = capsys.readouterr().err
    assert "[INFO] [1.000000000] [point2point_nav]: New goal: (2.00, 2.00)" in err
    assert "[point2point_nav]: Goal reached" in err


def test_bug2_follows_the_wall_around_to_a_goal_behind_it(
    capsys: pytest.CaptureFixture[str],
) -> None:
    bringup, end, probe = drive(ROS_NODES / "bug_nav.py", (2.2, 0.0), 60.0)
    assert end.failures == [] and probe.touched() == []
    assert bringup.mobile is not None
    truth = bringup.mobile.base.pose()
    assert math.hypot(truth.x - 2.2, truth.y) < 0.1
    err = capsys.readouterr().err
    hit, leave, reached = (err.index(text) for text in ("Hit point", "Leave point", "Goal reached"))
    assert hit < leave < reached


def test_two_runs_give_the_same_digest_and_timers_tick_at_multiples_of_their_period() -> None:
    digests = set()
    for _ in range(2):
        bringup, end, _ = drive(POINT2POINT, (2.0, 2.0), 6.0)
        assert end.failures == []
        digests.add(bringup.runtime.trace_digest)
    assert len(digests) == 1


TELEOP_KEYS = [
    (1.0, "press", "w"),
    (3.0, "release", "w"),
    (3.5, "press", "a"),
    (4.5, "release", "a"),
]


def test_keyboard_teleop_drives_the_robot_with_injected_key_events() -> None:
    bringup = bring_up("turtlebot3", "walls")
    assert bringup.mobile is not None

    def keys(runtime: RosRuntime) -> None:
        for time, action, key in TELEOP_KEYS:
            runtime.at(time, lambda action=action, key=key: getattr(runtime.keyboard, action)(key))

    end = run_node_files(bringup.runtime, [ROS_NODES / "keyboard_teleop.py"], 6.0, before=keys)
    assert end.failures == []
    pose = bringup.mobile.base.pose()
    # 2 s forward: the node asks 0.25 m/s, the Burger's base clips it to its 0.22 m/s; then
    # 1 s turning at 1.2 rad/s.
    assert pose.x == pytest.approx(0.44, abs=0.02) and abs(pose.y) < 0.02
    assert pose.yaw == pytest.approx(1.2, abs=0.1)


SENSORS = """\
import rclpy
import rclpy.time
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, JointState, LaserScan
from tf2_ros import Buffer, TransformListener

def main():
    rclpy.init()
    node = Node('sensors')
    seen = {}
    def keep(topic):
        return lambda message: seen.setdefault(topic, []).append(message)
    for topic, kind, qos in (('/odom', Odometry, 10), ('/scan', LaserScan, qos_profile_sensor_data),
                             ('/imu', Imu, qos_profile_sensor_data), ('/joint_states', JointState, 10),
                             ('/clock', Clock, 10)):
        node.create_subscription(kind, topic, keep(topic), qos)
    buffer = Buffer()
    TransformListener(buffer, node)
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
    stamps = {topic: [m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for m in messages]
              for topic, messages in seen.items() if topic != '/clock'}
    scan, imu, joints = seen['/scan'][-1], seen['/imu'][-1], seen['/joint_states'][-1]
    chain = buffer.lookup_transform('map', 'base_scan', rclpy.time.Time()).transform.translation
    print({topic: len(values) for topic, values in stamps.items()}, len(seen['/clock']))
    print(stamps['/scan'][:3], stamps['/odom'][:3])
    print(len(scan.ranges), round(scan.angle_increment, 4), scan.header.frame_id, round(min(scan.ranges), 2))
    print(round(imu.linear_acceleration.z, 2), joints.name)
    print(round(chain.x, 3), round(chain.y, 3), round(chain.z, 3))
"""


def test_the_robot_publishes_ros_topics_at_their_rates(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    bringup = bring_up("turtlebot3", "walls")
    paths = write_nodes(tmp_path, {"sensors.py": SENSORS})
    assert run_node_files(bringup.runtime, paths, 0.999).failures == []
    counts, stamps, scan, imu, chain = capsys.readouterr().out.splitlines()
    # Started at 0 s: 30 Hz odometry, joints and TF, 200 Hz IMU, 5 Hz scans, 10 Hz clock.
    # The run ends at the first physics step at or after 0.999 s: 1.0 s.
    assert counts == "{'/scan': 5, '/imu': 200, '/odom': 30, '/joint_states': 30} 10"
    # A scan is stamped when taken and published one physics step (5 ms) later; the first
    # /odom went out at 0 s, before the node subscribed.
    assert stamps == "[0, 200000000, 400000000] [35000000, 70000000, 100000000]"
    assert scan == "360 0.0175 base_scan 1.18"  # wall_east is 1.15 m ahead of base_link
    assert imu == "9.81 ['wheel_left_joint', 'wheel_right_joint']"
    assert chain == "-0.032 0.0 0.182"  # base_link is 1 cm above base_footprint


PLANNER = ROS_NODES / "exercise_pose_publisher.py"


def run_planner(goal_text: str, duration: float) -> tuple[RunEnd, list[tuple[int, str, Any]]]:
    bringup = bring_up("panda")
    log: list[tuple[int, str, Any]] = []
    for topic in ("desired_pose", "current_pose"):
        bringup.runtime.graph.tap(
            f"/cartesian_impedance/{topic}",
            lambda name, message: log.append((bringup.runtime.now_ns(), name, message.pose)),
        )
    end = run_node_files(
        bringup.runtime, [PLANNER], duration, args=["--ros-args", "-p", f"goal:={goal_text}"]
    )
    return end, log


def test_the_arm_tcp_follows_the_planners_lerp_and_slerp_reference() -> None:
    end, log = run_planner("[3.0, 0.45, 0.2, 0.35, 1.0, 0.0, 0.0, 0.0]", 5.0)
    assert end.failures == []
    desired = {time: pose for time, topic, pose in log if topic.endswith("desired_pose")}
    current = [(time, pose) for time, topic, pose in log if topic.endswith("current_pose")]
    errors = []
    for time, pose in current:
        if time in desired:
            target = desired[time].position
            errors.append(
                math.dist(
                    (pose.position.x, pose.position.y, pose.position.z),
                    (target.x, target.y, target.z),
                )
            )
    assert len(errors) > 250
    # The reference filter (0.05 per 1 ms step) and the impedance law lag the moving
    # set-point by under 1 cm; once it stops, the TCP settles on the goal.
    assert max(errors) < 0.01
    final = current[-1][1]
    assert (final.position.x, final.position.y, final.position.z) == pytest.approx(
        (0.45, 0.2, 0.35), abs=0.001
    )
    quaternion = np.array(
        [final.orientation.x, final.orientation.y, final.orientation.z, final.orientation.w]
    )
    assert abs(quaternion @ np.array([1.0, 0.0, 0.0, 0.0])) > 0.9999


@pytest.mark.parametrize(
    ("goal_text", "message"),
    [
        ("[3.0, 0.45, 0.2, 0.35, 1.0, 0.0, 0.0]", "'goal' must have 8 values"),
        ("[0.0, 0.45, 0.2, 0.35, 1.0, 0.0, 0.0, 0.0]", "the duration T must be > 0"),
        ("[3.0, 0.45, 0.2, 0.35, 0.0, 0.0, 0.0, 0.0]", "the goal quaternion has a norm near zero"),
    ],
)
def test_the_planners_value_errors_appear_for_each_bad_goal(goal_text: str, message: str) -> None:
    end, _ = run_planner(goal_text, 1.0)
    [failure] = end.failures
    assert isinstance(failure.error, ValueError) and message in str(failure.error)
    assert end.sim_time == 0.0
