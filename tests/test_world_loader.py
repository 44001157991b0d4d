"""World files that are wrong: every error is one line naming file, line, column and field."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from baobab.sim.errors import BaobabError, WorldError
from baobab.sim.world import bundled_world_names, load_world

# Line numbers matter: the cases below point into this text.
GOOD = """\
name: tiny
floor:
  size: [4.0, 3.0]
boxes:
  - {name: wall, center: [1.0, 0.0], size: [0.2, 2.0], yaw_deg: 90}
cylinders:
  - name: table
    center: [-1.0, 0.5]
    radius: 0.3
spawns:
  default: {x: 0.0, y: 0.0}
locations:
  door: {x: 1.5, y: -1.0, yaw_deg: 90}
"""


def _write(tmp_path: Path, text: str | bytes) -> Path:
    path = tmp_path / "world.yaml"
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")
    return path


def _edit(old: str, new: str) -> str:
    assert GOOD.count(old) == 1, old
    return GOOD.replace(old, new)


def test_the_good_file_loads_with_degrees_turned_into_radians(tmp_path: Path) -> None:
    world = load_world(_write(tmp_path, GOOD))
    assert world.name == "tiny"
    assert world.bounds == (-2.0, -1.5, 2.0, 1.5)
    assert world.boxes[0].yaw == pytest.approx(math.pi / 2)
    assert world.locations["door"].yaw == pytest.approx(math.pi / 2)
    assert world.spawn.yaw == 0.0
    assert world.cylinders[0].radius == 0.3


@pytest.mark.parametrize(
    ("text", "where", "fragment"),
    [
        pytest.param(
            _edit("size: [4.0, 3.0]", "size: [4.0, -3.0]"),
            "3:15",
            "floor.size.1: Input should be greater than 0",
            id="negative-size",
        ),
        pytest.param(
            _edit("    radius: 0.3\n", "    radius: 0.3\n    colr: [1, 0, 0, 1]\n"),
            "10:5",
            "unknown key 'colr' in cylinders.0",
            id="unknown-key",
        ),
        pytest.param(
            _edit("  default: {x", "  start: {x"),
            "10:1",
            "spawns: needs a 'default' entry",
            id="missing-default-spawn",
        ),
        pytest.param(
            _edit("y: -1.0, yaw_deg: 90}", "y: -1.0, yaw: 1.0, yaw_deg: 90}"),
            "13:37",
            "locations.door.yaw_deg: give either yaw (radians) or yaw_deg (degrees), not both",
            id="pose-yaw-and-yaw_deg",
        ),
        pytest.param(
            _edit("yaw_deg: 90}\ncylinders", "yaw_deg: 90, yaw: 0.5}\ncylinders"),
            "5:56",
            "boxes.0.yaw_deg: give either yaw (radians) or yaw_deg (degrees), not both",
            id="box-yaw-and-yaw_deg",
        ),
        pytest.param(
            _edit("door: {x: 1.5", "door: {x: 2.5"),
            "13:3",
            "locations.door: 'door' at (2.5, -1.0) is outside the floor x -2..2, y -1.5..1.5",
            id="location-outside-floor",
        ),
        pytest.param(
            _edit("  default: {x: 0.0, y: 0.0}", "  default: {x: 0.0, y: 1.6}"),
            "11:3",
            "spawns.default: 'default' at (0.0, 1.6) is outside the floor",
            id="spawn-outside-floor",
        ),
        pytest.param(
            _edit("  - name: table", "  - name: wall"),
            "7:5",
            "cylinders.0.name: obstacle name 'wall' is used twice",
            id="duplicate-obstacle-name",
        ),
        pytest.param(
            _edit("    radius: 0.3\n", "    radius: 0.3\n    radius: 0.4\n"),
            "10:5",
            "duplicate key 'radius' (first defined at line 9)",
            id="duplicate-yaml-key",
        ),
        pytest.param(
            _edit("radius: 0.3", "radius: .nan"),
            "9:13",
            "non-finite number '.nan'",
            id="nan-value",
        ),
        pytest.param(
            _edit("center: [-1.0, 0.5]", "center: [-1.0, .inf]"),
            "8:20",
            "non-finite number '.inf'",
            id="infinite-value",
        ),
        pytest.param(
            _edit("  door: {x: 1.5, y: -1.0", "  door: {x: 1.5, y: [-1.0"),
            "13:39",
            "YAML syntax error: expected ',' or ']', but got '}'",
            id="yaml-syntax-error",
        ),
        pytest.param(
            _edit("    radius: 0.3\n", ""),
            "7:5",
            "missing required key 'radius'",
            id="missing-field",
        ),
        pytest.param(
            _edit("boxes:\n  - {name: wall", "boxes:\n  - {name: wall, colour: [1, 0, 0, 2]"),
            "5:36",
            "boxes.0.colour.3: Input should be less than or equal to 1",
            id="colour-out-of-range",
        ),
        pytest.param(
            "- just\n- a list\n", "1:1", "a world file must be a mapping", id="not-a-mapping"
        ),
        pytest.param("", "1:1", "the file is empty", id="empty-file"),
        pytest.param("# only a comment\n", "1:1", "the file is empty", id="only-comments"),
        pytest.param(b"name: caf\xe9\n", "1:10", "not valid UTF-8 text", id="non-utf8"),
        pytest.param(b"name: a\x00b\n", "1:1", "binary data", id="nul-byte"),
    ],
)
def test_mistakes_are_located(tmp_path: Path, text: str | bytes, where: str, fragment: str) -> None:
    path = _write(tmp_path, text)
    with pytest.raises(WorldError) as caught:
        load_world(path)
    message = str(caught.value)
    assert message.startswith(f"{path}:{where}: "), message
    assert fragment in message, message
    assert "\n" not in message
    line, column = (int(part) for part in where.split(":"))
    assert (caught.value.path, caught.value.line, caught.value.column) == (str(path), line, column)


def test_missing_file_is_located_at_its_start(tmp_path: Path) -> None:
    path = tmp_path / "nowhere.yaml"
    with pytest.raises(WorldError, match=r"nowhere\.yaml:1:1: no such file$"):
        load_world(path)


def test_directory_is_refused(tmp_path: Path) -> None:
    folder = tmp_path / "worlds.yaml"
    folder.mkdir()
    with pytest.raises(
        WorldError, match=r"worlds\.yaml:1:1: is a directory; expected a YAML file$"
    ):
        load_world(folder)


def test_unknown_bundled_name_lists_the_known_worlds() -> None:
    known = bundled_world_names()
    assert {"cafe", "farm", "town"} <= set(known)
    with pytest.raises(WorldError) as caught:
        load_world("moon")
    assert (
        str(caught.value) == f"moon:1:1: unknown world 'moon'; bundled worlds: {', '.join(known)}"
    )


def test_world_errors_are_baobab_errors(tmp_path: Path) -> None:
    with pytest.raises(BaobabError):
        load_world(_write(tmp_path, ""))


def test_a_path_given_as_text_is_read_as_a_file(tmp_path: Path) -> None:
    path = _write(tmp_path, GOOD)
    assert load_world(str(path)).name == "tiny"
