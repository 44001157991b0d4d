"""Nav2 map_server maps: the map YAML, its image, and the occupancy grid they make.

A map_server map is a YAML file naming an image and how to read it (Nav2's ``map_io``;
reference/nav2_ros_facts.md §1)::

    image: office.pgm          # required; relative to the YAML's folder
    resolution: 0.05           # required, m per cell
    origin: [-10.0, -5.0, 0.0] # required: x, y (m) of the lower-left cell's corner, yaw (rad)
    negate: 0                  # required: 0/1 or false/true
    occupied_thresh: 0.65      # required
    free_thresh: 0.196         # required
    mode: trinary              # optional: trinary (default), scale, raw

:func:`load_occupancy_map` reads both files through the bounded reader and returns an
:class:`OccupancyMap`, or raises a located :class:`~baobab.sim.errors.WorldError` for every
problem (at the YAML key at fault; image problems at ``image``). baobab's own limits: the
image stays inside the YAML's folder, the map has at most :data:`MAX_MAP_CELLS` cells and
:data:`MAX_MAP_SIDE` metres a side, and the origin's yaw is 0 (Nav2's costmap does not rotate
maps: its static layer uses only the origin's position).
"""

from __future__ import annotations

import hashlib
import math
import os
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Annotated, Any

import numpy as np
from pydantic import ConfigDict, Field, ValidationError, field_validator, model_validator

from baobab.sim.errors import SourceError, WorldError, clip
from baobab.sim.input_files import read_input_file
from baobab.sim.map_image import (
    MAX_IMAGE_BYTES,
    OCCUPIED,
    UNKNOWN,
    MapImageError,
    MapMode,
    decode_map_image,
    occupancy_values,
)
from baobab.sim.yaml_models import YamlModel
from baobab.sim.yaml_source import (
    FieldValueError,
    LocatedDocument,
    describe_validation_error,
    load_located_yaml,
    read_yaml_text,
)

MAX_MAP_CELLS = 10_000_000
"""Most cells in a map (and in each filter mask): the global costmap's limit
(:data:`baobab.sim.world.MAX_COSTMAP_CELLS`), since the costmap takes the map's cells."""
MAX_MAP_SIDE = 1_000.0
"""Longest side of a map (m): the floor's limit (:data:`baobab.sim.world.MAX_FLOOR_SIDE`)."""
MAX_MAP_COORDINATE = 10_000.0
"""Largest distance (m) of the map's origin from the map frame's origin along x or y."""

Finite = Annotated[float, Field(allow_inf_nan=False)]
Threshold = Annotated[float, Field(ge=0, le=1, allow_inf_nan=False)]


class MapYaml(YamlModel):
    """The keys of a map_server map YAML (extra keys are refused, as typos)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    image: str = Field(min_length=1)
    resolution: Annotated[float, Field(gt=0, allow_inf_nan=False)]
    origin: tuple[Finite, Finite, Finite]
    negate: Any
    """0/1 or false/true (map_server reads an int, falling back to a bool); a bool once read."""
    occupied_thresh: Threshold
    free_thresh: Threshold
    mode: MapMode = "trinary"

    @field_validator("negate")
    @classmethod
    def _zero_or_one(cls, value: Any) -> bool:
        if isinstance(value, bool):
            return value
        if type(value) is not int or value not in (0, 1):
            raise ValueError(f"expected 0, 1, true or false, got {clip(value)}")
        return bool(value)

    @field_validator("origin", mode="before")
    @classmethod
    def _three_numbers(cls, value: Any) -> Any:
        if not isinstance(value, list | tuple) or len(value) != 3:
            raise ValueError(f"expected [x, y, yaw] (m, m, rad), got {clip(value)}")
        return value

    @model_validator(mode="after")
    def _check(self) -> MapYaml:
        if not self.free_thresh < self.occupied_thresh:
            raise FieldValueError(
                ("free_thresh",),
                f"free_thresh {self.free_thresh:g} must be below occupied_thresh "
                f"{self.occupied_thresh:g} (0 <= free < occupied <= 1)",
            )
        if self.origin[2] != 0.0:
            raise FieldValueError(
                ("origin", 2),
                f"the origin's yaw is {self.origin[2]:g} rad; Nav2's costmap does not rotate "
                "maps (its static layer reads only the origin's x and y): rotate the image "
                "and give yaw 0",
            )
        x, y = self.origin[0], self.origin[1]
        if max(abs(x), abs(y)) > MAX_MAP_COORDINATE:
            raise FieldValueError(
                ("origin",),
                f"the origin ({x:g}, {y:g}) is more than {MAX_MAP_COORDINATE:g} m from the map "
                "frame's origin (MAX_MAP_COORDINATE)",
            )
        return self


@dataclass(frozen=True, eq=False)
class OccupancyMap:
    """A map as map_server serves it: ``nav_msgs/OccupancyGrid`` values on a grid.

    Attributes:
        path: the map YAML, as the user named it.
        image_path: the image file, resolved.
        resolution: cell side (m).
        origin: map-frame position (m) of the lower-left corner of cell (0, 0).
        data: ``int8`` values, ``data[iy, ix]`` with row 0 at the bottom: -1 unknown, 0 free,
            100 occupied, 1..99 in between (scale and raw modes); read-only.
        settings: the YAML's keys as read.
    """

    path: str
    image_path: str
    resolution: float
    origin: tuple[float, float]
    data: np.ndarray
    settings: MapYaml

    @property
    def width(self) -> int:
        """Cells along x."""
        return int(self.data.shape[1])

    @property
    def height(self) -> int:
        """Cells along y."""
        return int(self.data.shape[0])

    @property
    def name(self) -> str:
        """The map YAML's file name without its extension (``office``)."""
        return Path(self.path).stem

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """Covered rectangle as (x_min, y_min, x_max, y_max) in metres."""
        x0, y0 = self.origin
        return (x0, y0, x0 + self.width * self.resolution, y0 + self.height * self.resolution)

    def cell(self, x: float, y: float) -> tuple[int, int] | None:
        """The cell ``(ix, iy)`` holding map-frame point ``(x, y)`` (m), or None off the map."""
        ix = math.floor((x - self.origin[0]) / self.resolution)
        iy = math.floor((y - self.origin[1]) / self.resolution)
        if 0 <= ix < self.width and 0 <= iy < self.height:
            return ix, iy
        return None

    def value_at(self, x: float, y: float) -> int | None:
        """The occupancy value under ``(x, y)`` (m), or None off the map."""
        cell = self.cell(x, y)
        return None if cell is None else int(self.data[cell[1], cell[0]])

    def solid(self, unknown_is_solid: bool) -> np.ndarray:
        """Cells a robot cannot enter: occupied (100), and unknown (-1) when so chosen."""
        key = bool(unknown_is_solid)
        cached = self._solid.get(key)
        if cached is None:
            cached = self.data == OCCUPIED
            if unknown_is_solid:
                cached |= self.data == UNKNOWN
            cached.setflags(write=False)
            self._solid[key] = cached
        return cached

    @cached_property
    def _solid(self) -> dict[bool, np.ndarray]:
        """:meth:`solid`'s arrays, by ``unknown_is_solid`` (``cached_property`` writes the
        instance's ``__dict__``, which a frozen dataclass allows)."""
        return {}


def load_occupancy_map(
    path: str | Path, error_type: type[SourceError] = WorldError, *, what: str = "map"
) -> OccupancyMap:
    """Load a map_server map YAML and its image.

    Args:
        path: the map YAML.
        error_type: the located error to raise.
        what: what the file is, for messages (``map``, ``keepout mask``).

    Raises:
        error_type: located at the YAML key at fault, or at ``image`` for the image.
    """
    text = read_yaml_text(path, error_type)
    document = load_located_yaml(path, error_type, text=text)
    if not isinstance(document.data, dict):
        raise document.error((), f"a {what} YAML must be a mapping of keys", error_type)
    try:
        settings = MapYaml.model_validate(document.data)
    except ValidationError as exc:
        raise describe_validation_error(document, exc, (), error_type) from None
    image = _image_path(Path(path), settings.image, document, error_type)
    raw = read_input_file(
        image,
        _at_image(document, error_type, settings.image),
        expected="an image file",
        limit=MAX_IMAGE_BYTES,
    )
    key = (
        str(Path(path).resolve()),
        hashlib.sha256(text.encode("utf-8", "surrogatepass") + raw).digest(),
    )
    cached = _LOADED.get(key)
    if cached is not None:
        return cached
    try:
        pixels = decode_map_image(raw, MAX_MAP_CELLS)
    except MapImageError as exc:
        raise document.error(
            ("image",), f"image '{clip(settings.image)}': {exc}", error_type
        ) from None
    values = occupancy_values(
        pixels,
        settings.mode,
        negate=bool(settings.negate),
        free_thresh=settings.free_thresh,
        occupied_thresh=settings.occupied_thresh,
    )
    values.setflags(write=False)
    height, width = values.shape
    side = max(width, height) * settings.resolution
    if side > MAX_MAP_SIDE:
        raise document.error(
            ("resolution",),
            f"the {what} is {width * settings.resolution:g} m x {height * settings.resolution:g}"
            f" m ({width} x {height} cells of {settings.resolution:g} m); the limit is "
            f"{MAX_MAP_SIDE:g} m a side (MAX_MAP_SIDE)",
            error_type,
        )
    loaded = OccupancyMap(
        path=str(path),
        image_path=str(image),
        resolution=settings.resolution,
        origin=(settings.origin[0], settings.origin[1]),
        data=values,
        settings=settings,
    )
    if len(_LOADED) >= _LOADED_MAX:
        _LOADED.pop(next(iter(_LOADED)))
    _LOADED[key] = loaded
    return loaded


_LOADED: dict[tuple[str, bytes], OccupancyMap] = {}
"""Maps loaded by this process, by YAML path and the content of both files."""
_LOADED_MAX = 4


def _image_path(
    yaml_path: Path, image: str, document: LocatedDocument, error_type: type[SourceError]
) -> Path:
    """The image file, resolved against the YAML's folder; it must stay inside that folder."""
    folder = yaml_path.parent
    candidate = folder / image
    real_folder = Path(os.path.realpath(folder))
    real_image = Path(os.path.realpath(candidate))
    if not real_image.is_relative_to(real_folder):
        raise document.error(
            ("image",),
            f"image '{clip(image)}' is outside the map's folder {clip(str(folder))}; keep the "
            "image beside its YAML (or in a folder below it)",
            error_type,
        )
    return candidate


def _at_image(document: LocatedDocument, error_type: type[SourceError], image: str) -> Any:
    """An error factory for the bounded reader that locates its errors at ``image``."""
    line, column = document.locate(("image",))

    def located(_shown: str, _line: int, _column: int, message: str) -> SourceError:
        return error_type(document.path, line, column, f"image '{clip(image)}': {message}")

    return located
