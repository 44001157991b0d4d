"""``baobab ros run`` and ``baobab ros launch`` (baobab.missions.ros_command, launch_files)."""

from __future__ import annotations

from pathlib import Path

import pytest
from ros_harness import BUNDLED_NODES, ROS_NODES

from baobab.missions.cli.command_line import main

PUB, SUB = str(ROS_NODES / "pub_node.py"), str(ROS_NODES / "sub_node.py")
LAUNCH = ROS_NODES / "launch"
GOAL = "{header: {frame_id: odom}, pose: {position: {x: 2, y: 2.0}}}"


def test_ros_run_runs_node_files_with_their_ros_args(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(
        ["ros", "run", PUB, SUB, "--duration", "1.2", "--", "--ros-args", "-p", "timer_period:=0.5"]
    )
    err = capsys.readouterr().err.splitlines()
    assert code == 0
    assert err[:4] == [
        '[INFO] [0.500000000] [minimal_publisher]: Publishing: "Counter: 0"',
        '[INFO] [0.500000000] [minimal_subscriber]: I heard: "Counter: 0"',
        '[INFO] [1.000000000] [minimal_publisher]: Publishing: "Counter: 1"',
        '[INFO] [1.000000000] [minimal_subscriber]: I heard: "Counter: 1"',
    ]
    assert err[4].startswith("baobab ros run: 1.200 s of sim time, trace digest ")


def test_a_goal_sent_with_pub_drives_the_point_to_point_node_and_echo_prints_topics(
    capsys: pytest.CaptureFixture[str],
) -> None:
    node = str(BUNDLED_NODES / "point2point_nav.py")
    args = ["ros", "run", node, "--world", "walls", "--robot", "turtlebot3", "--duration", "18"]
    args += ["--pub", "/goal", "geometry_msgs/msg/PoseStamped", GOAL, "--at", "1", "--echo", "goal"]
    assert main(args) == 0
    out, err = capsys.readouterr()
    assert out.startswith(
        "header:\n  stamp:\n    sec: 0\n    nanosec: 0\n  frame_id: odom\npose:\n"
    )
    assert out.endswith("---\n") and out.count("---\n") == 1
    assert "[INFO] [1.000000000] [point2point_nav]: New goal: (2.00, 2.00)" in err
    assert "[point2point_nav]: Goal reached" in err


def test_keys_pressed_at_sim_times_reach_a_pynput_listener(
    capsys: pytest.CaptureFixture[str],
) -> None:
    node = str(ROS_NODES / "keyboard_teleop.py")
    args = ["ros", "run", node, "--duration", "2", "--press", "w", "--at", "0.5"]
    args += ["--release", "w", "--at", "1.0", "--echo", "/cmd_vel"]
    assert main(args) == 0
    speeds = [line for line in capsys.readouterr().out.splitlines() if line.startswith("  x:")]
    assert speeds == ["  x: 0.25", "  x: 0.0", "  x: 0.0", "  x: 0.0"]


def test_a_node_that_raises_shows_its_traceback_names_the_node_and_exits_1(
    capsys: pytest.CaptureFixture[str],
) -> None:
    planner = str(ROS_NODES / "exercise_pose_publisher.py")
    args = ["ros", "run", planner, "--robot", "panda", "--duration", "1"]
    assert main([*args, "--", "--ros-args", "-p", "goal:=[1.0, 0.4, 0.2, 0.3]"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("Traceback (most recent call last):\n")
    assert f'File "{planner}", line 15, in __init__' in err
    assert err.endswith(
        f"{planner}: node code failed ('exercise_pose_publisher'): ValueError: 'goal' must have "
        "8 values [T, x, y, z, qx, qy, qz, qw], got 4\n"
    )


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--world", "nowhere"], "nowhere:1:1: unknown world 'nowhere'"),
        (
            ["--pub", "/goal", "geometry_msgs/msg/PoseStamped", "{pose: {positon: {x: 1}}}"],
            "baobab ros: --pub #1 (geometry_msgs/msg/PoseStamped): pose.positon: Pose has no "
            "such field (fields: position, orientation)",
        ),
        (
            ["--pub", "/goal", "geometry_msgs/msg/Pose3D", "{}"],
            "baobab ros: --pub #1: unknown message type 'geometry_msgs/msg/Pose3D'",
        ),
        (
            ["--pub", "/goal", "std_msgs/msg/Int32", "{data: 1.5}"],
            "baobab ros: --pub #1 (std_msgs/msg/Int32): data: The 'data' field must be of type "
            "'int'",
        ),
        (["--press", "ctrl-alt"], "baobab ros: --press ctrl-alt: unknown key 'ctrl-alt'"),
        (["--robot", "drone"], "baobab ros: unknown robot 'drone'"),
        (["--", "--ros-args", "-p", "oops"], "baobab ros: --ros-args: cannot read parameter"),
    ],
)
def test_mistakes_in_the_command_exit_2_with_one_line(
    extra: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["ros", "run", PUB, "--duration", "1", *extra]) == 2
    err = capsys.readouterr().err
    assert err.startswith(message) and err.count("\n") == 1


def test_a_node_file_that_does_not_compile_is_located(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    broken = tmp_path / "broken.py"
    broken.write_text("import rclpy\ndef main(:\n")
    assert main(["ros", "run", str(broken)]) == 2
    assert capsys.readouterr().err.startswith(f"{broken}:2:")


def test_ros_launch_passes_launch_arguments_to_node_parameters(
    capsys: pytest.CaptureFixture[str],
) -> None:
    launch = str(LAUNCH / "pub_sub.launch.py")
    code = main(
        ["ros", "launch", launch, "timer_period:=0.5", "topic_name:=tmp", "--duration", "1"]
    )
    assert code == 0
    err = capsys.readouterr().err.splitlines()
    assert err[:2] == [
        '[INFO] [0.500000000] [minimal_publisher]: Publishing: "Counter: 0"',
        '[INFO] [0.500000000] [minimal_subscriber]: I heard: "Counter: 0"',
    ]


def test_the_planners_launch_file_takes_the_seeds_goal_argument(
    capsys: pytest.CaptureFixture[str],
) -> None:
    launch = str(LAUNCH / "exercise_pose_publisher.launch.py")
    goal = "goal:=[[3.0, 0.45, 0.2, 0.35, 1.0, 0.0, 0.0, 0.0]]"  # as the seed writes it
    args = ["ros", "launch", launch, goal, "--robot", "panda", "--duration", "4"]
    assert main([*args, "--echo", "/cartesian_impedance/current_pose"]) == 0
    last = capsys.readouterr().out.split("---\n")[-2]
    assert "  position:\n    x: 0.4499" in last and "    z: 0.3500" in last
    bad = "goal:=[0.0, 0.45, 0.2, 0.35, 1.0, 0.0, 0.0, 0.0]"
    assert main(["ros", "launch", launch, bad, "--robot", "panda", "--duration", "1"]) == 1
    assert "ValueError: the duration T must be > 0, got 0.0\n" in capsys.readouterr().err
    assert main(["ros", "launch", launch, "--show-args"]) == 0
    assert "    'goal':\n        Goal as [T, x, y, z, qx, qy, qz, qw]\n" in capsys.readouterr().out


UNSUPPORTED = """\
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, TimerAction


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('rate', default_value='1'),
        TimerAction(period=1.0, actions=[]),
    ])
"""

MISSING = """\
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('rate'),
        Node(package='demo', executable='ghost'),
    ])
"""


def test_what_a_launch_file_asks_that_baobab_cannot_do_is_a_located_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    unsupported, missing = tmp_path / "timer.launch.py", tmp_path / "missing.launch.py"
    unsupported.write_text(UNSUPPORTED)
    missing.write_text(MISSING)
    assert main(["ros", "launch", str(unsupported)]) == 2
    assert capsys.readouterr().err.startswith(
        f"{unsupported}:8:1: launch.actions.TimerAction is not supported by baobab ros launch"
    )
    assert main(["ros", "launch", str(missing)]) == 2
    assert capsys.readouterr().err == (
        f"{missing}:8:1: launch argument 'rate' is required (no description given); give it as "
        "rate:=VALUE\n"
    )
    assert main(["ros", "launch", str(missing), "rate:=2"]) == 2
    assert capsys.readouterr().err.startswith(
        f"{missing}:9:1: node executable 'ghost' not found: looked for {tmp_path}/ghost.py"
    )


def test_record_writes_the_runs_messages_to_mcap(tmp_path: Path) -> None:
    from mcap.reader import make_reader

    target = tmp_path / "run.mcap"
    args = ["ros", "run", PUB, SUB, "--duration", "2", "--record", str(target)]
    assert main(args) == 0
    with target.open("rb") as stream:
        reader = make_reader(stream)
        topics = {channel.topic for channel in reader.get_summary().channels.values()}
        messages = [
            (channel.topic, message.log_time) for _, channel, message in reader.iter_messages()
        ]
    assert topics == {"/chatter", "/tf_static"}  # the robot's fixed frames, latched at 0 s
    chatter = [(topic, time) for topic, time in messages if topic == "/chatter"]
    assert chatter == [("/chatter", 1_000_000_000), ("/chatter", 2_000_000_000)]


OUTER = """\
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, IncludeLaunchDescription, LogInfo
from launch.launch_description_sources import PythonLaunchDescriptionSource
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('period', default_value='0.5'),
        LogInfo(msg=['period is ', LaunchConfiguration('period')]),
        IncludeLaunchDescription(
            PythonLaunchDescriptionSource('{pub_sub}'),
            launch_arguments={{'timer_period': LaunchConfiguration('period')}}.items(),
        ),
        Node(executable='pub_node', name='second_publisher', parameters=['{params}'],
             remappings=[('tmp', 'renamed')]),
    ])
"""


def test_a_launch_file_includes_another_and_passes_params_files_and_remappings(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "pub_node.py").write_text((ROS_NODES / "pub_node.py").read_text())
    params = tmp_path / "params.yaml"
    params.write_text(
        "second_publisher:\n  ros__parameters:\n    timer_period: 0.75\n    topic_name: tmp\n"
    )
    outer = tmp_path / "outer.launch.py"
    outer.write_text(OUTER.format(pub_sub=LAUNCH / "pub_sub.launch.py", params=params))
    assert (
        main(
            ["ros", "launch", str(outer), "period:=0.25", "--duration", "0.8", "--echo", "renamed"]
        )
        == 0
    )
    out, err = capsys.readouterr()
    assert out.splitlines()[0] == "[INFO] [launch.user]: period is 0.25"
    assert out.count("data: 'Counter: 0'") == 1  # the second publisher's, on /renamed at 0.75 s
    assert '[INFO] [0.250000000] [minimal_subscriber]: I heard: "Counter: 0"' in err
    assert '[INFO] [0.750000000] [second_publisher]: Publishing: "Counter: 0"' in err


def test_recorded_transforms_are_foxglove_frame_transforms(tmp_path: Path) -> None:
    from mcap.reader import make_reader

    target = tmp_path / "tf.mcap"
    node = str(BUNDLED_NODES / "point2point_nav.py")
    assert main(["ros", "run", node, "--duration", "0.5", "--record", str(target)]) == 0
    with target.open("rb") as stream:
        summary = make_reader(stream).get_summary()
    schemas = {schema.id: schema.name for schema in summary.schemas.values()}
    channels = {channel.topic: schemas[channel.schema_id] for channel in summary.channels.values()}
    assert channels["/tf"] == channels["/tf_static"] == "foxglove.FrameTransforms"
    assert summary.statistics.channel_message_counts  # the node's TF listener made /tf flow
