"""A Nav2 costmap's ``robot_radius``, ``footprint`` and ``footprint_padding`` as a footprint.

Nav2's ``Costmap2DROS`` takes ``footprint``, a polygon written as a string
(``"[[0.2, 0.15], [0.2, -0.15], [-0.2, -0.15], [-0.2, 0.15]]"``, m, x forward, y left of
``base_link``; a YAML list of pairs is read too) which wins over ``robot_radius`` (m) when it is
not empty (``"[]"``, the default). A polygon is padded by ``footprint_padding`` (m, Nav2's
0.01) as :meth:`~baobab.robots.footprint.Footprint.padded` does; a radius is used as given, as
baobab's robots use theirs (Nav2 pads the 16-point outline it makes of one: about the padding
more).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

from baobab.nav.nav2_params_file import Nav2Parameter, Nav2ParamsFile
from baobab.robots.footprint import NAV2_FOOTPRINT_PADDING, Footprint
from baobab.sim.errors import clip


@dataclass(frozen=True)
class FootprintSetting:
    """The footprint a costmap section gives, and the parameters that gave it.

    Attributes:
        footprint: the costmap's footprint (a polygon padded); None: the section sets none.
        parameters: ``robot_radius``, ``footprint`` and ``footprint_padding`` as the file sets
            them (those it sets).
        unused: a ``footprint_padding`` with no radius or polygon beside it to pad.
    """

    footprint: Footprint | None
    parameters: tuple[Nav2Parameter, ...]
    unused: tuple[Nav2Parameter, ...] = ()


def costmap_footprint(file: Nav2ParamsFile, node: str) -> FootprintSetting:
    """The footprint the costmap ``node``'s section sets.

    Raises:
        Nav2ParamsError: located: a radius that is not a positive number, a padding that is not
            a non-negative number, a footprint that is not a polygon (fewer than 3 points,
            crossing edges, no area, not around ``base_link``, not numbers).
    """
    radius = file.get(node, "robot_radius")
    polygon = file.get(node, "footprint")
    padding = file.get(node, "footprint_padding")
    given = tuple(p for p in (radius, polygon, padding) if p is not None)
    pad = NAV2_FOOTPRINT_PADDING if padding is None else _number(file, padding, "a padding", 0.0)
    if polygon is not None:
        points = _points(file, polygon)
        if points:
            footprint = Footprint(polygon=points)
            problem = footprint.problem()
            if problem is not None:
                raise file.error(polygon, f"footprint is not a usable polygon: {problem}")
            return FootprintSetting(footprint.padded(pad), given)
    if radius is not None:
        value = _number(file, radius, "a radius", None)
        unused = () if padding is None else (padding,)
        return FootprintSetting(Footprint.circle(value), given, unused)
    return FootprintSetting(None, given, given)


def _number(file: Nav2ParamsFile, parameter: Nav2Parameter, what: str, floor: Any) -> float:
    """A positive number (``floor`` None) or one at least ``floor``."""
    value = parameter.value
    number = isinstance(value, int | float) and not isinstance(value, bool)
    if not number or (value <= 0 if floor is None else value < floor):
        wanted = "a positive number" if floor is None else "a non-negative number"
        raise file.error(parameter, f"{parameter.name} (m) must be {wanted}, got {clip(value)}")
    return float(value)


def _points(file: Nav2ParamsFile, parameter: Nav2Parameter) -> tuple[tuple[float, float], ...]:
    """The vertices of a ``footprint`` value: Nav2's string, or a YAML list of [x, y] pairs."""
    value = parameter.value
    if isinstance(value, str):
        try:
            value = json.loads(value) if value.strip() else []
        except ValueError:
            raise file.error(
                parameter,
                f'footprint must be a polygon such as "[[0.2, 0.15], [0.2, -0.15], [-0.2, 0.0]]",'
                f" got {clip(repr(parameter.value))}",
            ) from None
    pairs = isinstance(value, list) and all(
        isinstance(point, list)
        and len(point) == 2
        and all(isinstance(v, int | float) and not isinstance(v, bool) for v in point)
        for point in value
    )
    if not pairs:
        raise file.error(
            parameter, f"footprint must be a list of [x, y] points (m), got {clip(parameter.value)}"
        )
    return tuple((float(x), float(y)) for x, y in value)
