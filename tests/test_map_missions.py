"""Missions on map_server maps: ``world: ./map.yaml``, ``filters:``, ``--world`` and ``--start``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from map_files import room_pixels, write_map

from baobab.missions.cli.command_line import main
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission

ROOM = (80, 60)
"""A 4 m x 3 m room on a map (0.05 m cells, origin 0, 0): the origin is in its wall."""


def _mission(folder: Path, extra: str = "", *, start: str | None = "{x: 1.0, y: 1.5}") -> Path:
    """A mission driving across the room on ``./room.yaml``; ``extra`` is appended."""
    write_map(folder, room_pixels(*ROOM), name="room")
    lines = [
        "mission: across",
        "world: ./room.yaml",
        "robot: turtlebot3",
        *([f"start: {start}"] if start is not None else []),
        "tree: {navigate_to_pose: {goal: {x: 3.0, y: 1.5}}}",
        "timeout: 60",
    ]
    path = folder / "across.yaml"
    path.write_text("\n".join(lines) + "\n" + extra)
    return path


def _error(path: Path, **options: object) -> MissionError:
    with pytest.raises(MissionError) as caught:
        load_mission(path, **options)  # type: ignore[arg-type]
    return caught.value


def test_a_mission_on_a_map_yaml_loads_its_map(tmp_path: Path) -> None:
    mission = load_mission(_mission(tmp_path))
    assert mission.world is not None and mission.world.grid is not None
    assert mission.world.bounds == (0.0, 0.0, 4.0, 3.0)
    assert mission.start is not None and (mission.start.x, mission.start.y) == (1.0, 1.5)


def test_a_map_has_no_spawn_so_the_mission_needs_a_start(tmp_path: Path) -> None:
    error = _error(_mission(tmp_path, start=None))
    assert error.line == 2  # at world:
    assert "world 'room' is a map with no spawn; give the mission a start" in str(error)


def test_a_start_in_the_maps_walls_is_refused_at_validate(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _mission(tmp_path, start="{x: 0.06, y: 1.5}")
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith(f"{path}:4:1: start (0.06, 1.50) ")
    assert "inside obstacle 'the map's walls'" in err[0]


def _masks(folder: Path) -> None:
    keepout = np.full((ROOM[1], ROOM[0]), 254, dtype=np.uint8)
    keepout[20:40, 50:60] = 0
    write_map(folder, keepout, name="keepout")
    speed = np.full((ROOM[1], ROOM[0]), 255, dtype=np.uint8)
    speed[:, 20:40] = 127
    write_map(folder, speed, name="speed", mode="scale", occupied_thresh=1.0, free_thresh=0.0)


def test_a_mission_brings_its_own_filter_masks(tmp_path: Path) -> None:
    _masks(tmp_path)
    extra = "filters:\n  keepout: ./keepout.yaml\n  speed: {mask: ./speed.yaml, base: 100}\n"
    mission = load_mission(_mission(tmp_path, extra))
    world = mission.world
    assert world is not None and world.filters is not None
    assert world.masks.keepout is not None and world.masks.speed is not None
    assert world.masks.keepout.value_at(2.75, 1.5) == 100
    assert world.filters.speed is not None and world.filters.speed.multiplier == -1.0


@pytest.mark.parametrize(
    ("filters", "where", "message"),
    [
        ("{keepout: ../keepout.yaml}", (7, 11), "outside the mission's folder"),
        ("{speed: ./nowhere.yaml}", (7, 11), "the speed mask './nowhere.yaml' does not exist"),
        ("{keepout: {mask: ./keepout.yaml, base: 3}}", (7, 43), "does not use base"),
        ("{keepout: '${zone}'}", (7, 11), "parameters are not substituted in 'filters'"),
    ],
)
def test_bad_mission_filters_are_located(
    tmp_path: Path, filters: str, where: tuple[int, int], message: str
) -> None:
    folder = tmp_path / "mission"
    folder.mkdir()
    _masks(tmp_path)
    _masks(folder)
    extra = "params: {zone: {type: str, default: ./keepout.yaml}}\n"
    error = _error(_mission(folder, f"filters: {filters}\n" + extra))
    assert (error.line, error.column) == where, str(error)
    assert message in str(error)


def test_run_world_replaces_the_missions_world(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    mission = tmp_path / "cafe_trip.yaml"
    mission.write_text(
        "mission: cafe_trip\nworld: cafe\nrobot: turtlebot3\nstart: {x: 1.0, y: 1.5}\n"
        "tree: {navigate_to_pose: {goal: {x: 3.0, y: 1.5}}}\ntimeout: 60\n"
        "expect: {result: SUCCEEDED, no_contact: true}\n"
    )
    (tmp_path / "maps").mkdir()
    room = write_map(tmp_path / "maps", room_pixels(*ROOM), name="room")
    out = tmp_path / "run"
    code = main(["run", str(mission), "--world", str(room), "--out", str(out), "--json"])
    result = json.loads(capsys.readouterr().out)
    assert code == 0, result
    assert result["world"] == "room.yaml"  # the file name, as for any world file
    assert result["metrics"]["contacts"] == 0


def test_run_world_is_for_mobile_robots(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    room = write_map(tmp_path, room_pixels(*ROOM), name="room")
    assert main(["run", "panda_pick", "--world", str(room), "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err == [
        "baobab run: --world: robot 'panda' stands in its own scene (panda_table); "
        "--world is for mobile robots"
    ]
    assert not (tmp_path / "r").exists()


def test_nav2_on_a_map_starts_at_its_origin_or_needs_start(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    room = write_map(tmp_path, room_pixels(*ROOM), name="room")  # the origin is in a wall
    script = tmp_path / "never_runs.py"
    script.write_text("print('ran')\n", encoding="utf-8")
    assert main(["nav2", str(script), "--world", str(room)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "has no spawn and the map origin (0, 0) is not free" in err[0]
    assert main(["nav2", str(script), "--world", str(room), "--start", "1,1"]) == 0
    assert capsys.readouterr().out == "ran\n"


def test_teleop_on_a_map_checks_its_start_before_the_terminal(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    room = write_map(tmp_path, room_pixels(*ROOM), name="room")
    assert main(["teleop", "--world", str(room), "--start", "0.02,1"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and "--start (0.020, 1.000) is not free in world 'room'" in err[0]
    assert main(["teleop", "--world", str(room)]) == 2
    assert "the map origin (0, 0) is not free" in capsys.readouterr().err


def test_a_broken_map_is_one_located_line_for_every_command(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    room = write_map(tmp_path, room_pixels(*ROOM), name="room")
    broken = tmp_path / "broken.yaml"
    broken.write_text(room.read_text().replace("resolution: 0.05", "resolution: -0.05"))
    mission = _mission(tmp_path).read_text().replace("./room.yaml", "./broken.yaml")
    (tmp_path / "across.yaml").write_text(mission)
    script = tmp_path / "never_runs.py"
    script.write_text("print('ran')\n", encoding="utf-8")
    out = tmp_path / "run"
    commands = [
        ["validate", str(tmp_path / "across.yaml")],
        ["run", str(tmp_path / "across.yaml"), "--out", str(out)],
        ["run", "walls_go_to_goal", "--world", str(broken), "--out", str(out)],
        ["nav2", str(script), "--world", str(broken)],
        ["teleop", "--world", str(broken)],
    ]
    for command in commands:
        assert main(command) == 2, command
        captured = capsys.readouterr()
        err = captured.err.splitlines()
        assert len(err) == 1 and err[0].endswith(
            "broken.yaml:2:1: resolution: Input should be greater than 0"
        ), err
        assert "ran" not in captured.out
        assert not out.exists()
