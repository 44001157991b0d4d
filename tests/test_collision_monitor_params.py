"""The collision monitor's parameters: Nav2's names and defaults, each mistake named by its key
path, a mission's block merged over its world's, and the navigator's toggle service.

Located errors in mission and world files (exit 2) are in the bad-input corpus
(``tests/bad_inputs/*/collision_monitor_*``)."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import pytest

from baobab.missions.language.loader import load_mission
from baobab.nav import BasicNavigator
from baobab.nav.collision_monitor_config import (
    layered_collision_monitor,
    merge_layers,
    parse_collision_monitor,
)
from baobab.nav.collision_monitor_params import (
    ActionType,
    CollisionMonitorConfigError,
    PolygonParams,
)
from baobab.nav.navigator_robot import NavigatorSetupError
from baobab.robots.footprint import Footprint

BLOCK: dict[str, Any] = {
    "polygons": ["PolygonStop"],
    "PolygonStop": {"type": "circle", "radius": 0.3, "action_type": "stop"},
    "observation_sources": ["scan"],
    "scan": {"type": "scan", "topic": "/scan"},
}
BURGER = Footprint.circle(0.105)
WAFFLE = Footprint.rectangle(-0.2045, 0.0765, -0.153, 0.153)


def with_changes(**changes: Any) -> dict[str, Any]:
    """BLOCK with top-level keys replaced; a key's value None removes it."""
    block = copy.deepcopy(BLOCK)
    for key, value in changes.items():
        if value is None:
            del block[key]
        else:
            block[key] = value
    return block


def test_nav2s_defaults() -> None:
    params = parse_collision_monitor(BLOCK)
    assert (
        params.enabled,
        params.source_timeout,
        params.base_shift_correction,
        params.stop_pub_timeout,
    ) == (True, 2.0, True, 1.0)
    (zone,) = params.polygons
    assert zone == PolygonParams(
        name="PolygonStop", type="circle", action_type=ActionType.STOP, radius=0.3
    )
    assert (zone.min_points, zone.slowdown_ratio, zone.linear_limit, zone.angular_limit) == (
        4,
        0.5,
        0.5,
        0.5,
    )
    assert (zone.time_before_collision, zone.simulation_time_step) == (2.0, 0.1)
    assert (zone.trigger_consecutive_points, zone.release_consecutive_points) == (1, 1)
    (source,) = params.observation_sources
    assert (source.type, source.enabled, params.timeout_of(source)) == ("scan", True, 2.0)


def test_nav2s_points_forms_are_read_alike() -> None:
    forms = [
        "[[0.4, 0.3], [0.4, -0.3], [0.0, -0.3], [0.0, 0.3]]",
        [[0.4, 0.3], [0.4, -0.3], [0.0, -0.3], [0.0, 0.3]],
        [0.4, 0.3, 0.4, -0.3, 0.0, -0.3, 0.0, 0.3],  # Humble's flat list
    ]
    read = {
        parse_collision_monitor(
            with_changes(PolygonStop={"type": "polygon", "points": form, "action_type": "stop"})
        )
        .polygons[0]
        .points
        for form in forms
    }
    assert read == {((0.4, 0.3), (0.4, -0.3), (0.0, -0.3), (0.0, 0.3))}


STOP = {"type": "circle", "radius": 0.3, "action_type": "stop"}
MISTAKES = [
    (
        {"PolygonStop": {**STOP, "action_type": "halt"}},
        ("PolygonStop", "action_type"),
        "unknown action_type 'halt'",
    ),
    ({"PolygonStop": {"type": "circle", "radius": 0.3}}, ("PolygonStop",), "'action_type'"),
    ({"PolygonStop": {**STOP, "radius": 0}}, ("PolygonStop", "radius"), "expected a finite"),
    (
        {"PolygonStop": {"type": "circle", "action_type": "stop"}},
        ("PolygonStop",),
        "a circle needs radius",
    ),
    (
        {"PolygonStop": {"type": "polygon", "action_type": "stop", "points": "[[0, 0], [1, 1]]"}},
        ("PolygonStop", "points"),
        "at least 3 points",
    ),
    (
        {
            "PolygonStop": {
                "type": "polygon",
                "action_type": "stop",
                "points": "[[0, 0], [1, 1], [1, 0], [0, 1]]",
            }
        },
        ("PolygonStop", "points"),
        "edges 1 and 3 cross",
    ),
    (
        {"PolygonStop": {"type": "polygon", "action_type": "stop", "points": [0, 0, 1, 0, 2, 0]}},
        ("PolygonStop", "points"),
        "no area",
    ),
    (
        {"PolygonStop": {**STOP, "min_point": 3}},
        ("PolygonStop", "min_point"),
        "did you mean 'min_points'",
    ),
    (
        {"PolygonStop": {**STOP, "min_points": 3, "max_points": 2}},
        ("PolygonStop", "max_points"),
        "not both",
    ),
    (
        {"PolygonStop": {**STOP, "slowdown_ratio": 1.5}},
        ("PolygonStop", "slowdown_ratio"),
        "<= 1",
    ),
    (
        {"PolygonStop": {**STOP, "sources_names": ["lidar"]}},
        ("PolygonStop", "sources_names", 0),
        "unknown source 'lidar'",
    ),
    (
        {"scan": {"type": "pointcloud", "topic": "/points"}},
        ("scan", "type"),
        "pointcloud source is not supported",
    ),
    ({"scan": {"type": "scan", "topic": "/front_scan"}}, ("scan", "topic"), "publishes /scan"),
    ({"polygons": []}, ("polygons",), "at least one name"),
    ({"polygons": ["PolygonStop", "PolygonStop"]}, ("polygons", 1), "listed twice"),
    ({"source_timeout": -1}, ("source_timeout",), ">= 0"),
    ({"enabled": "yes"}, ("enabled",), "expected true or false"),
]


@pytest.mark.parametrize(("changes", "key_path", "fragment"), MISTAKES)
def test_each_mistake_names_its_key_path(
    changes: dict[str, Any], key_path: tuple[str | int, ...], fragment: str
) -> None:
    with pytest.raises(CollisionMonitorConfigError) as caught:
        parse_collision_monitor(with_changes(**changes))
    assert caught.value.key_path == key_path
    assert fragment in caught.value.problem


@pytest.mark.parametrize(
    ("zone", "footprint", "fits"),
    [
        ({"type": "polygon"}, WAFFLE, True),  # no points: the robot's own footprint
        ({"type": "circle", "radius": 0.11}, BURGER, True),
        ({"type": "circle", "radius": 0.1}, BURGER, False),
        ({"type": "circle", "radius": 0.25}, WAFFLE, False),  # the Waffle's corners: 0.25 m
        (
            {"type": "polygon", "points": "[[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2], [-0.2, 0.2]]"},
            BURGER,
            True,
        ),
        (
            {"type": "polygon", "points": "[[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2], [-0.2, 0.2]]"},
            WAFFLE,
            False,
        ),
        (
            {"type": "polygon", "points": "[[0.5, 0.1], [0.5, -0.1], [0.0, -0.1], [0.0, 0.1]]"},
            BURGER,
            False,
        ),
    ],
)
def test_an_approach_zone_must_contain_the_robot(
    zone: dict[str, Any], footprint: Footprint, fits: bool
) -> None:
    block = with_changes(PolygonStop={**zone, "action_type": "approach"})
    if fits:
        assert layered_collision_monitor([block], footprint) is not None
        return
    with pytest.raises(CollisionMonitorConfigError, match="must contain the robot"):
        layered_collision_monitor([block], footprint)


def test_stop_and_slowdown_zones_need_not_contain_the_robot() -> None:
    ahead = {"type": "polygon", "points": "[[0.5, 0.1], [0.5, -0.1], [0.2, -0.1], [0.2, 0.1]]"}
    block = with_changes(PolygonStop={**ahead, "action_type": "stop"})
    assert layered_collision_monitor([block], BURGER) is not None


def test_a_later_layer_wins_parameter_by_parameter_and_mistakes_name_their_layer() -> None:
    world = with_changes(
        polygons=["PolygonStop", "PolygonSlow"],
        PolygonSlow={"type": "circle", "radius": 0.6, "action_type": "slowdown"},
    )
    mission = {"PolygonSlow": {"enabled": False, "slowdown_ratio": 0.3}}
    merged = merge_layers([world, mission])
    assert merged["PolygonSlow"] == {
        "type": "circle",
        "radius": 0.6,
        "action_type": "slowdown",
        "enabled": False,
        "slowdown_ratio": 0.3,
    }
    params = layered_collision_monitor([world, mission], BURGER)
    assert params is not None and not params.polygons[1].enabled
    assert layered_collision_monitor([None, None], BURGER) is None
    with pytest.raises(CollisionMonitorConfigError) as caught:
        layered_collision_monitor([world, {"PolygonSlow": {"radius": -1}}], BURGER)
    assert caught.value.layer == 1
    bad_world = with_changes(PolygonStop={**STOP, "radius": -1})
    with pytest.raises(CollisionMonitorConfigError) as caught:
        layered_collision_monitor([bad_world, mission], BURGER)
    assert caught.value.layer == 0


def test_a_mission_block_takes_parameters_and_merges_over_its_worlds(tmp_path: Path) -> None:
    world = (Path(__file__).parents[1] / "sim" / "worlds" / "walls.yaml").read_text()
    (tmp_path / "room.yaml").write_text(
        world
        + "collision_monitor:\n"
        + "  polygons: [PolygonStop]\n"
        + "  PolygonStop: {type: circle, radius: 0.3, action_type: stop}\n"
        + "  observation_sources: [scan]\n"
        + "  scan: {type: scan}\n",
        encoding="utf-8",
    )
    mission = tmp_path / "m.yaml"
    mission.write_text(
        "mission: m\nworld: room.yaml\nrobot: turtlebot3\n"
        "params:\n  radius: {type: float, default: 0.4}\n"
        "collision_monitor:\n  PolygonStop: {radius: '${radius}'}\n"
        "tree: {toggle_collision_monitor: false}\n",
        encoding="utf-8",
    )
    loaded = load_mission(mission, {"radius": "0.35"})
    assert loaded.collision_monitor is not None
    assert loaded.collision_monitor.polygons[0].radius == pytest.approx(0.35)
    assert loaded.collision_monitor.polygons[0].action_type is ActionType.STOP


# --- BasicNavigator ---------------------------------------------------------------------------


def test_the_navigator_serves_the_toggle_of_its_monitor(capsys: pytest.CaptureFixture[str]) -> None:
    navigator = BasicNavigator(world="walls", collision_monitor=BLOCK)
    try:
        monitor = navigator.server.services["collision_monitor/toggle"].__self__  # type: ignore[attr-defined]
        assert monitor.enabled
        navigator.toggleCollisionMonitor(False)
        assert not monitor.enabled
        navigator.toggleCollisionMonitor(True)
        assert monitor.enabled
        err = capsys.readouterr().err
        assert "Collision monitor disabled" in err and "Collision monitor enabled" in err
    finally:
        navigator.destroy_node()


def test_the_navigator_refuses_bad_parameters_by_name() -> None:
    bad = with_changes(PolygonStop={**STOP, "radius": math.inf})
    with pytest.raises(NavigatorSetupError, match=r"collision_monitor\.PolygonStop\.radius"):
        BasicNavigator(world="walls", collision_monitor=bad)
