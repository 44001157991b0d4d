"""Messages behave as rclpy's generated classes (baobab.nav.rosmsg and the *_msgs shims)."""

from __future__ import annotations

import copy
from array import array

import numpy as np
import pytest

from baobab.nav.ros.geometry_msgs.msg import Point, PoseStamped, TransformStamped, Twist
from baobab.nav.ros.nav_msgs.msg import OccupancyGrid, Odometry, Path
from baobab.nav.ros.rcl_interfaces.msg import ParameterDescriptor
from baobab.nav.ros.sensor_msgs.msg import Imu, JointState, LaserScan
from baobab.nav.ros.std_msgs.msg import Bool, Int32, String, UInt8
from baobab.nav.ros.tf2_msgs.msg import TFMessage
from baobab.nav.rosmsg import message_class, to_plain


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: setattr(Twist().linear, "x", 1), "The 'x' field must be of type 'float'"),
        (lambda: String(data=3), "The 'data' field must be of type 'str'"),
        (lambda: Bool(data=1), "The 'data' field must be of type 'bool'"),
        (lambda: Int32(data=1.0), "The 'data' field must be of type 'int'"),
        (lambda: UInt8(data=256), "The 'data' field must be an integer in [0, 255]"),
        (
            lambda: Int32(data=2**31),
            "The 'data' field must be an integer in [-2147483648, 2147483647]",
        ),
        (
            lambda: PoseStamped(pose=Point()),
            "The 'pose' field must be a sub message of type 'Pose'",
        ),
        (
            lambda: Path(poses=[Point()]),
            "The 'poses' field must be a set or sequence and each value of type 'PoseStamped'",
        ),
        (
            lambda: LaserScan(ranges=[1.0, 2]),
            "The 'ranges' field must be a set or sequence and each value of type 'float'",
        ),
        (
            lambda: Odometry().pose.__setattr__("covariance", [0.0] * 35),
            "The 'covariance' field must be a set or sequence with length 36",
        ),
        (lambda: Twist(linar=None), "Invalid arguments passed to constructor: linar"),
    ],
)
def test_a_wrong_field_type_raises_as_rclpy_generated_classes_do(build, message: str) -> None:
    with pytest.raises(AssertionError) as raised:
        build()
    assert str(raised.value) == message


def test_fields_have_ros_types_defaults_and_storage() -> None:
    scan = LaserScan(ranges=[1.0, float("inf")])
    assert isinstance(scan.ranges, array) and scan.ranges.typecode == "f"
    scan.ranges = np.array([0.5, 1.5], dtype=np.float32)
    assert scan.ranges.tolist() == [0.5, 1.5]
    imu = Imu()
    assert imu.orientation.w == 1.0 and imu.orientation_covariance.shape == (9,)
    state = JointState(name=["a"], position=[0.1])
    assert state.position.typecode == "d" and state.name == ["a"]
    grid = OccupancyGrid(data=[-1, 100])
    assert grid.data.typecode == "b"
    assert Odometry().child_frame_id == "" and Odometry().pose.covariance.dtype == np.float64
    assert ParameterDescriptor().floating_point_range == []
    assert Twist.get_fields_and_field_types() == {
        "linear": "geometry_msgs/Vector3",
        "angular": "geometry_msgs/Vector3",
    }


def test_messages_compare_copy_print_and_flatten_by_value() -> None:
    transform = TransformStamped(child_frame_id="base_link")
    transform.transform.translation.x = 1.5
    message = TFMessage(transforms=[transform])
    clone = copy.deepcopy(message)
    assert clone == message and clone.transforms[0] is not transform
    clone.transforms[0].transform.translation.x = 2.0
    assert clone != message
    assert repr(Point(x=1.0)) == "geometry_msgs.msg.Point(x=1.0, y=0.0, z=0.0)"
    assert to_plain(Point(x=1.0)) == {"x": 1.0, "y": 0.0, "z": 0.0}
    assert message_class("sensor_msgs/msg/LaserScan") is LaserScan
    assert message_class("geometry_msgs/Twist") is Twist
    with pytest.raises(AttributeError):
        Point().w = 1.0  # type: ignore[attr-defined]
