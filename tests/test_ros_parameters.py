"""Parameters, --ros-args and params files as rclpy reads them (baobab.nav.ros.rclpy._parameters,
arguments), with the seed's pub/sub nodes."""

from __future__ import annotations

from pathlib import Path

import pytest
from ros_harness import ROS_NODES, run_node_files, write_nodes

from baobab.nav.ros.arguments import RosArgumentError, parse_ros_arguments
from baobab.nav.ros.runtime import RosRuntime

PUB_SUB = [ROS_NODES / "pub_node.py", ROS_NODES / "sub_node.py"]


def test_the_seed_pub_sub_nodes_take_their_parameters_from_ros_args(
    capsys: pytest.CaptureFixture[str],
) -> None:
    args = ["--ros-args", "-p", "timer_period:=0.25", "-p", "topic_name:=tmp"]
    end = run_node_files(RosRuntime(), PUB_SUB, 0.6, args=args)
    assert end.failures == []
    assert capsys.readouterr().err.splitlines() == [
        '[INFO] [0.250000000] [minimal_publisher]: Publishing: "Counter: 0"',
        '[INFO] [0.250000000] [minimal_subscriber]: I heard: "Counter: 0"',
        '[INFO] [0.500000000] [minimal_publisher]: Publishing: "Counter: 1"',
        '[INFO] [0.500000000] [minimal_subscriber]: I heard: "Counter: 1"',
    ]


def test_an_override_of_another_type_fails_the_declaration_as_in_rclpy() -> None:
    end = run_node_files(
        RosRuntime(), PUB_SUB[:1], 1.0, args=["--ros-args", "-p", "timer_period:=1"]
    )
    [failure] = end.failures
    assert type(failure.error).__name__ == "InvalidParameterTypeException"
    assert str(failure.error) == (
        "Trying to set parameter 'timer_period' to '1' of type 'INTEGER', expecting type "
        "'DOUBLE': timer_period"
    )


def test_params_files_remaps_and_node_renames_apply(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    params = tmp_path / "params.yaml"
    params.write_text(
        "/**:\n  ros__parameters:\n    timer_period: 0.5\n"
        "talker:\n  ros__parameters:\n    topic_name: from_file\n"
    )
    args = [
        "--ros-args",
        "--params-file",
        str(params),
        "-r",
        "__node:=talker",
        "-r",
        "from_file:=/renamed",
    ]
    listener = write_nodes(
        tmp_path,
        {
            "listener.py": (
                "import rclpy\nfrom rclpy.node import Node\nfrom std_msgs.msg import String\n"
                "rclpy.init(args=[])\nnode = Node('listener')\n"
                "node.create_subscription(String, '/renamed', lambda m: print('heard', m.data), 10)\n"
                "rclpy.spin(node)\n"
            )
        },
    )
    end = run_node_files(RosRuntime(), [*PUB_SUB[:1], *listener], 1.0, args=args)
    assert end.failures == []
    out, err = capsys.readouterr()
    assert out.splitlines() == ["heard Counter: 0", "heard Counter: 1"]
    assert '[INFO] [0.500000000] [talker]: Publishing: "Counter: 0"' in err


PARAMETERS = """\
import rclpy
from rclpy.exceptions import (InvalidParameterValueException, ParameterNotDeclaredException,
    ParameterUninitializedException)
from rclpy.node import Node
from rclpy.parameter import Parameter
from rcl_interfaces.msg import FloatingPointRange, ParameterDescriptor, SetParametersResult

rclpy.init(args=['--ros-args', '-p', 'goal:=[3.0, 0.6, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0]'])
node = Node('params')
print(node.declare_parameter('goal', [1.0]).value, node.get_parameter('use_sim_time').value)
speed = ParameterDescriptor(floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1.0)])
node.declare_parameter('speed', 0.5, speed)
try:
    node.declare_parameter('gain', 2.0, speed)
except InvalidParameterValueException as exc:
    print('refused gain')
node.declare_parameter('frame', 'odom', ParameterDescriptor(read_only=True))
node.declare_parameter('count', Parameter.Type.INTEGER)
try:
    node.get_parameter('count')
except ParameterUninitializedException:
    print('count uninitialized')
node.add_on_set_parameters_callback(
    lambda params: SetParametersResult(successful=all(p.value != 0.25 for p in params), reason='no quarter'))
results = node.set_parameters([Parameter('speed', value=2.0), Parameter('speed', value=0.25),
    Parameter('frame', value='map'), Parameter('speed', value=0.75), Parameter('count', value=3),
    Parameter('speed', value='fast')])
print([(r.successful, r.reason) for r in results])
print(node.get_parameter('speed').value, node.get_parameter('count').value,
      node.get_parameter('frame').get_parameter_value().string_value)
node.declare_parameters('limits', [('v', 0.2), ('w', 1.2)])
print(sorted((k, p.value) for k, p in node.get_parameters_by_prefix('limits').items()))
try:
    node.get_parameter('missing')
except ParameterNotDeclaredException as exc:
    print(exc)
"""


def test_descriptors_callbacks_and_types_decide_what_a_set_does(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    paths = write_nodes(tmp_path, {"parameters.py": PARAMETERS})
    assert run_node_files(RosRuntime(), paths, 0.1).failures == []
    assert capsys.readouterr().out.splitlines() == [
        "[3.0, 0.6, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0] True",
        "refused gain",
        "count uninitialized",
        str(
            [
                (False, "Parameter speed out of range. Min: 0.0, Max: 1.0"),
                (False, "no quarter"),
                (False, "Trying to set a read-only parameter: frame."),
                (True, ""),
                (True, ""),
                (
                    False,
                    "Wrong parameter type, parameter {speed} is of type {DOUBLE}, setting it to "
                    "{STRING} is not allowed.",
                ),
            ]
        ),
        "0.75 3 odom",
        "[('v', 0.2), ('w', 1.2)]",
        "Invalid access to undeclared parameter(s): missing",
    ]


def test_ros_args_rules_are_read_as_rcl_reads_them() -> None:
    parsed = parse_ros_arguments(
        [
            "prog",
            "--ros-args",
            "-p",
            "a:=1",
            "--param",
            "b:=[1, 2.5]",
            "-p",
            "c:=tmp",
            "-r",
            "talker:chatter:=news",
            "--log-level",
            "debug",
            "--",
            "rest",
        ]
    )
    assert parsed.parameters == {"a": 1, "b": [1.0, 2.5], "c": "tmp"}
    assert [(rule.node, rule.source, rule.target) for rule in parsed.remaps] == [
        ("talker", "chatter", "news")
    ]
    assert parsed.log_levels == {"": "DEBUG"} and parsed.other == ["prog", "rest"]
    for bad in (["--ros-args", "-p", "oops"], ["--ros-args", "-r", "x"], ["--ros-args", "--bogus"]):
        with pytest.raises(RosArgumentError):
            parse_ros_arguments(bad)
