"""Writing map_server maps for tests: an image (PGM P2/P5, PNG, BMP) beside its YAML."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

FREE_PIXEL = 254
OCCUPIED_PIXEL = 0
UNKNOWN_PIXEL = 205


def write_image(path: Path, pixels: np.ndarray, fmt: str = "P5") -> None:
    """``pixels`` (rows top first; grey, or RGB/RGBA channels) as ``fmt``: P2, P5, PNG, BMP."""
    pixels = np.asarray(pixels, dtype=np.uint8)
    if fmt == "P2":
        height, width = pixels.shape
        body = "\n".join(" ".join(str(v) for v in row) for row in pixels)
        path.write_text(f"P2\n# written by a test\n{width} {height}\n255\n{body}\n")
    elif fmt == "P5":
        Image.fromarray(pixels).save(path, format="PPM")
    else:
        Image.fromarray(pixels).save(path, format=fmt)


def write_map(
    folder: Path,
    pixels: np.ndarray,
    *,
    name: str = "map",
    fmt: str = "P5",
    resolution: float = 0.05,
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0),
    negate: int = 0,
    occupied_thresh: float = 0.65,
    free_thresh: float = 0.196,
    mode: str | None = None,
    extra: str = "",
) -> Path:
    """Write ``name``.yaml and its image into ``folder``; returns the YAML's path."""
    suffix = {"P2": "pgm", "P5": "pgm", "PNG": "png", "BMP": "bmp"}[fmt]
    image = folder / f"{name}.{suffix}"
    write_image(image, pixels, fmt)
    lines = [
        f"image: {image.name}",
        f"resolution: {resolution}",
        f"origin: [{origin[0]}, {origin[1]}, {origin[2]}]",
        f"negate: {negate}",
        f"occupied_thresh: {occupied_thresh}",
        f"free_thresh: {free_thresh}",
    ]
    if mode is not None:
        lines.append(f"mode: {mode}")
    path = folder / f"{name}.yaml"
    path.write_text("\n".join(lines) + "\n" + extra)
    return path


def room_pixels(width: int, height: int, *, wall: int = 2) -> np.ndarray:
    """A free room ``width`` x ``height`` cells with walls ``wall`` cells thick all round."""
    pixels = np.full((height, width), FREE_PIXEL, dtype=np.uint8)
    pixels[:wall, :] = pixels[-wall:, :] = OCCUPIED_PIXEL
    pixels[:, :wall] = pixels[:, -wall:] = OCCUPIED_PIXEL
    return pixels


def maze_pixels(seed: int, cells: int = 5, cell_px: int = 20, wall: int = 2) -> np.ndarray:
    """A perfect maze of ``cells`` x ``cells`` rooms (``cell_px`` pixels each), seeded."""
    rng = np.random.default_rng(seed)
    size = cells * cell_px + wall
    pixels = np.full((size, size), OCCUPIED_PIXEL, dtype=np.uint8)
    seen = np.zeros((cells, cells), dtype=bool)
    stack = [(0, 0)]
    seen[0, 0] = True

    def open_room(r: int, c: int) -> None:
        pixels[r * cell_px + wall : (r + 1) * cell_px, c * cell_px + wall : (c + 1) * cell_px] = (
            FREE_PIXEL
        )

    open_room(0, 0)
    while stack:
        r, c = stack[-1]
        options = [
            (r + dr, c + dc)
            for dr, dc in ((1, 0), (-1, 0), (0, 1), (0, -1))
            if 0 <= r + dr < cells and 0 <= c + dc < cells and not seen[r + dr, c + dc]
        ]
        if not options:
            stack.pop()
            continue
        nr, nc = options[int(rng.integers(len(options)))]
        seen[nr, nc] = True
        open_room(nr, nc)
        # knock down the wall between (r, c) and (nr, nc)
        top = min(r, nr) * cell_px + wall
        left = min(c, nc) * cell_px + wall
        bottom = (max(r, nr) + 1) * cell_px
        right = (max(c, nc) + 1) * cell_px
        pixels[top:bottom, left:right] = FREE_PIXEL
        stack.append((nr, nc))
    return pixels


def image_cells(
    rect: tuple[float, float, float, float], height: int, resolution: float = 0.05
) -> tuple[slice, slice]:
    """Image rows and columns of the map rectangle ``(x0, y0, x1, y1)`` (m) of a map ``height``
    pixels high whose origin is (0, 0): row 0 is the image's top."""
    x0, y0, x1, y1 = (round(v / resolution) for v in rect)
    return slice(height - y1, height - y0), slice(x0, x1)
