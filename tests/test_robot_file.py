"""A user's own differential-drive robot from a YAML file: built from its facts, driven by the
same navigation stack, and every mistake in the file one located error (exit 2)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
import yaml

from baobab.missions.cli.command_line import main
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.missions.run.runner import run_mission
from baobab.nav import BasicNavigator, TaskResult
from baobab.nav.msgs import pose_stamped
from baobab.robots.robot_file import RobotFileError, load_robot_file
from baobab.sim.world import Pose2D

ROVER = """\
name: rover
description: a small box rover
footprint: {polygon: [[0.16, 0.15], [-0.2, 0.15], [-0.2, -0.15], [0.16, -0.15]]}
body: {shape: box, length: 0.32, width: 0.26, height: 0.12, bottom: 0.02, center_x: -0.02}
wheels: {radius: 0.04, separation: 0.24, width: 0.02, mass: 0.15}
casters: [{x: -0.15, y: 0.0, radius: 0.012}]
mass: 3.0
limits: {linear_speed: 0.4, angular_speed: 2.0, linear_accel: 1.0, angular_accel: 4.0}
lidar: {x: -0.02, z: 0.2, range_min: 0.12, range_max: 8.0, rate: 10, beams: 360}
"""


def _write(folder: Path, text: str, name: str = "rover.yaml") -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def _mission(folder: Path, robot: str = "./rover.yaml", extra: str = "") -> Path:
    path = folder / "mission.yaml"
    path.write_text(
        f"mission: rover_run\nworld: walls\nrobot: {robot}\n{extra}"
        "tree:\n  navigate_to_pose: {goal: goal_open}\n"
        "expect: {result: SUCCEEDED, no_contact: true}\n",
        encoding="utf-8",
    )
    return path


def test_a_robot_file_gives_facts_and_the_defaults_they_decide(tmp_path: Path) -> None:
    robot = load_robot_file(_write(tmp_path, ROVER))
    facts = robot.mobile_facts
    assert robot.name == "rover" and robot.path == str((tmp_path / "rover.yaml").resolve())
    assert facts.chassis_mass == pytest.approx(3.0 - 0.3)
    assert facts.lidar.range_max == 8.0 and facts.lidar.rate == 10
    tuning = robot.tuning
    assert tuning.max_linear_speed == 0.4 and tuning.teleop_speeds == (0.25, 1.2)
    assert tuning.footprint.inscribed_radius == pytest.approx(0.15 + 0.01)
    assert tuning.scan_timeout == pytest.approx(0.5)


def test_a_mission_runs_a_robot_file_from_its_folder(tmp_path: Path) -> None:
    _write(tmp_path, ROVER)
    mission = load_mission(_mission(tmp_path))
    assert mission.robot.name == "rover"
    record = run_mission(mission)
    assert record.intended, [(e.name, e.measured) for e in record.expectations]
    driven = record.metrics["path_length"]
    assert isinstance(driven, float) and driven > 2.0


def test_a_robot_file_outside_the_missions_folder_is_refused(tmp_path: Path) -> None:
    inner = tmp_path / "inner"
    inner.mkdir()
    _write(tmp_path, ROVER)
    with pytest.raises(
        MissionError, match=r"mission.yaml:3:1: robot file '\.\./rover\.yaml' is outside"
    ):
        load_mission(_mission(inner, robot="../rover.yaml"))
    with pytest.raises(MissionError, match=r"no robot file '\./missing\.yaml'"):
        load_mission(_mission(inner, robot="./missing.yaml"))


def test_the_navigator_drives_a_robot_file(tmp_path: Path) -> None:
    path = _write(tmp_path, ROVER)
    navigator = BasicNavigator(world="walls", robot=str(path))
    navigator.goToPose(pose_stamped(1.0, 1.0, 0.0))
    while not navigator.isTaskComplete():
        pass
    assert navigator.getResult() == TaskResult.SUCCEEDED
    pose = navigator.robot_pose()
    assert math.hypot(pose.x - 1.0, pose.y - 1.0) < 0.26
    navigator.destroyNode()


def _edited(change: dict[str, object]) -> str:
    """ROVER with the keys of ``change`` replaced (a dotted key reaches inside a mapping)."""
    data = yaml.safe_load(ROVER)
    for key, value in change.items():
        node = data
        *parents, last = key.split(".")
        for part in parents:
            node = node[part]
        if value is None:
            del node[last]
        else:
            node[last] = value
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=None)


MISTAKES = [
    ("missing facts", {"wheels": None}, "missing required key 'wheels'"),
    ("a zero size", {"wheels.radius": 0.0}, "greater than 0"),
    ("a negative mass", {"mass": -1.0}, "greater than 0"),
    ("an unknown key", {"colour": "red"}, "unknown key 'colour'"),
    ("a lidar off the body", {"lidar.x": 0.3}, "mounted outside the body"),
    ("a lidar under the body", {"lidar.z": 0.01}, "below the body's underside"),
    (
        "a footprint that is not simple",
        {"footprint.polygon": [[0.16, 0.15], [-0.2, -0.15], [-0.2, 0.15], [0.16, -0.15]]},
        "is not simple",
    ),
    (
        "a footprint without base_link",
        {"footprint.polygon": [[0.1, 0.1], [0.3, 0.1], [0.2, 0.3]]},
        "must hold base_link",
    ),
    (
        "a body outside the footprint",
        {"body.length": 0.5},
        "the body reaches outside the footprint",
    ),
    ("a wheel outside the footprint", {"wheels.separation": 0.4}, "a wheel reaches outside"),
    ("a tipping robot", {"casters": [{"x": 0.1}]}, "would tip over"),
    ("ranges the wrong way", {"lidar.range_min": 9.0}, "range_min 9 m must be below range_max 8 m"),
    (
        "a speed the wheels cannot reach",
        {"limits.wheel_speed": 5.0},
        "linear_speed 0.4 m/s contradicts wheel_speed 5 rad/s",
    ),
    (
        "an acceleration the motors cannot give",
        {"limits.wheel_torque": 0.01},
        "linear_accel 1 m/s^2 contradicts wheel_torque 0.01 N m",
    ),
]


@pytest.mark.parametrize(("case", "change", "fragment"), MISTAKES, ids=[m[0] for m in MISTAKES])
def test_every_mistake_in_a_robot_file_is_one_located_error(
    tmp_path: Path, case: str, change: dict[str, object], fragment: str
) -> None:
    path = _write(tmp_path, _edited(change))
    with pytest.raises(RobotFileError) as caught:
        load_robot_file(path)
    message = str(caught.value)
    assert message.startswith(f"{path}:"), message
    assert fragment in message, message
    line = int(message.split(":")[1])
    key = next(iter(change)).split(".")[0]
    text = path.read_text(encoding="utf-8")
    if key in yaml.safe_load(text):  # located in the block of the key that is wrong
        assert _block_of(text, line) == key, (message, text)


def _block_of(text: str, line: int) -> str:
    """The top-level key whose block holds the 1-based ``line``."""
    top = ""
    for number, content in enumerate(text.splitlines(), 1):
        if content and not content[0].isspace() and not content.startswith("-"):
            top = content.split(":")[0]
        if number == line:
            return top
    return ""


def test_a_bad_robot_file_exits_2_with_its_located_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _write(tmp_path, _edited({"lidar.x": 0.3}))
    mission = _mission(tmp_path)
    assert main(["validate", str(mission)]) == 2
    err = capsys.readouterr().err
    assert f"{tmp_path / 'rover.yaml'}:" in err and "mounted outside the body" in err
    assert main(["run", str(mission), "--json", "--out", str(tmp_path / "run")]) == 2
    assert not (tmp_path / "run").exists()


def test_nav2_and_teleop_take_a_robot_file_or_refuse_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = tmp_path / "script.py"
    script.write_text(
        "from nav2_simple_commander.robot_navigator import BasicNavigator\n"
        "navigator = BasicNavigator()\n"
        "print('robot', navigator.robot_pose().x)\n",
        encoding="utf-8",
    )
    rover = _write(tmp_path, ROVER)
    assert main(["nav2", str(script), "--world", "walls", "--robot", str(rover)]) == 0
    assert "robot 0.0" in capsys.readouterr().out
    bad = _write(tmp_path, _edited({"mass": 0.1}), "bad.yaml")
    assert main(["nav2", str(script), "--world", "walls", "--robot", str(bad)]) == 2
    mass_line = bad.read_text(encoding="utf-8").splitlines().index("mass: 0.1") + 1
    assert f"{bad}:{mass_line}:" in capsys.readouterr().err
    assert main(["nav2", str(script), "--world", "walls", "--robot", "panda"]) == 2
    assert "does not drive" in capsys.readouterr().err
    assert main(["teleop", "--world", "walls", "--robot", "turtlebot9"]) == 2
    assert "unknown robot 'turtlebot9'" in capsys.readouterr().err


def test_list_json_describes_robots_as_data(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["list", "--json"]) == 0
    robots = json.loads(capsys.readouterr().out)["robots"]
    assert robots["turtlebot4"]["footprint"] == {"radius": 0.175}
    assert robots["turtlebot4"]["max_linear_speed"] == 0.306


def test_a_robot_file_start_that_is_not_free_is_refused(tmp_path: Path) -> None:
    _write(tmp_path, ROVER)
    with pytest.raises(MissionError, match="too narrow for robot 'rover'"):
        load_mission(_mission(tmp_path, extra="start: {x: 2.85, y: 0.0, yaw: 0.0}\n"))
    start = load_mission(_mission(tmp_path, extra="start: {x: 2.7, y: 0.0, yaw: 0.0}\n")).start
    assert start == Pose2D(x=2.7, y=0.0, yaw=0.0)
