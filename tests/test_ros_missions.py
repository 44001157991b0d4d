"""Missions that run node files (``ros_node``) and publish messages (``publish`` events), so
that ``expect:`` judges a node (baobab.missions.nodes_ros, baobab.nav.ros.mission_nodes)."""

from __future__ import annotations

from pathlib import Path

import pytest

from baobab.missions.language.bundled_missions import resolve_mission
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.missions.run.events import EventError
from baobab.missions.run.runner import run_mission

FIXTURES = Path(__file__).parent / "missions"

MISSION = """\
mission: ros_case
world: walls
robot: turtlebot3
tree:
  parallel:
    policy: success_on_one
    children:
      - ros_node: {{script: {script}}}
      - wait: 2
events:
{events}
timeout: 5
"""

FAILING = """\
import rclpy
from rclpy.node import Node
from std_msgs.msg import String


def main():
    rclpy.init()
    node = Node('picky')
    def on_message(msg):
        raise RuntimeError(f'cannot take {msg.data!r}')
    node.create_subscription(String, 'news', on_message, 10)
    rclpy.spin(node)
"""


def write_mission(folder: Path, script: str, events: str) -> Path:
    path = folder / "case.yaml"
    path.write_text(MISSION.format(script=script, events=events))
    return path


def test_a_node_hears_what_the_mission_publishes_and_stops_with_its_parent(
    capfd: pytest.CaptureFixture[str],
) -> None:
    record = run_mission(load_mission(FIXTURES / "ros_listener.yaml"))
    assert record.outcome.result == "SUCCEEDED" and record.outcome.sim_time == pytest.approx(2.0)
    err = capfd.readouterr().err
    assert '[INFO] [0.500000000] [listener]: I heard: "hello"' in err
    events = [line for line in record.trace.lines if '"publish"' in line]
    assert len(events) == 1 and '"topic":"/news"' in events[0]


def test_a_node_that_raises_fails_its_leaf_and_the_mission(
    tmp_path: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "picky.py").write_text(FAILING)
    events = "  - {at: 0.5, publish: {topic: news, type: std_msgs/msg/String, message: {data: hi}}}"
    record = run_mission(load_mission(write_mission(tmp_path, "picky.py", events)))
    assert record.outcome.result == "FAILED"
    assert record.outcome.error_msg.endswith("picky.py: RuntimeError: cannot take 'hi'")
    err = capfd.readouterr().err
    assert f'File "{tmp_path / "picky.py"}", line 10, in on_message' in err
    assert err.rstrip().endswith(
        f"{tmp_path / 'picky.py'}: node code failed ('picky'): RuntimeError: cannot take 'hi'"
    )


def test_a_missing_node_file_is_a_located_mission_error(tmp_path: Path) -> None:
    path = write_mission(tmp_path, "absent.py", "  - {at: 1, cancel: true}")
    with pytest.raises(
        MissionError, match=r"case\.yaml:8:20: ros_node\.script: no Python node file 'absent\.py'"
    ):
        load_mission(path)


def test_a_publish_event_whose_fields_do_not_fit_stops_the_run_before_it_starts(
    tmp_path: Path,
) -> None:
    (tmp_path / "picky.py").write_text(FAILING)
    events = "  - {at: 0.5, publish: {topic: news, type: std_msgs/msg/String, message: {text: hi}}}"
    mission = load_mission(write_mission(tmp_path, "picky.py", events))
    with pytest.raises(
        EventError, match=r"events\[0\]\.publish\.message: text: String has no such field"
    ):
        run_mission(mission)


def test_the_bundled_point_to_point_mission_judges_the_reference_node() -> None:
    mission = load_mission(resolve_mission("walls_ros_point2point"))
    digests = set()
    for _ in range(2):
        record = run_mission(mission)
        assert record.outcome.result == "SUCCEEDED"
        assert all(expectation.passed for expectation in record.expectations)
        digests.add(record.trace.digest)
    assert len(digests) == 1
