"""A broken map or filter mask is one located line: the file, line and column at fault."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from map_files import room_pixels, write_map

from baobab.sim.errors import WorldError
from baobab.sim.world import load_world

GOOD = {
    "image": "map.pgm",
    "resolution": "0.05",
    "origin": "[0.0, 0.0, 0.0]",
    "negate": "0",
    "occupied_thresh": "0.65",
    "free_thresh": "0.196",
}


def _map_yaml(folder: Path, **changes: str | None) -> Path:
    """map.yaml beside a valid map.pgm, with keys replaced (None drops a key)."""
    write_map(folder, room_pixels(20, 20))
    keys = {**GOOD, **changes}
    text = "".join(f"{key}: {value}\n" for key, value in keys.items() if value is not None)
    path = folder / "map.yaml"
    path.write_text(text)
    return path


def _line_of(path: Path, key: str) -> int:
    lines = path.read_text().splitlines()
    return next(i for i, line in enumerate(lines, 1) if line.startswith(f"{key}:"))


CASES: dict[str, tuple[dict[str, str | None], str, str]] = {
    "missing image": ({"image": "gone.pgm"}, "image", "image 'gone.pgm': no such file"),
    "image is a folder": ({"image": "sub"}, "image", "is a directory"),
    "text as image": ({"image": "notes.pgm"}, "image", "not an image of a format a map may use"),
    "truncated image": ({"image": "cut.pgm"}, "image", "a broken or truncated image"),
    "zero resolution": ({"resolution": "0"}, "resolution", "greater than 0"),
    "negative resolution": ({"resolution": "-0.05"}, "resolution", "greater than 0"),
    "resolution not a number": ({"resolution": "fine"}, "resolution", "valid number"),
    "free above occupied": (
        {"free_thresh": "0.7"},
        "free_thresh",
        "must be below occupied_thresh 0.65",
    ),
    "threshold above one": ({"occupied_thresh": "1.5"}, "occupied_thresh", "less than or equal"),
    "negative threshold": ({"free_thresh": "-0.1"}, "free_thresh", "greater than or equal"),
    "unknown mode": ({"mode": "binary"}, "mode", "'trinary', 'scale' or 'raw'"),
    "origin of two": ({"origin": "[1.0, 2.0]"}, "origin", "expected [x, y, yaw]"),
    "origin not a list": ({"origin": "here"}, "origin", "expected [x, y, yaw]"),
    "rotated origin": ({"origin": "[0.0, 0.0, 0.3]"}, "origin", "does not rotate maps"),
    "image above the folder": ({"image": "../map.pgm"}, "image", "outside the map's folder"),
    "image by absolute path": ({"image": "/etc/hostname"}, "image", "outside the map's folder"),
    "negate of two": ({"negate": "2"}, "negate", "expected 0, 1, true or false"),
    "negate missing": ({"negate": None}, "", "missing required key 'negate'"),
    "huge image": ({"image": "huge.pgm"}, "image", "the limit is 10,000,000 cells"),
}


def _extra_files(folder: Path) -> None:
    (folder / "sub").mkdir()
    (folder / "notes.pgm").write_text("these are not pixels\n")
    (folder / "cut.pgm").write_bytes(b"P5\n20 20\n255\n" + bytes(50))
    (folder / "huge.pgm").write_bytes(b"P5\n4000 3000\n255\n")  # the header alone
    (folder.parent / "map.pgm").write_bytes((folder / "map.pgm").read_bytes())


@pytest.mark.parametrize("case", sorted(CASES))
def test_each_bad_map_is_one_located_line(tmp_path: Path, case: str) -> None:
    changes, key, fragment = CASES[case]
    folder = tmp_path / "maps"
    folder.mkdir()
    path = _map_yaml(folder, **changes)
    _extra_files(folder)
    with pytest.raises(WorldError) as caught:
        load_world(path)
    error = caught.value
    assert error.path == str(path)
    assert error.line == (_line_of(path, key) if key else 1), str(error)
    assert fragment in error.message, str(error)
    assert "\n" not in str(error)


def _world(folder: Path, text: str) -> Path:
    write_map(folder, room_pixels(40, 40), name="office")
    path = folder / "world.yaml"
    path.write_text(text)
    return path


WORLD_CASES: dict[str, tuple[Callable[[Path], None], str, int, str]] = {
    "map missing": (lambda _: None, "name: w\nmap: ./nothing.yaml\n", 2, "does not exist"),
    "map outside the folder": (
        lambda folder: write_map(folder.parent, room_pixels(10, 10), name="far"),
        "name: w\nmap: ../far.yaml\n",
        2,
        "outside the world's folder",
    ),
    "floor beside a map": (
        lambda _: None,
        "name: w\nmap: ./office.yaml\nfloor: {size: [2, 2]}\n",
        3,
        "takes its floor from the map",
    ),
    "spawn off the map": (
        lambda _: None,
        "name: w\nmap: ./office.yaml\nspawns: {default: {x: 9.0, y: 0.5}}\n",
        3,
        "outside the floor",
    ),
    "box named like a map wall": (
        lambda _: None,
        "name: w\nmap: ./office.yaml\nboxes: [{name: map_3, center: [1, 1], size: [1, 1]}]\n",
        3,
        "is reserved",
    ),
    "mask beside the map": (
        lambda folder: write_map(
            folder, np.zeros((4, 4), dtype=np.uint8), name="far", origin=(50.0, 0.0, 0.0)
        ),
        "name: w\nmap: ./office.yaml\nfilters:\n  keepout: ./far.yaml\n",
        4,
        "none of the map",
    ),
    "keepout with a multiplier": (
        lambda folder: write_map(folder, np.zeros((4, 4), dtype=np.uint8), name="zone"),
        "name: w\nmap: ./office.yaml\nfilters:\n  keepout: {mask: ./zone.yaml, multiplier: 2}\n",
        4,
        "does not use base and multiplier",
    ),
    "speed filter of type 0": (
        lambda folder: write_map(folder, np.zeros((4, 4), dtype=np.uint8), name="zone"),
        "name: w\nmap: ./office.yaml\nfilters:\n  speed: {mask: ./zone.yaml, type: 0}\n",
        4,
        "1 or 2",
    ),
    "a world with neither floor nor map": (
        lambda _: None,
        "name: w\nspawns: {default: {x: 0, y: 0}}\n",
        1,
        "missing required key 'floor' (or a 'map')",
    ),
}


@pytest.mark.parametrize("case", sorted(WORLD_CASES))
def test_each_bad_world_on_a_map_is_one_located_line(tmp_path: Path, case: str) -> None:
    prepare, text, line, fragment = WORLD_CASES[case]
    folder = tmp_path / "world"
    folder.mkdir()
    path = _world(folder, text)
    prepare(folder)
    with pytest.raises(WorldError) as caught:
        load_world(path)
    error = caught.value
    assert (error.path, error.line) == (str(path), line), str(error)
    assert fragment in error.message, str(error)


def test_an_error_inside_a_mask_points_into_the_mask(tmp_path: Path) -> None:
    folder = tmp_path / "world"
    folder.mkdir()
    mask = write_map(folder, np.zeros((4, 4), dtype=np.uint8), name="zone")
    mask.write_text(mask.read_text().replace("free_thresh: 0.196", "free_thresh: 0.9"))
    path = _world(folder, "name: w\nmap: ./office.yaml\nfilters:\n  keepout: ./zone.yaml\n")
    with pytest.raises(WorldError) as caught:
        load_world(path)
    assert caught.value.path == str(mask)
    assert "must be below occupied_thresh" in caught.value.message
