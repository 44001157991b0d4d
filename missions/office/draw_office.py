"""Draw the office map of the bundled mission ``office_patrol``, as a user draws their own.

    python missions/office/draw_office.py [FOLDER]     # default: this script's folder

Writes three Nav2 map_server maps (a PGM image and its YAML each), 0.05 m a cell:

- ``office.yaml`` / ``office.pgm``: a 16 m x 10 m office. Four rooms north of an east-west
  corridor (a 1 m door each), an open-plan area south of it (two openings to the corridor,
  desks, a kitchen counter), unexplored space (unknown) round the outer walls;
- ``keepout.yaml`` / ``keepout.pgm``: a keepout mask (trinary: black is the zone) over a
  construction area in the middle of the open plan, which the way from the kitchen to the
  printer would cross;
- ``speed.yaml`` / ``speed.pgm``: a speed mask (scale mode: a pixel's darkness is the
  percentage the speed filter takes off, nav2_bringup's convention) slowing the robot to 50 %
  in the corridor in front of the two middle rooms.

Pixels follow map_server's reading: 254 free, 0 occupied, 205 unknown; row 0 is the top of the
map (largest y). Coordinates below are map-frame metres, origin at the lower-left corner.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

RESOLUTION = 0.05
"""Cell side (m)."""
SIZE = (16.0, 10.0)
"""Width and height of the map (m)."""
FREE, OCCUPIED, UNKNOWN = 254, 0, 205
"""map_server's trinary pixels (negate 0, thresholds 0.65 and 0.196)."""
SLOW_PERCENT = 50
"""The speed limit in the slow zone, percent of the controller's top speed."""

Rect = tuple[float, float, float, float]
"""``(x0, y0, x1, y1)`` in metres."""

BUILDING: Rect = (0.5, 0.5, 15.5, 9.5)
WALL = 0.15
CORRIDOR: Rect = (0.65, 5.0, 15.35, 6.5)
ROOM_WALLS_X = (4.25, 8.0, 11.75)
"""Walls between the four north rooms (their west faces, m)."""
DOORS_X = (2.45, 6.1, 9.9, 13.55)
"""Centres of the rooms' doors onto the corridor (m)."""
DOOR_WIDTH = 1.0
OPENINGS_X = ((4.5, 6.0), (11.0, 12.5))
"""Openings between the corridor and the open plan (m)."""
FURNITURE: tuple[Rect, ...] = (
    (2.0, 1.6, 3.6, 2.4),  # desks
    (6.0, 1.6, 7.6, 2.4),
    (12.4, 1.6, 14.0, 2.4),
    (14.6, 3.0, 15.35, 4.5),  # the kitchen counter
    (0.65, 0.65, 1.2, 1.4),  # a cabinet in the south-west corner
)
KEEPOUT_ZONE: Rect = (8.6, 0.65, 11.0, 3.8)
SLOW_ZONE: Rect = (4.25, 5.0, 11.75, 6.5)

MAP_YAML = """image: {image}
resolution: {resolution}
origin: [0.0, 0.0, 0.0]
negate: 0
occupied_thresh: {occupied}
free_thresh: {free}
{mode}"""


def _blank(value: int) -> np.ndarray:
    width, height = (round(side / RESOLUTION) for side in SIZE)
    return np.full((height, width), value, dtype=np.uint8)


def _fill(pixels: np.ndarray, rect: Rect, value: int) -> None:
    """Set the pixels of ``rect`` (m) to ``value``."""
    height = pixels.shape[0]
    x0, y0, x1, y1 = (round(v / RESOLUTION) for v in rect)
    pixels[height - y1 : height - y0, x0:x1] = value


def office_pixels() -> np.ndarray:
    """The office plan as map_server pixels (rows top first)."""
    pixels = _blank(UNKNOWN)
    x0, y0, x1, y1 = BUILDING
    _fill(pixels, BUILDING, OCCUPIED)
    _fill(pixels, (x0 + WALL, y0 + WALL, x1 - WALL, y1 - WALL), FREE)
    corridor_x0, south, corridor_x1, north = CORRIDOR
    _fill(pixels, (corridor_x0, north, corridor_x1, north + WALL), OCCUPIED)  # rooms' wall
    _fill(pixels, (corridor_x0, south - WALL, corridor_x1, south), OCCUPIED)  # open plan's
    for x in ROOM_WALLS_X:
        _fill(pixels, (x, north, x + WALL, y1 - WALL), OCCUPIED)
    for x in DOORS_X:
        _fill(pixels, (x - DOOR_WIDTH / 2, north, x + DOOR_WIDTH / 2, north + WALL), FREE)
    for left, right in OPENINGS_X:
        _fill(pixels, (left, south - WALL, right, south), FREE)
    for rect in FURNITURE:
        _fill(pixels, rect, OCCUPIED)
    return pixels


def keepout_pixels() -> np.ndarray:
    """The keepout mask: the zone black (occupied), the rest white (free)."""
    pixels = _blank(FREE)
    _fill(pixels, KEEPOUT_ZONE, OCCUPIED)
    return pixels


def speed_pixels() -> np.ndarray:
    """The speed mask (scale mode, thresholds 0 and 1): darkness = percent taken off."""
    pixels = _blank(255)
    _fill(pixels, SLOW_ZONE, round(255 * SLOW_PERCENT / 100))
    return pixels


def write_pgm(path: Path, pixels: np.ndarray) -> None:
    """``pixels`` as a binary PGM (P5), the format map_server saves."""
    height, width = pixels.shape
    path.write_bytes(f"P5\n{width} {height}\n255\n".encode() + pixels.tobytes())


def write_map(folder: Path, name: str, pixels: np.ndarray, *, scale: bool = False) -> None:
    """``name``.pgm and its map_server YAML in ``folder``."""
    write_pgm(folder / f"{name}.pgm", pixels)
    text = MAP_YAML.format(
        image=f"{name}.pgm",
        resolution=RESOLUTION,
        occupied=1.0 if scale else 0.65,
        free=0.0 if scale else 0.196,
        mode="mode: scale\n" if scale else "",
    )
    (folder / f"{name}.yaml").write_text(text)


def main(folder: Path) -> None:
    """Write the map and its two masks into ``folder``."""
    write_map(folder, "office", office_pixels())
    write_map(folder, "keepout", keepout_pixels())
    write_map(folder, "speed", speed_pixels(), scale=True)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent)
