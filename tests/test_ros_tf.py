"""tf2_ros on sim time: lookups, interpolation, TF's errors, timeouts, broadcasters
(baobab.nav.ros.tf_tree, tf2_ros)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from ros_harness import run_node_files, write_nodes

from baobab.nav.ros.runtime import RosRuntime
from baobab.nav.ros.tf_tree import (
    ConnectivityException,
    Edge,
    ExtrapolationException,
    LookupException,
    TransformTree,
)

S = 1_000_000_000


def yaw(angle: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(angle / 2), math.cos(angle / 2))


def test_lookups_compose_interpolate_and_raise_tf_errors() -> None:
    tree = TransformTree()
    tree.set("odom", Edge(0, "map", (1.0, 0.0, 0.0), yaw(math.pi / 2)), static=True)
    tree.set("base_link", Edge(1 * S, "odom", (0.0, 0.0, 0.0), yaw(0.0)), static=False)
    tree.set("base_link", Edge(3 * S, "odom", (2.0, 0.0, 0.0), yaw(math.pi / 2)), static=False)
    tree.set("base_scan", Edge(0, "base_link", (-0.032, 0.0, 0.172), yaw(0.0)), static=True)
    (x, y, z), rotation, _ = tree.lookup("map", "base_scan", 2 * S)
    # odom is the map turned by 90 deg at (1, 0); base_link is 1 m along odom's x at 2 s,
    # turned 45 deg; base_scan 3.2 cm behind it.
    behind = -0.032 * math.cos(math.radians(135)), -0.032 * math.sin(math.radians(135))
    assert (x, y, z) == pytest.approx((1.0 + behind[0], 1.0 + behind[1], 0.172))
    assert rotation == pytest.approx(yaw(math.radians(135)))
    assert tree.lookup("map", "base_link", 0)[2] == 3 * S  # time 0: the latest common time
    (x, y, _), _, _ = tree.lookup("base_link", "map", 3 * S)
    assert (x, y) == pytest.approx((1.0, 2.0))  # base_link sits at (1, 2) facing -x
    with pytest.raises(
        ExtrapolationException, match=r"into the future\.  Requested time 4\.000000"
    ):
        tree.lookup("odom", "base_link", 4 * S)
    with pytest.raises(ExtrapolationException, match="into the past"):
        tree.lookup("odom", "base_link", S // 2)
    with pytest.raises(
        LookupException, match='"world" passed to lookupTransform argument target_frame'
    ):
        tree.lookup("world", "base_link", 0)
    tree.set("camera", Edge(0, "table", (0.0, 0.0, 1.0), yaw(0.0)), static=True)
    with pytest.raises(ConnectivityException, match="not part of the same tree"):
        tree.lookup("map", "camera", 0)


BROADCASTER = """\
import rclpy
from geometry_msgs.msg import TransformStamped
from rclpy.node import Node
from tf2_ros import StaticTransformBroadcaster, TransformBroadcaster

def stamped(node, parent, child, x):
    t = TransformStamped()
    t.header.stamp = node.get_clock().now().to_msg()
    t.header.frame_id, t.child_frame_id = parent, child
    t.transform.translation.x = x
    return t

def main():
    rclpy.init()
    node = Node('tf_broadcaster')
    StaticTransformBroadcaster(node).sendTransform(stamped(node, 'map', 'odom', 1.0))
    broadcaster = TransformBroadcaster(node)
    node.create_timer(0.5, lambda: broadcaster.sendTransform(stamped(node, 'odom', 'base_link', 0.25)))
    rclpy.spin(node)
"""

LATE_LISTENER = """\
import time
import rclpy
import rclpy.time
from rclpy.duration import Duration
from rclpy.node import Node
from tf2_ros import Buffer, LookupException, TransformListener

def main():
    rclpy.init()
    node = Node('tf_user')
    time.sleep(0.2)
    buffer = Buffer()
    TransformListener(buffer, node)  # after the static transform was sent: it is latched
    clock = node.get_clock()
    try:
        buffer.lookup_transform('map', 'base_link', rclpy.time.Time())
    except LookupException as exc:
        print('not yet:', exc)
    print('map -> odom:', buffer.lookup_transform('map', 'odom', rclpy.time.Time()).transform.translation.x)
    found = buffer.can_transform('map', 'base_link', rclpy.time.Time(), timeout=Duration(seconds=0.1))
    print('after 0.1 s:', found, clock.now().nanoseconds)
    tf = buffer.lookup_transform('map', 'base_link', rclpy.time.Time(), timeout=Duration(seconds=1.0))
    print('found', tf.transform.translation.x, tf.header.stamp.sec, tf.header.stamp.nanosec, clock.now().nanoseconds)
"""


def test_a_lookup_waits_on_sim_time_and_a_late_listener_gets_static_transforms(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    paths = write_nodes(
        tmp_path, {"broadcaster.py": BROADCASTER, "late_listener.py": LATE_LISTENER}
    )
    end = run_node_files(RosRuntime(), paths, 3.0)
    assert end.failures == []
    assert capsys.readouterr().out.splitlines() == [
        'not yet: "base_link" passed to lookupTransform argument source_frame does not exist. ',
        "map -> odom: 1.0",
        "after 0.1 s: False 300000000",
        "found 1.25 0 500000000 500000000",  # the broadcaster's timer sent it at 0.5 s
    ]
