"""The ROS import shims and the Nav2 script runner (baobab.nav.ros, baobab.nav.script_runner)."""

from __future__ import annotations

import copy
import importlib
import pkgutil
import sys
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from types import ModuleType

import pytest

import baobab.nav.ros
from baobab.nav.defaults import DEFAULT_WORLD, NavigatorDefaults, navigator_defaults
from baobab.nav.msgs import PoseStamped
from baobab.nav.ros import ROS_MODULES, RUNTIME_MODULES, UnsupportedRosFeatureError, ros_shims
from baobab.nav.ros._navigator_exports import NAVIGATOR_MODULE, NAVIGATOR_NAMES
from baobab.nav.rostime import Clock, ClockType, Duration, DurationMsg, Time, set_sim_time_source
from baobab.nav.script_runner import run_nav2_script
from baobab.sim.world import Pose2D


def write(folder: Path, name: str, source: str) -> Path:
    path = folder / name
    path.write_text(source)
    return path


ROS_SCRIPT = """\
import sys

import rclpy
import rclpy.duration
from builtin_interfaces.msg import Time
from geometry_msgs.msg import Pose, PoseStamped, Quaternion, Twist
from nav_msgs.msg import Path
from rclpy.duration import Duration
from rclpy.node import Node
from std_msgs.msg import Header, String

rclpy.init()
node = Node('script_node')
goal = PoseStamped()
goal.header.frame_id = 'map'
goal.header.stamp = node.get_clock().now().to_msg()
goal.pose.position.x = 1.5
goal.pose.orientation = Quaternion(z=1.0, w=0.0)
path = Path(header=Header(frame_id='map'), poses=[goal])
status = String(data='ok')
assert isinstance(goal.header.stamp, Time)
assert rclpy.duration.Duration is Duration
print('built', len(path.poses), goal.pose.position.x, status.data, Twist().linear.x,
      rclpy.ok(), Duration(seconds=2.0) > Duration(seconds=1.0), __name__, sys.argv[1:])
rclpy.shutdown()
print('ok after shutdown:', rclpy.ok())
exit(3)
"""


def test_script_with_ros_imports_runs_and_its_exit_code_passes_through(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = write(tmp_path, "uses_ros.py", ROS_SCRIPT)
    assert run_nav2_script(script, navigator_defaults={}, argv=["--fast"]) == 3
    out = capsys.readouterr().out
    assert out.splitlines() == [
        "built 1 1.5 ok 0.0 True True __main__ ['--fast']",
        "ok after shutdown: False",
    ]
    assert not any(name.partition(".")[0] == "rclpy" for name in sys.modules)
    assert "geometry_msgs.msg" not in sys.modules and "robot_navigator" not in sys.modules


def test_init_and_shutdown_pair_up_across_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    twice = write(
        tmp_path,
        "twice.py",
        "import rclpy\nrclpy.init()\nrclpy.shutdown()\nrclpy.init(args=None)\nrclpy.shutdown()\n",
    )
    forgetful = write(tmp_path, "forgetful.py", "import rclpy\nrclpy.init()\nprint(rclpy.ok())\n")
    for script in (twice, forgetful, twice, forgetful):
        assert run_nav2_script(script, navigator_defaults={}) == 0
    assert capsys.readouterr().out == "True\nTrue\n"


def test_rclpy_lifecycle_mistakes_raise_as_rclpy_does() -> None:
    with ros_shims():
        rclpy = importlib.import_module("rclpy")
        assert not rclpy.ok()
        with pytest.raises(RuntimeError, match="must be initialized"):
            rclpy.shutdown()
        rclpy.init()
        with pytest.raises(RuntimeError, match="only be called once"):
            rclpy.init()
        rclpy.shutdown()
        rclpy.try_shutdown()
        with rclpy.init() as context:
            assert context.ok() and rclpy.ok()
        assert not rclpy.ok()


def test_shutdown_destroys_the_nodes_a_script_leaves_behind(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = write(
        tmp_path,
        "leaves_node.py",
        "import rclpy\n"
        "from rclpy.node import Node\n"
        "class Robot(Node):\n"
        "    def destroy_node(self):\n"
        "        print('destroyed', self.get_name())\n"
        "        super().destroy_node()\n"
        "rclpy.init()\n"
        "robot = Robot('robot')\n"
        "gone = Robot('gone')\n"
        "gone.destroy_node()\n",
    )
    assert run_nav2_script(script, navigator_defaults={}) == 0
    assert capsys.readouterr().out == "destroyed gone\ndestroyed robot\n"


@pytest.mark.parametrize(
    ("source", "status", "stderr"),
    [
        ("x = 1\n", 0, ""),
        ("import sys\nsys.exit()\n", 0, ""),
        ("exit(None)\n", 0, ""),
        ("raise SystemExit(7)\n", 7, ""),
        ("import sys\nsys.exit('giving up')\n", 1, "giving up\n"),
        ("def main():\n    exit(0)\nif __name__ == '__main__':\n    main()\n", 0, ""),
    ],
)
def test_exit_status_follows_python(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], source: str, status: int, stderr: str
) -> None:
    script = write(tmp_path, "ends.py", source)
    assert run_nav2_script(script, navigator_defaults={}) == status
    assert capsys.readouterr().err == stderr


def test_syntax_error_is_one_located_line_and_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = write(tmp_path, "broken.py", "print('before')\nif True\n    pass\n")
    assert run_nav2_script(script, navigator_defaults={}) == 2
    captured = capsys.readouterr()
    assert captured.out == ""  # nothing of the script ran
    assert captured.err == f"{script}:2:8: SyntaxError: expected ':'\n"


def test_missing_script_is_one_located_line_and_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert run_nav2_script(tmp_path / "absent.py", navigator_defaults={}) == 2
    assert capsys.readouterr().err == f"{tmp_path / 'absent.py'}:1:1: no such file\n"


def test_exception_in_the_script_prints_its_own_traceback_and_exit_1(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = write(
        tmp_path,
        "raises.py",
        "print('started')\ndef fail():\n    raise ValueError('no such goal')\nfail()\n",
    )
    assert run_nav2_script(script, navigator_defaults={}) == 1
    captured = capsys.readouterr()
    assert captured.out == "started\n"
    lines = captured.err.splitlines()
    assert lines[0] == "Traceback (most recent call last):"
    assert lines[1] == f'  File "{script}", line 4, in <module>'
    assert f'  File "{script}", line 3, in fail' in lines
    assert lines[-1] == "ValueError: no such goal"
    assert "runpy" not in captured.err and "script_runner" not in captured.err


def test_located_input_error_while_running_is_one_line_and_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = write(
        tmp_path,
        "unknown_world.py",
        "from baobab.sim.world import load_world\nprint('loading')\nload_world('atlantis')\n",
    )
    assert run_nav2_script(script, navigator_defaults={}) == 2
    captured = capsys.readouterr()
    assert captured.out == "loading\n"
    assert captured.err.startswith("atlantis:1:1: unknown world 'atlantis'")
    assert len(captured.err.splitlines()) == 1


def test_keyboard_interrupt_is_exit_130(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    script = write(tmp_path, "interrupted.py", "raise KeyboardInterrupt\n")
    assert run_nav2_script(script, navigator_defaults={}) == 130
    assert capsys.readouterr().err == f"{script}: interrupted\n"


def test_navigator_defaults_reach_the_script_and_end_with_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = write(
        tmp_path,
        "defaults.py",
        "from baobab.nav.defaults import navigator_defaults\n"
        "d = navigator_defaults()\n"
        "print(d.world, d.start.x, d.start.yaw, d.seed, d.realtime)\n",
    )
    start = Pose2D(x=-2.0, y=1.0, yaw=0.5)
    defaults = {"world": "town", "start": start, "seed": 11, "realtime": True}
    assert run_nav2_script(script, navigator_defaults=defaults) == 0
    assert capsys.readouterr().out == "town -2.0 0.5 11 True\n"
    assert navigator_defaults() == NavigatorDefaults()
    assert navigator_defaults().world == DEFAULT_WORLD


def test_bad_navigator_defaults_are_a_programming_error(tmp_path: Path) -> None:
    script = write(tmp_path, "noop.py", "pass\n")
    with pytest.raises(TypeError):
        run_nav2_script(script, navigator_defaults={"wrold": "cafe"})
    with pytest.raises(TypeError, match="seed"):
        run_nav2_script(script, navigator_defaults={"seed": -1})
    assert "rclpy" not in sys.modules


def test_modules_already_loaded_under_ros_names_are_hidden_then_restored(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    real_rclpy, real_action = ModuleType("rclpy"), ModuleType("rclpy.action")
    monkeypatch.setitem(sys.modules, "rclpy", real_rclpy)
    monkeypatch.setitem(sys.modules, "rclpy.action", real_action)
    script = write(
        tmp_path,
        "which.py",
        "import rclpy\n"
        "print(rclpy.__name__)\n"
        "try:\n"
        "    import rclpy.action\n"
        "except ModuleNotFoundError as exc:\n"
        "    print(exc)\n",
    )
    assert run_nav2_script(script, navigator_defaults={}) == 0
    assert capsys.readouterr().out == "baobab.nav.ros.rclpy\nNo module named 'rclpy.action'\n"
    assert sys.modules["rclpy"] is real_rclpy and sys.modules["rclpy.action"] is real_action


def test_modules_next_to_the_script_are_loaded_afresh_for_each_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    scripts = []
    for label in ("first", "second"):
        folder = tmp_path / label
        folder.mkdir()
        write(folder, "helper_for_shim_test.py", f"LABEL = {label!r}\n")
        scripts.append(
            write(folder, "main.py", "from helper_for_shim_test import LABEL\nprint(LABEL)\n")
        )
    for script in scripts:
        assert run_nav2_script(script, navigator_defaults={}) == 0
    assert capsys.readouterr().out == "first\nsecond\n"
    assert "helper_for_shim_test" not in sys.modules
    assert str(tmp_path / "second") not in sys.path


def test_every_shim_module_is_served_under_its_ros_name() -> None:
    found = {
        info.name.removeprefix("baobab.nav.ros.")
        for info in pkgutil.walk_packages(baobab.nav.ros.__path__, "baobab.nav.ros.")
        if not any(part.startswith("_") for part in info.name.split("."))
    }
    assert found == set(ROS_MODULES) | set(RUNTIME_MODULES)
    with ros_shims():
        for name in ROS_MODULES:
            assert sys.modules[name] is importlib.import_module(f"baobab.nav.ros.{name}")
            assert importlib.import_module(name).__name__ == f"baobab.nav.ros.{name}"


def test_robot_navigator_modules_import_before_the_navigator_is_touched() -> None:
    with ros_shims():
        old = importlib.import_module("robot_navigator")
        new = importlib.import_module("nav2_simple_commander.robot_navigator")
        for module in (old, new):
            assert set(NAVIGATOR_NAMES) <= set(dir(module)) and module.__all__ == list(
                NAVIGATOR_NAMES
            )
            with pytest.raises(AttributeError, match="has no attribute 'Navigator'"):
                _ = module.Navigator


def test_node_clock_and_logger_follow_the_registered_sim_time(
    capsys: pytest.CaptureFixture[str],
) -> None:
    with ros_shims():
        node_module = importlib.import_module("rclpy.node")
        node = node_module.Node("watcher", namespace="robot1")
        assert node.get_clock().now() == Time(clock_type=ClockType.ROS_TIME)
        set_sim_time_source(lambda: 12.3)
        try:
            assert node.get_clock().now() == Time(seconds=12.3, clock_type=ClockType.ROS_TIME)
            node.get_logger().info("waiting")
            node.get_logger().debug("not shown at the default level")
        finally:
            set_sim_time_source(None)
        assert node.get_fully_qualified_name() == "/robot1/watcher"
    assert capsys.readouterr().err == "[INFO] [12.300000000] [watcher]: waiting\n"


def test_ros_features_baobab_does_not_model_raise_clear_errors() -> None:
    with ros_shims():
        rclpy = importlib.import_module("rclpy")
        node = rclpy.create_node("lonely")
        with pytest.raises(UnsupportedRosFeatureError, match="create_client"):
            node.create_client(object, "/get_map")
        with pytest.raises(UnsupportedRosFeatureError, match="baobab ros run"):
            rclpy.spin(node)
        rclpy.spin_once(node, timeout_sec=0.1)


def test_a_nav2_scripts_nodes_talk_among_themselves_outside_a_run() -> None:
    with ros_shims():
        rclpy = importlib.import_module("rclpy")
        twist_type = importlib.import_module("geometry_msgs.msg").Twist
        rclpy.init()
        teleop, listener = rclpy.create_node("teleop"), rclpy.create_node("listener")
        heard: list[float] = []
        listener.create_subscription(
            twist_type, "cmd_vel_teleop", lambda m: heard.append(m.linear.x), 10
        )
        publisher = teleop.create_publisher(twist_type, "/cmd_vel_teleop", 10)
        command = twist_type()
        command.linear.x = 0.2
        publisher.publish(command)
        command.linear.x = 0.5  # the subscriber got its own copy
        assert heard == []
        rclpy.spin_once(listener, timeout_sec=0.0)
        assert heard == [0.2]
        rclpy.shutdown()


# --- an unmodified seed script against a scripted navigator ----------------------------------

NAV_TO_POSE_SEED = """\
#! /usr/bin/env python3
# Copyright 2021 Samsung Research America
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.
#
# Modified by AutomaticAddison.com

import time  # Time library

from geometry_msgs.msg import PoseStamped # Pose with ref frame and timestamp
from rclpy.duration import Duration # Handles time for ROS 2
import rclpy # Python client library for ROS 2

from robot_navigator import BasicNavigator, NavigationResult # Helper module

'''
Navigates a robot from an initial pose to a goal pose.
'''
def main():

  # Start the ROS 2 Python Client Library
  rclpy.init()

  # Launch the ROS 2 Navigation Stack
  navigator = BasicNavigator()

  # Set the robot's initial pose if necessary
  # initial_pose = PoseStamped()
  # initial_pose.header.frame_id = 'map'
  # initial_pose.header.stamp = navigator.get_clock().now().to_msg()
  # initial_pose.pose.position.x = 0.0
  # initial_pose.pose.position.y = 0.0
  # initial_pose.pose.position.z = 0.0
  # initial_pose.pose.orientation.x = 0.0
  # initial_pose.pose.orientation.y = 0.0
  # initial_pose.pose.orientation.z = 0.0
  # initial_pose.pose.orientation.w = 1.0
  # navigator.setInitialPose(initial_pose)

  # Activate navigation, if not autostarted. This should be called after setInitialPose()
  # or this will initialize at the origin of the map and update the costmap with bogus readings.
  # If autostart, you should `waitUntilNav2Active()` instead.
  # navigator.lifecycleStartup()

  # Wait for navigation to fully activate. Use this line if autostart is set to true.
  navigator.waitUntilNav2Active()

  # If desired, you can change or load the map as well
  # navigator.changeMap('/path/to/map.yaml')

  # You may use the navigator to clear or obtain costmaps
  # navigator.clearAllCostmaps()  # also have clearLocalCostmap() and clearGlobalCostmap()
  # global_costmap = navigator.getGlobalCostmap()
  # local_costmap = navigator.getLocalCostmap()

  # Set the robot's goal pose
  goal_pose = PoseStamped()
  goal_pose.header.frame_id = 'map'
  goal_pose.header.stamp = navigator.get_clock().now().to_msg()
  goal_pose.pose.position.x = 10.0
  goal_pose.pose.position.y = -2.0
  goal_pose.pose.position.z = 0.0
  goal_pose.pose.orientation.x = 0.0
  goal_pose.pose.orientation.y = 0.0
  goal_pose.pose.orientation.z = 0.0
  goal_pose.pose.orientation.w = 1.0

  # sanity check a valid path exists
  # path = navigator.getPath(initial_pose, goal_pose)

  # Go to the goal pose
  navigator.goToPose(goal_pose)

  i = 0

  # Keep doing stuff as long as the robot is moving towards the goal
  while not navigator.isNavComplete():
    ################################################
    #
    # Implement some code here for your application!
    #
    ################################################

    # Do something with the feedback
    i = i + 1
    feedback = navigator.getFeedback()
    if feedback and i % 5 == 0:
      print('Distance remaining: ' + '{:.2f}'.format(
            feedback.distance_remaining) + ' meters.')

      # Some navigation timeout to demo cancellation
      if Duration.from_msg(feedback.navigation_time) > Duration(seconds=600.0):
        navigator.cancelNav()

      # Some navigation request change to demo preemption
      if Duration.from_msg(feedback.navigation_time) > Duration(seconds=120.0):
        goal_pose.pose.position.x = -3.0
        navigator.goToPose(goal_pose)

  # Do something depending on the return code
  result = navigator.getResult()
  if result == NavigationResult.SUCCEEDED:
      print('Goal succeeded!')
  elif result == NavigationResult.CANCELED:
      print('Goal was canceled!')
  elif result == NavigationResult.FAILED:
      print('Goal failed!')
  else:
      print('Goal has an invalid return status!')

  # Shut down the ROS 2 Navigation Stack
  navigator.lifecycleShutdown()

  exit(0)

if __name__ == '__main__':
  main()

"""


class _TaskResult(Enum):
    UNKNOWN = 0
    SUCCEEDED = 1
    CANCELED = 2
    FAILED = 3


@dataclass
class _NavigateToPoseFeedback:
    navigation_time: DurationMsg
    distance_remaining: float


class _ScriptedNavigator:
    """Stands in for BasicNavigator: each completion poll advances sim time by 0.1 s.

    A goal at x = -3 (the seed's preemption target) succeeds 20 s after it is sent; others
    never finish on their own.
    """

    goals: list[PoseStamped]
    seen_defaults: list[NavigatorDefaults]

    def __init__(self) -> None:
        self.steps = 0
        self.sent_at = 0
        self.goal: PoseStamped | None = None
        type(self).seen_defaults.append(navigator_defaults())

    def _seconds(self) -> float:
        return self.steps / 10

    def get_clock(self) -> Clock:
        return Clock(clock_type=ClockType.ROS_TIME, source=self._seconds)

    def waitUntilNav2Active(self) -> None:
        pass

    def goToPose(self, pose: PoseStamped) -> bool:
        self.goal = copy.deepcopy(pose)
        type(self).goals.append(self.goal)
        self.sent_at = self.steps
        return True

    def _elapsed(self) -> Duration:
        return Duration(nanoseconds=(self.steps - self.sent_at) * 100_000_000)

    def isNavComplete(self) -> bool:
        self.steps += 1
        assert self.goal is not None
        return self.goal.pose.position.x == -3.0 and self._elapsed() >= Duration(seconds=20)

    def getFeedback(self) -> _NavigateToPoseFeedback:
        return _NavigateToPoseFeedback(self._elapsed().to_msg(), 0.25 * self.steps)

    def cancelNav(self) -> None:
        raise AssertionError("the seed cancels only after 600 s")

    def getResult(self) -> _TaskResult:
        return _TaskResult.SUCCEEDED

    def lifecycleShutdown(self) -> None:
        pass


def test_unmodified_nav_to_pose_seed_preempts_at_120_s_and_exits_0(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    navigator = ModuleType(NAVIGATOR_MODULE)
    navigator.BasicNavigator = type(  # type: ignore[attr-defined]
        "BasicNavigator", (_ScriptedNavigator,), {"goals": [], "seen_defaults": []}
    )
    navigator.TaskResult = navigator.NavigationResult = _TaskResult  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, NAVIGATOR_MODULE, navigator)
    script = write(tmp_path, "nav_to_pose.py", NAV_TO_POSE_SEED)

    assert run_nav2_script(script, navigator_defaults={"world": "town"}) == 0

    lines = capsys.readouterr().out.splitlines()
    assert lines[-1] == "Goal succeeded!"
    assert lines[0] == "Distance remaining: 1.25 meters."
    # Polls 5, 10, ... print; the first print after 120 s of navigation (poll 1205) preempts.
    assert lines.index("Distance remaining: 301.25 meters.") == 240
    sent = navigator.BasicNavigator.goals
    assert [goal.pose.position.x for goal in sent] == [10.0, -3.0]
    assert sent[0].header.frame_id == "map" and sent[0].pose.position.y == -2.0
    assert navigator.BasicNavigator.seen_defaults[0].world == "town"
