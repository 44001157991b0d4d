"""The world description: a small YAML format for flat floors with walls, boxes and tables.

A world file names a floor, static boxes (walls, counters, crop rows, houses), static cylinders
(tables, trees, pumps), named spawn poses and named locations. It is validated with pydantic
and every error names the file, line, column and field.

A world may instead stand on a Nav2 map_server map (``map: ./office.yaml``): the map's
rectangle is the floor, its solid cells are walls, and the boxes, cylinders, spawns and
locations of the file come on top; a map alone has no spawn. ``filters:`` names Nav2 costmap
filter masks (:mod:`baobab.sim.world_map`). ``load_world`` also takes a map_server YAML
itself as a world. Optional: a ``route_graph`` (a Nav2 GeoJSON file next to the world file,
:mod:`baobab.sim.route_graph_file`) and a ``datum`` (:mod:`baobab.sim.datum`).
"""

from __future__ import annotations

import hashlib
import math
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

from pydantic import (
    ConfigDict,
    Field,
    PrivateAttr,
    ValidationError,
    ValidationInfo,
    model_validator,
)

from baobab.sim.datum import Datum
from baobab.sim.docks import DOCK_COLOUR, DOCK_HEIGHT, Dock, check_docks
from baobab.sim.errors import WorldError
from baobab.sim.moving_objects import MovingObject, check_moving_objects
from baobab.sim.route_graph_file import RouteGraph, load_route_graph
from baobab.sim.route_graph_geometry import check_on_world
from baobab.sim.world_map import FilterSettings, MapSettings, WorldMaps, load_world_maps
from baobab.sim.yaml_models import YamlModel, degrees_in_place
from baobab.sim.yaml_source import (
    FieldValueError,
    describe_validation_error,
    empty_list,
    load_located_yaml,
    read_yaml_text,
)

if TYPE_CHECKING:
    import numpy as np

    from baobab.sim.occupancy_map import OccupancyMap

Finite = Annotated[float, Field(allow_inf_nan=False)]
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
Colour = tuple[
    Annotated[float, Field(ge=0, le=1)],
    Annotated[float, Field(ge=0, le=1)],
    Annotated[float, Field(ge=0, le=1)],
    Annotated[float, Field(ge=0, le=1)],
]


FLOOR_NAME = "floor"
"""Name of the floor geom in every built model."""

MOVABLE_SLOT_PREFIX = "movable_"
"""Prefix of the run-time obstacle slots' body and geom names."""

MOVABLE_SLOT_COUNT = 4
"""How many run-time obstacle slots every built model has (at most that many spawned at once)."""

MAP_GEOM_PREFIX = "map_"
"""Prefix of the geoms a world's map becomes (reserved for obstacle names on a map)."""

# Size limits of a world (README "Limits"): each is checked when the file is loaded, so
# `baobab validate` refuses a world that a run could not build in memory or in good time.
MAX_FLOOR_SIDE = 1_000.0
"""Longest floor side (m); no obstacle is larger either."""
MAX_COORDINATE = 10_000.0
"""Largest distance of the floor's and the obstacles' centres from the origin along x or y (m)."""
COSTMAP_CELL_SIZE = 0.05
"""Cell side (m) of the navigation stack's global costmap, which covers the whole floor (Nav2's
default ``resolution``, :class:`baobab.nav.layered_costmap.CostmapParams`)."""
MAX_COSTMAP_CELLS = 10_000_000
"""Most cells in a global costmap: about 10 bytes each while a run navigates, so a floor of
about 158 m x 158 m (or 1000 m x 10 m) costs some 100 MB."""
MAX_OBSTACLES = 1_000
"""Most boxes and cylinders in one world (each adds to the model's build and contact sensing)."""
MAX_NAMED_POSES = 1_000
"""Most spawns and locations in one world."""


class _Strict(YamlModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class _Yawed(_Strict):
    """Accepts ``yaw_deg`` (degrees) on input in place of ``yaw`` (radians)."""

    @model_validator(mode="before")
    @classmethod
    def _degrees(cls, value: object) -> object:
        both = "give either yaw (radians) or yaw_deg (degrees), not both"
        return degrees_in_place(value, "yaw", both)


class Pose2D(_Yawed):
    """A planar pose in the map frame: metres and radians (``yaw_deg`` accepted on input)."""

    x: Finite
    y: Finite
    yaw: Finite = 0.0


class Floor(_Strict):
    """The floor rectangle: full side lengths ``size`` (m) around ``center`` (m)."""

    size: tuple[Positive, Positive]
    center: tuple[Finite, Finite] = (0.0, 0.0)
    colour: Colour = (0.82, 0.80, 0.74, 1.0)


class Box(_Yawed):
    """A static box standing on the floor: full side lengths ``size`` (m), ``yaw`` (rad).

    ``yaw_deg`` (degrees) is accepted on input in place of ``yaw``.
    """

    name: str
    center: tuple[Finite, Finite]
    size: tuple[Positive, Positive]
    height: Positive = 0.5
    yaw: Finite = 0.0
    colour: Colour = (0.55, 0.55, 0.60, 1.0)


class Cylinder(_Strict):
    """A static upright cylinder standing on the floor (a table, a tree): metres."""

    name: str
    center: tuple[Finite, Finite]
    radius: Positive
    height: Positive = 0.75
    colour: Colour = (0.60, 0.42, 0.25, 1.0)


class World(_Strict):
    """A whole world: floor (or a map), obstacles, spawn poses, named locations and filters."""

    name: str
    description: str = ""
    map: MapSettings | None = None
    floor: Floor = Floor(size=(1.0, 1.0))
    boxes: list[Box] = Field(default_factory=empty_list)
    cylinders: list[Cylinder] = Field(default_factory=empty_list)
    spawns: dict[str, Pose2D] = Field(default_factory=dict)
    locations: dict[str, Pose2D] = Field(default_factory=dict)
    docks: dict[str, Dock] = Field(default_factory=dict)
    """Charging docks, as Nav2's dock database lists them (:mod:`baobab.sim.docks`)."""
    moving_objects: list[MovingObject] = Field(default_factory=empty_list)
    """Scripted objects that walk about (:mod:`baobab.sim.moving_objects`)."""
    filters: FilterSettings | None = None
    collision_monitor: dict[str, Any] | None = Field(
        default=None,
        description="parameters of the robot's collision monitor in this world, kept as "
        "written: the navigation stack reads them (baobab.nav.collision_monitor_params)",
    )
    _maps: WorldMaps = PrivateAttr(default_factory=WorldMaps)
    route_graph: str | None = Field(
        default=None, description="Nav2 GeoJSON route graph file, relative to the world file"
    )
    datum: Datum | None = None
    _routes: RouteGraph | None = PrivateAttr(default=None)

    @model_validator(mode="after")
    def _check(self, info: ValidationInfo) -> World:
        self._load_maps(info)
        if self.map is None and "floor" not in self.model_fields_set:
            raise FieldValueError((), "missing required key 'floor' (or a 'map')")
        if self.map is None and "default" not in self.spawns:
            raise FieldValueError(("spawns",), "needs a 'default' entry")
        self._check_sizes()
        self._check_names()
        check_docks(self.docks, self.boxes, self.cylinders, self.bounds)
        check_moving_objects(
            self.moving_objects, [*self.boxes, *self.cylinders, *self.dock_boxes], self.bounds
        )
        for group, poses in (("spawns", self.spawns), ("locations", self.locations)):
            for label, pose in poses.items():
                if not self.contains(pose.x, pose.y):
                    x_min, y_min, x_max, y_max = self.bounds
                    raise FieldValueError(
                        (group, label),
                        f"'{label}' at ({pose.x}, {pose.y}) is outside the floor "
                        f"x {x_min:g}..{x_max:g}, y {y_min:g}..{y_max:g}",
                    )
        return self

    def _load_maps(self, info: ValidationInfo) -> None:
        """Load the map and masks (relative to the world file's folder) and take the floor."""
        if self.map is None and self.filters is None:
            return
        context = info.context if isinstance(info.context, dict) else {}
        folder = Path(context.get("folder", "."))
        self._maps = load_world_maps(self.map, self.filters, folder)
        grid = self._maps.grid
        if grid is None:
            return
        if "floor" in self.model_fields_set:
            raise FieldValueError(("floor",), "a world on a map takes its floor from the map")
        x_min, y_min, x_max, y_max = grid.bounds
        floor = Floor(
            size=(x_max - x_min, y_max - y_min), center=((x_min + x_max) / 2, (y_min + y_max) / 2)
        )
        object.__setattr__(self, "floor", floor)  # frozen: the floor is the map's, set once

    def _check_names(self) -> None:
        obstacles = [("boxes", i, b.name) for i, b in enumerate(self.boxes)]
        obstacles += [("cylinders", i, c.name) for i, c in enumerate(self.cylinders)]
        seen: set[str] = set()
        reserved = f"'{FLOOR_NAME}', '{MOVABLE_SLOT_PREFIX}N' name the floor and run-time obstacles"
        if self.map is not None:
            reserved = (
                f"'{FLOOR_NAME}', '{MOVABLE_SLOT_PREFIX}N', '{MAP_GEOM_PREFIX}N' name the floor, "
                "run-time obstacles and the map's walls"
            )
        for group, index, name in obstacles:
            if name in seen:
                raise FieldValueError(
                    (group, index, "name"), f"obstacle name '{name}' is used twice"
                )
            if (
                name == FLOOR_NAME
                or name.startswith(MOVABLE_SLOT_PREFIX)
                or (self.map is not None and name.startswith(MAP_GEOM_PREFIX))
            ):
                raise FieldValueError(
                    (group, index, "name"),
                    f"obstacle name '{name}' is reserved ({reserved})",
                )
            seen.add(name)

    def _check_sizes(self) -> None:
        """The limits of :data:`MAX_FLOOR_SIDE` ... :data:`MAX_NAMED_POSES`."""
        (sx, sy), (cx, cy) = self.floor.size, self.floor.center
        if max(sx, sy) > MAX_FLOOR_SIDE:
            raise FieldValueError(
                ("floor", "size"),
                f"the floor is {sx:g} m x {sy:g} m; the limit is {MAX_FLOOR_SIDE:g} m a side "
                "(MAX_FLOOR_SIDE)",
            )
        if max(abs(cx), abs(cy)) > MAX_COORDINATE:
            raise FieldValueError(("floor", "center"), _far_away("the floor's centre", cx, cy))
        cells = math.ceil(round(sx / COSTMAP_CELL_SIZE, 9)) * math.ceil(
            round(sy / COSTMAP_CELL_SIZE, 9)
        )
        if cells > MAX_COSTMAP_CELLS:
            raise FieldValueError(
                ("floor", "size"),
                f"the floor is {sx:g} m x {sy:g} m: {cells:,} cells of the navigation costmap at "
                f"{COSTMAP_CELL_SIZE:g} m; the limit is {MAX_COSTMAP_CELLS:,} cells "
                "(MAX_COSTMAP_CELLS)",
            )
        count = len(self.boxes) + len(self.cylinders)
        if count > MAX_OBSTACLES:
            group = "boxes" if len(self.boxes) >= len(self.cylinders) else "cylinders"
            raise FieldValueError(
                (group,),
                f"{count} obstacles (boxes and cylinders); the limit is {MAX_OBSTACLES} "
                "(MAX_OBSTACLES)",
            )
        poses = len(self.spawns) + len(self.locations)
        if poses > MAX_NAMED_POSES:
            raise FieldValueError(
                ("locations",) if self.locations else ("spawns",),
                f"{poses} spawns and locations; the limit is {MAX_NAMED_POSES} (MAX_NAMED_POSES)",
            )
        for group, index, center, extent in [
            *(("boxes", i, b.center, max(b.size + (b.height,))) for i, b in enumerate(self.boxes)),
            *(
                ("cylinders", i, c.center, max(2 * c.radius, c.height))
                for i, c in enumerate(self.cylinders)
            ),
        ]:
            if max(abs(center[0]), abs(center[1])) > MAX_COORDINATE:
                raise FieldValueError(
                    (group, index, "center"), _far_away("the centre", center[0], center[1])
                )
            if extent > MAX_FLOOR_SIDE:
                raise FieldValueError(
                    (group, index),
                    f"an obstacle {extent:g} m across; the limit is {MAX_FLOOR_SIDE:g} m "
                    "(MAX_FLOOR_SIDE)",
                )

    @cached_property
    def dock_boxes(self) -> list[Box]:
        """The parts of every dock as static boxes (named ``<dock>/back`` ...)."""
        return [
            Box(
                name=part.name,
                center=part.center,
                size=part.size,
                yaw=part.yaw,
                height=DOCK_HEIGHT,
                colour=DOCK_COLOUR,
            )
            for name, dock in self.docks.items()
            for part in dock.parts(name)
        ]

    @cached_property
    def bounds(self) -> tuple[float, float, float, float]:
        """Floor extent as (x_min, y_min, x_max, y_max) in metres."""
        (sx, sy), (cx, cy) = self.floor.size, self.floor.center
        return (cx - sx / 2, cy - sy / 2, cx + sx / 2, cy + sy / 2)

    def contains(self, x: float, y: float) -> bool:
        """True when (x, y) (m) lies on the floor."""
        (sx, sy), (cx, cy) = self.floor.size, self.floor.center
        return abs(x - cx) <= sx / 2 and abs(y - cy) <= sy / 2

    @property
    def spawn(self) -> Pose2D:
        """The default spawn pose.

        Raises:
            WorldError: the world (a map alone) has none.
        """
        found = self.spawns.get("default")
        if found is None:
            raise WorldError(
                self.name, 1, 1, f"world '{self.name}' has no default spawn; give a start pose"
            )
        return found

    @property
    def grid(self) -> OccupancyMap | None:
        """The map_server map the world stands on, or None."""
        return self._maps.grid

    @property
    def masks(self) -> WorldMaps:
        """The loaded map and costmap filter masks."""
        return self._maps

    @property
    def unknown_is_solid(self) -> bool:
        """Whether the map's unknown cells are walls."""
        return self.map is not None and self.map.unknown == "solid"

    def map_solid(self) -> np.ndarray | None:
        """The map's solid cells (``bool``, ``[iy, ix]``, row 0 at the bottom), or None."""
        grid = self._maps.grid
        return None if grid is None else grid.solid(self.unknown_is_solid)

    def with_filters(self, filters: FilterSettings, folder: Path) -> World:
        """This world with ``filters`` (mask paths relative to ``folder``, inside it) in place
        of its own filters of the same kinds: a mission's ``filters:``.

        Raises:
            FieldValueError: a mask outside ``folder``, missing, or off the map (located at
                the key ``(kind,)`` in ``filters``).
            WorldError: a problem inside a mask file (located in it).
        """
        try:
            loaded = load_world_maps(None, filters, folder, self._maps.grid, "mission's")
        except FieldValueError as exc:
            raise FieldValueError(exc.key_path[1:], str(exc)) from None
        own = self.filters or FilterSettings()
        kept = FilterSettings(
            keepout=filters.keepout or own.keepout, speed=filters.speed or own.speed
        )
        world = self.model_copy(update={"filters": kept})
        masks = self._maps
        world._maps = WorldMaps(
            masks.grid, loaded.keepout or masks.keepout, loaded.speed or masks.speed
        )
        return world

    @property
    def routes(self) -> RouteGraph | None:
        """The route graph loaded from ``route_graph``, or None."""
        return self._routes

    def with_route_graph(self, graph: RouteGraph) -> World:
        """This world with ``graph`` as its route graph (a mission's own ``route_graph``)."""
        world = self.model_copy()
        world._routes = graph
        return world

    def pose(self, name: str) -> Pose2D:
        """A named location or spawn pose; ``WorldError``-free lookup is the caller's job."""
        if name in self.locations:
            return self.locations[name]
        return self.spawns[name]


def _far_away(what: str, x: float, y: float) -> str:
    return (
        f"{what} ({x:g}, {y:g}) is more than {MAX_COORDINATE:g} m from the origin along x or y "
        "(MAX_COORDINATE)"
    )


_WORLDS_FOLDER = Path(__file__).parent / "worlds"
"""The bundled world files, package data next to this module (importlib.resources would add
its own imports to every command's start-up)."""


def bundled_world_path(name: str) -> Path:
    """Path of a bundled world file such as ``cafe`` -> ``.../sim/worlds/cafe.yaml``."""
    return _WORLDS_FOLDER / f"{name}.yaml"


def bundled_world_names() -> list[str]:
    """Names of all bundled 2D worlds, sorted."""
    if not _WORLDS_FOLDER.is_dir():
        return []
    return sorted(
        entry.name.removesuffix(".yaml")
        for entry in _WORLDS_FOLDER.iterdir()
        if entry.name.endswith(".yaml")
    )


def load_world(name_or_path: str | Path) -> World:
    """Load a bundled world by name (``cafe``), a world YAML file or a map_server map YAML.

    A map YAML (a mapping with an ``image`` key) becomes a world named after its file, with
    the map and nothing else: no spawn, no filters.

    Raises:
        WorldError: located ``file:line:col: message`` for any problem in the file.
    """
    text_name = str(name_or_path)
    if (
        isinstance(name_or_path, str)
        and "/" not in text_name
        and not text_name.endswith((".yaml", ".yml"))
    ):
        known = bundled_world_names()
        if text_name not in known:
            raise WorldError(
                text_name, 1, 1, f"unknown world '{text_name}'; bundled worlds: {', '.join(known)}"
            )
        path = bundled_world_path(text_name)
    else:
        path = Path(name_or_path)
    text = read_yaml_text(path, WorldError)
    key = _cache_key(path, text)
    cached = _LOADED.get(key)
    if cached is not None:
        return cached
    document = load_located_yaml(path, WorldError, text=text)
    if not isinstance(document.data, dict):
        raise document.error((), "a world file must be a mapping of keys", WorldError)
    data = document.data
    if "image" in data and "name" not in data:  # a map_server map YAML
        data = {"name": path.stem, "map": {"file": path.name}}
    try:
        world = World.model_validate(data, context={"folder": path.parent})
    except ValidationError as exc:
        raise describe_validation_error(document, exc, (), WorldError) from None
    if world.route_graph is not None:
        graph_path = path.parent / world.route_graph
        if not graph_path.is_file():
            raise document.error(
                ("route_graph",), f"route graph file '{graph_path}' not found", WorldError
            )
        world._routes = load_route_graph(graph_path)
        check_on_world(world._routes, world)
    if world.map is not None or world.filters is not None:
        return world  # its map and masks are files of their own, cached where they load
    if len(_LOADED) >= _LOADED_MAX:
        _LOADED.pop(next(iter(_LOADED)))
    _LOADED[key] = world
    return world


_LOADED: dict[tuple[str, bytes], World] = {}
"""Worlds loaded by this process, by file and content: a World is immutable, so missions in one
process (``baobab validate`` of many files, a campaign worker) share it instead of parsing the
same text again."""
_LOADED_MAX = 32


def _cache_key(path: Path, text: str) -> tuple[str, bytes]:
    """(resolved path, SHA-256 of the content) of a world file."""
    return str(path.resolve()), hashlib.sha256(text.encode("utf-8", "surrogatepass")).digest()
