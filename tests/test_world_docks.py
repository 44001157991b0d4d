"""The world file's ``docks:`` and ``moving_objects:``, and Nav2's dock database files."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from baobab.sim.docks import PLATE_FRONT, Dock, load_dock_database
from baobab.sim.errors import SourceError, WorldError
from baobab.sim.geometry import clearance
from baobab.sim.moving_objects import Script
from baobab.sim.world import load_world

# Line numbers matter: the cases below point into this text.
GOOD = """\
name: docked
floor:
  size: [4.0, 3.0]
boxes:
  - {name: wall, center: [1.0, 0.0], size: [0.2, 2.0], yaw_deg: 90}
spawns:
  default: {x: 0.0, y: 0.0}
docks:
  home: {type: charging_dock, frame: map, pose: [1.8, 1.2, 0.0]}
moving_objects:
  - name: person
    waypoints: [{x: -1.5, y: -1.0}, {x: 1.5, y: -1.0, wait: 1.0}]
"""


def _write(tmp_path: Path, text: str, name: str = "world.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _edit(old: str, new: str) -> str:
    assert GOOD.count(old) == 1, old
    return GOOD.replace(old, new)


def test_a_dock_stands_in_the_world_as_three_static_boxes(tmp_path: Path) -> None:
    world = load_world(_write(tmp_path, GOOD))
    assert [box.name for box in world.dock_boxes] == ["home/back", "home/left", "home/right"]
    dock = world.docks["home"]
    # The back plate's face is PLATE_FRONT ahead of the dock pose: clearance sees it.
    face = clearance(world, [[dock.x + PLATE_FRONT - 0.01, dock.y]])
    assert float(face[0]) == pytest.approx(0.01, abs=1e-9)


def test_a_moving_object_walks_its_waypoints_then_waits_and_stays(tmp_path: Path) -> None:
    script = Script.of(load_world(_write(tmp_path, GOOD)).moving_objects[0])
    assert script.pose(0.0)[:2] == pytest.approx((-1.5, -1.0))
    assert script.pose(5.0)[:2] == pytest.approx((0.0, -1.0))  # 0.3 m/s for 5 s
    assert script.state(5.0)[3] == pytest.approx(0.3)
    assert script.state(10.5)[3] == 0.0  # waiting at the last waypoint
    assert script.pose(99.0)[:2] == pytest.approx((1.5, -1.0))


def test_a_velocity_profile_drives_exact_arcs(tmp_path: Path) -> None:
    text = _edit(
        "    waypoints: [{x: -1.5, y: -1.0}, {x: 1.5, y: -1.0, wait: 1.0}]\n",
        "    start: {x: -1.0, y: -0.8}\n"
        "    velocity_profile: [{duration: 3.14159265, linear: 0.3, angular: 1.0}]\n",
    )
    script = Script.of(load_world(_write(tmp_path, text)).moving_objects[0])
    x, y, yaw = script.pose(math.pi)
    # Half a circle of radius 0.3 m turning left: 0.6 m to the left of the start.
    assert (x, y, yaw) == pytest.approx((-1.0, -0.2, math.pi), abs=1e-6)


@pytest.mark.parametrize(
    ("text", "where", "fragment"),
    [
        pytest.param(
            _edit("pose: [1.8, 1.2, 0.0]", "pose: [1.1, 0.0, 0.0]"),
            "9:43",
            "docks.home.pose: dock 'home': it stands inside obstacle 'wall'; move the dock",
            id="dock-inside-a-wall",
        ),
        pytest.param(
            _edit("pose: [1.8, 1.2, 0.0]", "pose: [1.95, 1.2, 0.0]"),
            "9:43",
            "dock 'home' stands partly off the floor",
            id="dock-off-the-floor",
        ),
        pytest.param(
            _edit("type: charging_dock", "type: nova_carter_dock"),
            "9:10",
            "unknown dock type 'nova_carter_dock'",
            id="unknown-dock-type",
        ),
        pytest.param(
            _edit("frame: map", "frame: base_link"),
            "9:31",
            "frame 'base_link': docks are given in the map frame",
            id="dock-frame",
        ),
        pytest.param(
            _edit("{x: -1.5, y: -1.0}, {x: 1.5, y: -1.0,", "{x: -1.5, y: -1.0}, {x: 1.5, y: 0.0,"),
            "12:37",
            "'person' (radius 0.2 m) walks into 'wall'",
            id="object-walks-into-a-wall",
        ),
        pytest.param(
            _edit("{x: 1.5, y: -1.0, wait: 1.0}]", "{x: 1.5, y: -1.4, wait: 1.0}]"),
            "12:37",
            "'person' (radius 0.2 m) leaves the floor",
            id="object-leaves-the-floor",
        ),
        pytest.param(
            _edit("    waypoints: [{x: -1.5, y: -1.0}, ", "    waypoints: ["),
            "12:5",
            "needs at least two waypoints",
            id="one-waypoint",
        ),
        pytest.param(
            _edit("  - name: person\n", "  - name: person\n    frame: map\n"),
            "12:5",
            "frame 'map' is taken",
            id="reserved-frame",
        ),
    ],
)
def test_bad_docks_and_objects_are_located_errors(
    tmp_path: Path, text: str, where: str, fragment: str
) -> None:
    path = _write(tmp_path, text)
    with pytest.raises(WorldError) as caught:
        load_world(path)
    message = str(caught.value)
    assert message.startswith(f"{path}:{where}: "), message
    assert fragment in message
    assert "\n" not in message


def test_a_dock_database_in_nav2s_format_loads(tmp_path: Path) -> None:
    path = _write(
        tmp_path,
        "docks:\n"
        "  home:\n"
        "    type: ''\n"
        "    frame: map\n"
        "    pose: [0.3, 0.0, 1.57]\n"
        "  spare:\n"
        "    type: charging_dock\n"
        "    pose: [1.0, 2.0, 0.0]\n"
        "    id: c67f50cb\n",
        "docks.yaml",
    )
    assert load_dock_database(path) == {
        "home": Dock(type="charging_dock", frame="map", pose=(0.3, 0.0, 1.57)),
        "spare": Dock(pose=(1.0, 2.0, 0.0), id="c67f50cb"),
    }


def test_a_dock_database_without_a_pose_is_a_located_error(tmp_path: Path) -> None:
    path = _write(tmp_path, "docks:\n  home:\n    type: charging_dock\n", "docks.yaml")
    with pytest.raises(SourceError, match=r"docks\.yaml:2:3: .*missing required key 'pose'"):
        load_dock_database(path)


def test_a_moving_object_moves_its_mocap_body_in_the_simulation(tmp_path: Path) -> None:
    from baobab.robots.turtlebot3 import build_turtlebot3_sim
    from baobab.sim.moving_object_motion import moving_object_body, start_moving_objects

    world = load_world(_write(tmp_path, GOOD))
    sim, _robot = build_turtlebot3_sim(world, None)
    objects = start_moving_objects(sim, world)
    assert objects is not None
    sim.step_for(3.0)
    mocap = int(sim.model.body(moving_object_body("person")).mocapid[0])
    x, y, z = (float(v) for v in sim.data.mocap_pos[mocap])
    assert objects.pose("person").x == pytest.approx(-0.6)
    assert (x, y, z) == pytest.approx((-0.6, -1.0, 0.85), abs=0.3 * 0.02 + 1e-9)
    objects.walk("person", [(-0.6, 1.0)], speed=0.5)
    sim.step_for(1.0)
    assert objects.pose("person").y == pytest.approx(-0.5)
    objects.close()
