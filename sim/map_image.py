"""A map_server map image -> occupancy values, the way Nav2's ``map_server`` reads it.

Nav2's ``map_io`` turns each pixel into an ``OccupancyGrid`` value (-1 unknown, 0 free, 100
occupied, and 1..99 in scale mode; reference/nav2_ros_facts.md §1, Rolling semantics):

- the pixel's shade ``g`` (0..255) is its grey level; a colour pixel's is the mean of its red,
  green and blue (map_server's ``averaged`` shade);
- trinary and scale: ``p = g / 255`` when ``negate``, else ``1 - g / 255``; ``p >= occupied``
  -> 100, ``p <= free`` -> 0, else -1 (trinary) or ``round(100 (p - free) / (occupied -
  free))`` (scale); a pixel whose alpha is below 255 -> -1 in both modes;
- raw: ``g`` itself when 0 <= g <= 100, else -1; ``negate`` and the thresholds are ignored.

Image row 0 is the top of the picture; grid row 0 is the bottom (cell (0, 0) is the lower-left
pixel), so the rows are flipped. Images are read with Pillow from bytes already read through
the bounded reader; PGM (P2 and P5), PNG and BMP are accepted.
"""

from __future__ import annotations

import io
import warnings
from typing import TYPE_CHECKING, Literal

import numpy as np

if TYPE_CHECKING:
    from PIL.Image import Image

MapMode = Literal["trinary", "scale", "raw"]

UNKNOWN = -1
FREE = 0
OCCUPIED = 100

IMAGE_FORMATS = {"PPM": "PGM/PPM", "PNG": "PNG", "BMP": "BMP"}
"""Pillow's format names of the images a map may use, and what users call them."""

MAX_IMAGE_BYTES = 64_000_000
"""The largest map image file read (bytes): an ASCII PGM (P2) of the largest map allowed."""


class MapImageError(ValueError):
    """An image that cannot be a map; the message says why (the caller locates it)."""


def decode_map_image(raw: bytes, max_pixels: int) -> np.ndarray:
    """The image in ``raw`` as an array: (rows, cols) grey, or (rows, cols, channels) colour.

    Channels are grey+alpha (2), RGB (3) or RGBA (4), 8 bits each; 16-bit grey images are
    scaled to 8 bits. The pixel count is checked against ``max_pixels`` before decoding.

    Raises:
        MapImageError: not an image of :data:`IMAGE_FORMATS`, a broken one, or too big.
    """
    from PIL import Image, UnidentifiedImageError  # Pillow: only when a map is read

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            image = Image.open(io.BytesIO(raw), formats=list(IMAGE_FORMATS))
            width, height = image.size
            if width * height > max_pixels:
                raise MapImageError(
                    f"the image is {width} x {height} pixels ({width * height:,} cells); "
                    f"the limit is {max_pixels:,} cells (MAX_MAP_CELLS)"
                )
            image.load()
    except MapImageError:
        raise
    except UnidentifiedImageError:
        raise MapImageError(
            f"not an image of a format a map may use ({', '.join(IMAGE_FORMATS.values())})"
        ) from None
    except (OSError, ValueError, SyntaxError, Image.DecompressionBombError) as exc:
        raise MapImageError(f"a broken or truncated image ({exc})") from None
    if width == 0 or height == 0:
        raise MapImageError("the image has no pixels")
    return _pixels(image)


def _pixels(image: Image) -> np.ndarray:
    """8-bit grey, grey+alpha, RGB or RGBA pixels of a loaded Pillow image."""
    mode = image.mode
    if mode in ("I", "I;16", "I;16B", "I;16L", "I;16N"):
        wide = np.asarray(image, dtype=np.float64)
        return np.clip(np.floor(wide * 255.0 / 65535.0 + 0.5), 0, 255).astype(np.uint8)
    if mode == "P":
        image = image.convert("RGBA" if "transparency" in image.info else "RGB")
    elif mode == "PA":
        image = image.convert("RGBA")
    elif mode not in ("L", "LA", "RGB", "RGBA"):
        image = image.convert("RGBA" if "A" in mode else "L")
    return np.asarray(image, dtype=np.uint8)


def occupancy_values(
    pixels: np.ndarray,
    mode: MapMode,
    *,
    negate: bool,
    free_thresh: float,
    occupied_thresh: float,
) -> np.ndarray:
    """Occupancy values (``int8``, -1..100) of decoded ``pixels``; row 0 is the map's bottom.

    Args:
        pixels: from :func:`decode_map_image`.
        mode: ``trinary``, ``scale`` or ``raw``.
        negate: white is occupied (trinary and scale).
        free_thresh: occupancy probability at or below which a cell is free.
        occupied_thresh: occupancy probability at or above which a cell is occupied.
    """
    alpha = None
    if pixels.ndim == 2:
        shade = pixels.astype(np.float64)
    else:
        channels = pixels.shape[2]
        colour = pixels[..., :3] if channels >= 3 else pixels[..., :1]
        shade = colour.astype(np.float64).mean(axis=2)
        if channels in (2, 4):
            alpha = pixels[..., -1]
    if mode == "raw":
        level = np.floor(shade + 0.5)
        values = np.where(level <= OCCUPIED, level, UNKNOWN)
    else:
        x = shade / 255.0
        p = x if negate else 1.0 - x
        if mode == "trinary":
            between = np.full(p.shape, float(UNKNOWN))
        else:
            between = np.floor(100.0 * (p - free_thresh) / (occupied_thresh - free_thresh) + 0.5)
        values = np.where(p >= occupied_thresh, OCCUPIED, np.where(p <= free_thresh, FREE, between))
        if alpha is not None:
            values = np.where(alpha < 255, UNKNOWN, values)
    return np.ascontiguousarray(values[::-1].astype(np.int8))
