"""A Nav2 parameter file's ``collision_monitor`` node configures the collision monitor."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from baobab.missions.cli.command_line import main
from baobab.missions.language.loader import load_mission
from baobab.nav.collision_monitor_params import ActionType
from baobab.nav.msgs import pose_stamped
from baobab.nav.nav2_configuration import load_nav2_params
from baobab.nav.nav2_params_file import Nav2ParamsError
from baobab.nav.navigator import BasicNavigator

MONITOR = """\
controller_server:
  ros__parameters:
    controller_frequency: 20.0
collision_monitor:
  ros__parameters:
    base_frame_id: base_footprint
    stop_pub_timeout: 0.7
    polygons: [PolygonStop]
    PolygonStop:
      type: polygon
      points: {points}
      action_type: stop
      min_points: 3
    observation_sources: [scan]
    scan:
      type: scan
      topic: /scan
"""
SQUARE = '"[[0.3, 0.25], [0.3, -0.25], [-0.1, -0.25], [-0.1, 0.25]]"'


def _params(folder: Path, points: str = SQUARE, name: str = "nav2_params.yaml") -> Path:
    path = folder / name
    path.write_text(MONITOR.format(points=points), encoding="utf-8")
    return path


def test_the_files_stop_polygon_configures_the_navigators_monitor(tmp_path: Path) -> None:
    navigator = BasicNavigator(world="walls", params_file=_params(tmp_path))
    try:
        toggle = navigator.server.services["collision_monitor/toggle"]
        monitor = toggle.__self__  # type: ignore[attr-defined]
        assert monitor.params.stop_pub_timeout == pytest.approx(0.7)
        (zone,) = monitor.params.polygons
        assert (zone.name, zone.action_type, zone.min_points) == ("PolygonStop", ActionType.STOP, 3)
        assert zone.points == ((0.3, 0.25), (0.3, -0.25), (-0.1, -0.25), (-0.1, 0.25))
        navigator.toggleCollisionMonitor(False)
        assert not monitor.enabled
    finally:
        navigator.destroy_node()


WIDE = '"[[3.0, 3.0], [3.0, -3.0], [-3.0, -3.0], [-3.0, 3.0]]"'
"""A stop zone that holds the walls round the start: the monitor stops every command."""


def _driven(navigator: BasicNavigator, polls: int = 30) -> float:
    """Distance (m) the robot moves during ``polls`` completion polls (0.1 s of sim each)."""
    start = navigator.robot_pose()
    for _ in range(polls):
        navigator.isTaskComplete()
    end = navigator.robot_pose()
    return float(((end.x - start.x) ** 2 + (end.y - start.y) ** 2) ** 0.5)


def test_the_files_stop_zone_holds_the_robot_until_toggled_off(tmp_path: Path) -> None:
    navigator = BasicNavigator(world="walls", params_file=_params(tmp_path, points=WIDE))
    try:
        navigator.goToPose(pose_stamped(0.5, 0.5))
        assert _driven(navigator) < 0.01
        navigator.toggleCollisionMonitor(False)
        assert _driven(navigator) > 0.1
    finally:
        navigator.destroy_node()


def test_the_constructors_parameters_override_the_file_parameter_by_parameter(
    tmp_path: Path,
) -> None:
    navigator = BasicNavigator(
        world="walls",
        params_file=_params(tmp_path),
        collision_monitor={"PolygonStop": {"min_points": 5}},
    )
    try:
        monitor = navigator.server.services["collision_monitor/toggle"].__self__  # type: ignore[attr-defined]
        (zone,) = monitor.params.polygons
        assert zone.min_points == 5 and zone.points[0] == (0.3, 0.25)
    finally:
        navigator.destroy_node()


def test_without_the_node_the_navigator_has_no_monitor(tmp_path: Path) -> None:
    path = tmp_path / "nav2_params.yaml"
    path.write_text("controller_server:\n  ros__parameters:\n    controller_frequency: 20.0\n")
    navigator = BasicNavigator(world="walls", params_file=path)
    try:
        assert "collision_monitor/toggle" not in navigator.server.services
    finally:
        navigator.destroy_node()


def test_a_bad_polygon_is_located_in_the_file(tmp_path: Path) -> None:
    path = _params(tmp_path, points='"[[0.3, 0.25], [0.3, -0.25]]"')
    with pytest.raises(Nav2ParamsError) as caught:
        load_nav2_params(path)
    assert str(caught.value).startswith(f"{path}:11:7: collision_monitor.PolygonStop.points:")


def test_a_mistake_found_only_against_the_robot_is_located_in_the_file(tmp_path: Path) -> None:
    path = tmp_path / "nav2_params.yaml"
    text = MONITOR.format(points='"[[0.05, 0.02], [0.05, -0.02], [0.0, 0.0]]"')
    path.write_text(text.replace("action_type: stop", "action_type: approach"))
    with pytest.raises(Nav2ParamsError, match=r"nav2_params.yaml:11:7: .*must contain the robot"):
        BasicNavigator(world="walls", params_file=path)


def test_nav2_params_lists_the_monitors_parameters_as_used(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["nav2-params", str(_params(tmp_path)), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    used = {(p["name"], p["line"]) for p in data["parameters"] if p["node"] == "collision_monitor"}
    assert ("PolygonStop.points", 11) in used and ("base_frame_id", 6) in used
    assert "collision_monitor" not in data["ignored_nodes"]
    assert not any("collision_monitor" in group for group in data["unused"])
    assert main(["nav2-params", str(_params(tmp_path))]) == 0
    out = capsys.readouterr().out
    assert "collision_monitor:" in out and "PolygonStop.action_type" in out


MISSION = """\
mission: m
world: walls
robot: turtlebot3
{extra}
tree:
  toggle_collision_monitor: false
"""


def test_a_missions_file_layer_sits_between_its_world_and_its_own_block(tmp_path: Path) -> None:
    _params(tmp_path)
    mission_path = tmp_path / "m.yaml"
    extra = "nav2_params: ./nav2_params.yaml\ncollision_monitor:\n  PolygonStop: {min_points: 6}"
    mission_path.write_text(MISSION.format(extra=extra))
    mission = load_mission(mission_path)
    assert mission.collision_monitor is not None
    (zone,) = mission.collision_monitor.polygons
    assert zone.min_points == 6 and zone.points[0] == (0.3, 0.25)
    assert mission.collision_monitor.stop_pub_timeout == pytest.approx(0.7)


def test_nav2_params_flag_gives_a_mission_its_monitor(tmp_path: Path) -> None:
    params = _params(tmp_path, name="elsewhere.yaml")
    mission_path = tmp_path / "m.yaml"
    mission_path.write_text(MISSION.format(extra=""))
    mission = load_mission(mission_path, nav2_params=params)
    assert mission.collision_monitor is not None
    assert mission.collision_monitor.polygons[0].min_points == 3


def test_run_exits_2_with_the_files_line_for_a_bad_polygon(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    params = _params(tmp_path, points='"[[0.3, 0.25], [0.3, -0.25]]"')
    mission_path = tmp_path / "m.yaml"
    mission_path.write_text(MISSION.format(extra="nav2_params: ./nav2_params.yaml"))
    assert main(["run", str(mission_path)]) == 2
    assert f"{params}:11:7: collision_monitor.PolygonStop.points" in capsys.readouterr().err


def test_the_file_overrides_its_worlds_block_and_the_mission_the_file(tmp_path: Path) -> None:
    world = (Path(__file__).parents[1] / "sim" / "worlds" / "walls.yaml").read_text()
    (tmp_path / "room.yaml").write_text(
        world
        + "collision_monitor:\n"
        + "  polygons: [PolygonStop]\n"
        + "  PolygonStop: {type: circle, radius: 0.3, action_type: stop, min_points: 2}\n"
        + "  observation_sources: [scan]\n"
        + "  scan: {type: scan}\n"
        + "  source_timeout: 1.5\n",
        encoding="utf-8",
    )
    (tmp_path / "nav2_params.yaml").write_text(
        "collision_monitor:\n  ros__parameters:\n"
        "    source_timeout: 0.8\n    PolygonStop: {radius: 0.4, min_points: 5}\n"
    )
    mission_path = tmp_path / "m.yaml"
    extra = "nav2_params: ./nav2_params.yaml\ncollision_monitor:\n  PolygonStop: {min_points: 7}"
    mission_path.write_text(MISSION.format(extra=extra).replace("world: walls", "world: room.yaml"))
    monitor = load_mission(mission_path).collision_monitor
    assert monitor is not None
    (zone,) = monitor.polygons
    assert (zone.type, zone.radius, zone.min_points) == ("circle", 0.4, 7)
    assert monitor.source_timeout == pytest.approx(0.8)


def test_a_partial_files_mistake_is_located_in_the_file_not_the_world(tmp_path: Path) -> None:
    path = tmp_path / "nav2_params.yaml"
    path.write_text("collision_monitor:\n  ros__parameters:\n    PolygonStop: {radius: -1.0}\n")
    with pytest.raises(Nav2ParamsError, match=r"nav2_params.yaml:3:19: .*PolygonStop.radius"):
        BasicNavigator(world="walls", params_file=path, collision_monitor=_BLOCK)


_BLOCK = {
    "polygons": ["PolygonStop"],
    "PolygonStop": {"type": "circle", "action_type": "stop"},
    "observation_sources": ["scan"],
    "scan": {"type": "scan"},
}
