"""What a world file says about its map and its costmap filter masks, and loading them.

A world may stand on a Nav2 map_server map and carry Nav2's costmap filter masks::

    map: ./office.yaml               # or {file: ./office.yaml, wall_height: 1.0, unknown: solid}
    filters:
      keepout: {mask: ./keepout.yaml}
      speed: {mask: ./speed.yaml, type: 1, base: 100, multiplier: -1}

Each file is a map_server YAML + image (:mod:`baobab.sim.occupancy_map`), named relative to
the world file's folder and inside it. ``type``, ``base`` and ``multiplier`` are Nav2's
``CostmapFilterInfo`` fields (filter value = mask value x multiplier + base); a speed mask
defaults to nav2_bringup's info (type 1 = SPEED_FILTER_PERCENT, base 100, multiplier -1: a
scale-mode mask's darkness is the percentage taken off). A keepout filter is type 0 and, as in
Nav2, does not use base and multiplier.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

from pydantic import ConfigDict, Field, GetJsonSchemaHandler, model_validator
from pydantic.json_schema import JsonSchemaValue
from pydantic_core import CoreSchema

from baobab.sim.errors import WorldError, clip
from baobab.sim.yaml_models import YamlModel
from baobab.sim.yaml_source import FieldValueError, KeyPath

if TYPE_CHECKING:  # numpy and Pillow load only when a world has a map
    from baobab.sim.occupancy_map import OccupancyMap

Finite = Annotated[float, Field(allow_inf_nan=False)]

DEFAULT_WALL_HEIGHT = 1.0
"""Height (m) of the boxes a map's solid cells become: well above a mobile robot's lidar."""

KEEPOUT: Literal[0] = 0
"""``CostmapFilterInfo.type`` of a keepout filter."""
SPEED_FILTER_PERCENT: Literal[1] = 1
"""``CostmapFilterInfo.type``: the filter value is a percentage of the maximum speed."""
SPEED_FILTER_ABSOLUTE: Literal[2] = 2
"""``CostmapFilterInfo.type``: the filter value is a speed (m/s)."""


class _Strict(YamlModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class _FileShorthand(_Strict):
    """Accepts a bare path in place of the mapping (``map: ./office.yaml``)."""

    @classmethod
    def __get_pydantic_json_schema__(
        cls, core_schema: CoreSchema, handler: GetJsonSchemaHandler
    ) -> JsonSchemaValue:
        mapping = handler(core_schema)
        path = {"type": "string", "minLength": 1, "description": f"the {cls._path_key()} alone"}
        return {"anyOf": [path, mapping]}

    @model_validator(mode="before")
    @classmethod
    def _path_alone(cls, value: Any) -> Any:
        if isinstance(value, str):
            return {cls._path_key(): value}
        return value

    @classmethod
    def _path_key(cls) -> str:
        return "file"


class MapSettings(_FileShorthand):
    """The map a world stands on: its YAML, how tall its walls are (m), what unknown cells are.

    ``unknown: solid`` (the default) makes unknown cells walls, so a robot cannot drive into
    unexplored space; ``free`` leaves them open floor.
    """

    file: str = Field(min_length=1)
    wall_height: Annotated[float, Field(gt=0, le=100, allow_inf_nan=False)] = DEFAULT_WALL_HEIGHT
    unknown: Literal["solid", "free"] = "solid"


class KeepoutSettings(_FileShorthand):
    """A keepout filter: mask cells become lethal in the costmaps (Nav2's KeepoutFilter)."""

    mask: str = Field(min_length=1)
    type: Literal[0] = KEEPOUT
    base: Finite = 0.0
    multiplier: Finite = 1.0

    @classmethod
    def _path_key(cls) -> str:
        return "mask"

    @model_validator(mode="after")
    def _unused_terms(self) -> KeepoutSettings:
        if self.base != 0.0 or self.multiplier != 1.0:
            raise FieldValueError(
                ("base",) if self.base != 0.0 else ("multiplier",),
                "Nav2's KeepoutFilter does not use base and multiplier (0 and 1); leave them out",
            )
        return self


class SpeedSettings(_FileShorthand):
    """A speed filter: the mask value under the robot limits its speed (Nav2's SpeedFilter)."""

    mask: str = Field(min_length=1)
    type: Literal[1, 2] = SPEED_FILTER_PERCENT
    base: Finite = 100.0
    multiplier: Finite = -1.0

    @classmethod
    def _path_key(cls) -> str:
        return "mask"


class FilterSettings(_Strict):
    """The costmap filters of a world."""

    keepout: KeepoutSettings | None = None
    speed: SpeedSettings | None = None


@dataclass(frozen=True)
class WorldMaps:
    """The loaded map and masks of a world (each None when the world has none)."""

    grid: OccupancyMap | None = None
    keepout: OccupancyMap | None = None
    speed: OccupancyMap | None = None


def load_world_maps(
    map_settings: MapSettings | None,
    filters: FilterSettings | None,
    folder: Path,
    grid: OccupancyMap | None = None,
    owner: str = "world's",
) -> WorldMaps:
    """Load the map and the masks a world names, relative to its ``folder``.

    Args:
        map_settings: the world's ``map:``, if any.
        filters: the world's (or a mission's) ``filters:``, if any.
        folder: where the files are named from; they must lie inside it.
        grid: the map the masks go on, when ``map_settings`` does not name it.
        owner: whose folder it is, in messages (``world's``, ``mission's``).

    Raises:
        FieldValueError: a file outside ``folder`` or missing (located at the world's key).
        WorldError: a problem inside a map or mask file (located in that file).
    """
    keepout = speed = None
    if map_settings is not None:
        grid = _load(folder, map_settings.file, ("map",), "map", owner)
    if filters is not None and filters.keepout is not None:
        at: KeyPath = ("filters", "keepout")
        keepout = _load(folder, filters.keepout.mask, at, "keepout mask", owner)
    if filters is not None and filters.speed is not None:
        speed = _load(folder, filters.speed.mask, ("filters", "speed"), "speed mask", owner)
    for mask, key in ((keepout, "keepout"), (speed, "speed")):
        if mask is not None and grid is not None and not _overlap(mask, grid):
            raise FieldValueError(
                ("filters", key),
                f"the {key} mask covers x {_span(mask, 0)}, y {_span(mask, 1)}: none of the map "
                f"(x {_span(grid, 0)}, y {_span(grid, 1)})",
            )
    return WorldMaps(grid, keepout, speed)


def _load(folder: Path, name: str, key: KeyPath, what: str, owner: str) -> OccupancyMap:
    path = folder / name
    if not Path(os.path.realpath(path)).is_relative_to(Path(os.path.realpath(folder))):
        raise FieldValueError(
            key, f"the {what} '{clip(name)}' is outside the {owner} folder {clip(str(folder))}"
        )
    if not path.exists():
        raise FieldValueError(key, f"the {what} '{clip(name)}' does not exist")
    from baobab.sim.occupancy_map import load_occupancy_map

    return load_occupancy_map(path, WorldError, what=what)


def _overlap(a: OccupancyMap, b: OccupancyMap) -> bool:
    ax0, ay0, ax1, ay1 = a.bounds
    bx0, by0, bx1, by1 = b.bounds
    return ax0 < bx1 and bx0 < ax1 and ay0 < by1 and by0 < ay1


def _span(grid: OccupancyMap, axis: int) -> str:
    bounds = grid.bounds
    return f"{bounds[axis]:g}..{bounds[axis + 2]:g}"
