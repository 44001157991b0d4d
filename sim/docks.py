"""Charging docks: the world file's ``docks:``, Nav2's dock database files, the dock's model.

A world lists its docks as Nav2's dock database does (``docks: {name: {type, frame, pose:
[x, y, yaw], id}}``), and each stands in the world as a charger the lidar sees: a back plate
with two side walls, open towards the robot (:data:`DOCK_PARTS`). A dock's pose is where a
docked robot's base sits, facing the back plate, as in Nav2's database: the plate's front face
lies :data:`PLATE_FRONT` m ahead of it along its yaw, and the side walls frame a bay
:data:`BAY_HALF_WIDTH` m either side of its axis.

A dock database file (``docks:`` at its top, the same entries) lists where a docking server
believes docks stand, which need not be where they do. Everything here is plain math: checking
a world costs no numpy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any

from pydantic import ConfigDict, Field, ValidationError, field_validator

from baobab.sim.errors import SourceError, unknown_name
from baobab.sim.planar_shapes import (
    Rectangle,
    rectangle_corners,
    rectangle_meets_circle,
    rectangles_overlap,
)
from baobab.sim.yaml_models import YamlModel
from baobab.sim.yaml_source import FieldValueError, describe_validation_error, load_located_yaml

Finite = Annotated[float, Field(allow_inf_nan=False)]

CHARGING_DOCK = "charging_dock"
"""The dock model baobab builds (Nav2's ``SimpleChargingDock``), the one type there is."""
DOCK_TYPES = (CHARGING_DOCK,)
"""The dock types a world or a database may name."""
MAP_FRAMES = ("map", "odom")
"""Frames a dock's pose may be given in: the simulation localises perfectly, so ``odom`` is
``map``."""

DOCK_HEIGHT = 0.25
"""Height (m) of every part of a dock: a small robot's lidar scan plane (0.18 m) cuts it."""
PLATE_FRONT = 0.06
"""Distance (m) from the dock pose to the back plate's front face, along the dock's yaw: a
small robot docked within Nav2's 5 cm ``docking_threshold`` stands 0 to 7.5 cm from it (its
chassis ends 3.5 cm ahead of its base)."""
BAY_HALF_WIDTH = 0.135
"""Half the free width (m) between the side walls: 4.6 cm of room past the wheels of a robot
0.178 m wide (the charger fits the smallest bundled robot only)."""
CHARGING_CONTACT = (0.06, 0.25)
"""How close (m, rad) a robot's base must come to the dock pose for the charger's spring
contacts to touch it: a base within Nav2's 5 cm ``docking_threshold`` of a well detected dock
does."""
DOCK_COLOUR = (0.20, 0.22, 0.26, 1.0)


@dataclass(frozen=True)
class DockPart:
    """One box of the dock model, in the dock's frame: centre and full size (m)."""

    suffix: str
    center: tuple[float, float]
    size: tuple[float, float]


_PLATE_DEPTH = 0.04
_WALL = (0.12, 0.03)
"""Side wall length along the dock axis and thickness (m)."""
DOCK_PARTS = (
    DockPart(
        "back", (PLATE_FRONT + _PLATE_DEPTH / 2, 0.0), (_PLATE_DEPTH, 2 * BAY_HALF_WIDTH + 0.07)
    ),
    DockPart("left", (PLATE_FRONT - _WALL[0] / 2, BAY_HALF_WIDTH + _WALL[1] / 2), _WALL),
    DockPart("right", (PLATE_FRONT - _WALL[0] / 2, -BAY_HALF_WIDTH - _WALL[1] / 2), _WALL),
)
"""The U-shaped charger: back plate 4 cm deep, side walls 12 cm long, open towards -x."""
BAY = DockPart("bay", (PLATE_FRONT - _WALL[0] / 2, 0.0), (_WALL[0], 2 * BAY_HALF_WIDTH))
"""Where a docked robot stands between the walls: it must be free."""


def visible_faces() -> list[tuple[tuple[float, float], tuple[float, float]]]:
    """The faces a sensor in front of a dock can see, as segments in the dock frame (m): the
    back plate's face between the walls, and each wall's inner face, front end and outer
    face."""
    plate_x = PLATE_FRONT
    back, inner, outer = PLATE_FRONT - _WALL[0], BAY_HALF_WIDTH, BAY_HALF_WIDTH + _WALL[1]
    faces = [((plate_x, -inner), (plate_x, inner))]
    for side in (1.0, -1.0):
        faces += [
            ((back, side * inner), (plate_x, side * inner)),
            ((back, side * inner), (back, side * outer)),
            ((back, side * outer), (plate_x, side * outer)),
        ]
    return faces


@dataclass(frozen=True)
class PlacedPart:
    """A dock part in the map frame: name, centre (m), full size (m), yaw (rad)."""

    name: str
    center: tuple[float, float]
    size: tuple[float, float]
    yaw: float


class Dock(YamlModel):
    """One dock as Nav2's database lists it: ``type``, ``frame``, ``pose: [x, y, yaw]``, ``id``.

    ``pose`` is the docked robot's base pose (m, m, rad); ``id`` is the dock's detector id
    (unused by baobab's lidar detector, kept for Nav2's format).
    """

    model_config = ConfigDict(extra="forbid", frozen=True)

    type: str = CHARGING_DOCK
    frame: str = "map"
    pose: tuple[Finite, Finite, Finite]
    id: str = ""

    @field_validator("type")
    @classmethod
    def _known_type(cls, value: str) -> str:
        if value == "" and len(DOCK_TYPES) == 1:
            return DOCK_TYPES[0]  # Nav2: the type may be left empty when one plugin exists
        if value not in DOCK_TYPES:
            raise ValueError(unknown_name("dock type", value, DOCK_TYPES))
        return value

    @field_validator("frame")
    @classmethod
    def _map_frame(cls, value: str) -> str:
        if value not in MAP_FRAMES:
            raise ValueError(
                f"frame '{value}': docks are given in the map frame ('map' or 'odom', which is "
                "the same frame in the simulation)"
            )
        return value

    @property
    def x(self) -> float:
        """Docked base position x (m)."""
        return self.pose[0]

    @property
    def y(self) -> float:
        """Docked base position y (m)."""
        return self.pose[1]

    @property
    def yaw(self) -> float:
        """Docked heading (rad): towards the back plate."""
        return self.pose[2]

    def to_map(self, local_x: float, local_y: float) -> tuple[float, float]:
        """A point of the dock's frame (m) in the map frame (m)."""
        cos, sin = math.cos(self.yaw), math.sin(self.yaw)
        return self.x + cos * local_x - sin * local_y, self.y + sin * local_x + cos * local_y

    def parts(self, name: str) -> list[PlacedPart]:
        """The boxes of this dock, called ``name`` in the world, in the map frame."""
        return [self._placed(name, part) for part in DOCK_PARTS]

    def bay(self, name: str) -> PlacedPart:
        """Where the docked robot stands, in the map frame."""
        return self._placed(name, BAY)

    def _placed(self, name: str, part: DockPart) -> PlacedPart:
        return PlacedPart(f"{name}/{part.suffix}", self.to_map(*part.center), part.size, self.yaw)


def check_docks(
    docks: dict[str, Dock],
    boxes: list[Any],
    cylinders: list[Any],
    bounds: tuple[float, float, float, float],
) -> None:
    """Refuse docks that stand off the floor, in an obstacle or another dock, or whose bay is
    taken.

    Args:
        docks: the world's docks by name.
        boxes: the world's boxes (rectangles with a ``name``).
        cylinders: the world's cylinders (circles with a ``name``).
        bounds: the floor as (x_min, y_min, x_max, y_max) (m).

    Raises:
        FieldValueError: located at ``docks.<name>.pose``.
    """
    placed = {name: dock.parts(name) for name, dock in docks.items()}
    names = list(docks)
    for index, (name, dock) in enumerate(docks.items()):
        where = ("docks", name, "pose")
        for part in [*placed[name], dock.bay(name)]:
            if not _on_floor(part, bounds):
                raise FieldValueError(where, f"dock '{name}' stands partly off the floor")
            blocker = _first_overlap(part, boxes, cylinders)
            if blocker is not None:
                what = "it stands"
                if part.name.endswith(f"/{BAY.suffix}"):
                    what = "its bay (where the docked robot stands) is"
                raise FieldValueError(
                    where, f"dock '{name}': {what} inside obstacle '{blocker}'; move the dock"
                )
            for other in names[:index]:
                if any(rectangles_overlap(part, mine) for mine in placed[other]):
                    raise FieldValueError(where, f"dock '{name}' overlaps dock '{other}'")


def _on_floor(part: PlacedPart, bounds: tuple[float, float, float, float]) -> bool:
    x_min, y_min, x_max, y_max = bounds
    return all(x_min <= x <= x_max and y_min <= y <= y_max for x, y in rectangle_corners(part))


def _first_overlap(part: Rectangle, boxes: list[Any], cylinders: list[Any]) -> str | None:
    for box in boxes:
        if rectangles_overlap(part, box):
            return str(box.name)
    for cylinder in cylinders:
        if rectangle_meets_circle(part, cylinder):
            return str(cylinder.name)
    return None


class _DatabaseFile(YamlModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    docks: dict[str, Dock]


def load_dock_database(path: str | Path) -> dict[str, Dock]:
    """Read a Nav2 dock database file: ``docks:`` mapping each name to its entry.

    Raises:
        SourceError: located ``file:line:col: message`` for any problem in the file.
    """
    document = load_located_yaml(path, SourceError)
    if not isinstance(document.data, dict):
        raise document.error((), "a dock database must be a mapping with a 'docks' key")
    try:
        return dict(_DatabaseFile.model_validate(document.data).docks)
    except ValidationError as exc:
        raise describe_validation_error(document, exc, (), SourceError) from None


__all__ = [
    "BAY_HALF_WIDTH",
    "CHARGING_CONTACT",
    "CHARGING_DOCK",
    "DOCK_HEIGHT",
    "DOCK_PARTS",
    "DOCK_TYPES",
    "PLATE_FRONT",
    "Dock",
    "PlacedPart",
    "check_docks",
    "load_dock_database",
]
