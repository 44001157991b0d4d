"""Nav2's costmap filters over baobab's costmaps: KeepoutFilter and SpeedFilter.

A filter reads a mask (a map_server map served as Nav2's filter mask servers serve it) and
the ``CostmapFilterInfo`` fields (type, base, multiplier; reference/nav2_ros_facts.md §2):

- :class:`KeepoutFilter`: each mask cell's cost (-1 -> none, else ``round(v * 254 / 100)``)
  is written over the costmap cell when it is higher or the cell is unknown, after the layers
  and their inflation (Nav2 runs filters last). With ``override_lethal_cost`` (nav2_bringup's
  setting), while the robot stands on an inscribed or lethal mask cell the mask's inscribed
  and lethal cells are written as ``lethal_override_cost`` instead, so it can drive out.
  One difference from Nav2, on purpose: the zone's lethal cells are inflated like a wall's
  (their inflation is written with them), so the planner keeps the robot's footprint out of
  the zone, not only its centre; Nav2 writes the bare mask, and a path that hugs a zone lets
  the controller's projected motion clip its corners.
- :class:`SpeedFilter`: the mask value ``m`` under the robot gives a speed limit: ``m == 0``
  no limit, ``m == -1`` nothing new; else ``base + multiplier * m``, a percentage of the
  maximum speed (type 1; outside 0..100 is no limit) or m/s (type 2; below 0 is no limit); a
  computed 0 is the no-limit value. Off the mask nothing new. A new limit is published only
  when it changes, and the controller applies it (Regulated Pure Pursuit's ``setSpeedLimit``).

Masks are sampled at the costmap's cell centres, so a mask need not share the map's
resolution or origin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from baobab.nav.costmap import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from baobab.nav.layers import InflationLayer
from baobab.sim.occupancy_map import OccupancyMap
from baobab.sim.world import World
from baobab.sim.world_map import SPEED_FILTER_PERCENT

if TYPE_CHECKING:
    from baobab.nav.layers import InflationParams, StaticLayer

NO_SPEED_LIMIT = 0.0
"""Nav2's ``SpeedLimit.speed_limit`` value meaning "no limit"."""


@dataclass(frozen=True)
class KeepoutParams:
    """KeepoutFilter settings: nav2_bringup's (``override_lethal_cost`` true, cost 200)."""

    override_lethal_cost: bool = True
    lethal_override_cost: int = 200


@dataclass(frozen=True)
class SpeedLimit:
    """``nav2_msgs/SpeedLimit``: ``speed_limit`` in percent or m/s; 0 means no limit."""

    percentage: bool
    speed_limit: float


def mask_costs(values: np.ndarray) -> np.ndarray:
    """A mask's occupancy values as costs: -1 -> 255, else ``round(v * 254 / 100)``."""
    scaled = np.floor(values.astype(np.float64) * 254.0 / 100.0 + 0.5)
    return np.where(values < 0, NO_INFORMATION, np.clip(scaled, 0, 254)).astype(np.uint8)


class KeepoutFilter:
    """A keepout mask laid on a costmap lattice.

    Args:
        mask: the keepout mask.
        origin: map-frame position (m) of lattice cell (0, 0)'s lower-left corner.
        resolution: the lattice's cell side (m).
        shape: ``(size_y, size_x)`` lattice cells the mask is sampled on.
        params: override settings.
        inflation: the costmap's inflation, applied to the zone's lethal cells (None: none).
    """

    def __init__(
        self,
        mask: OccupancyMap,
        origin: tuple[float, float],
        resolution: float,
        shape: tuple[int, int],
        params: KeepoutParams | None = None,
        inflation: InflationLayer | None = None,
    ) -> None:
        self.params = params or KeepoutParams()
        self.mask = mask
        size_y, size_x = shape
        xs = origin[0] + (np.arange(size_x) + 0.5) * resolution
        ys = origin[1] + (np.arange(size_y) + 0.5) * resolution
        ix = np.floor((xs - mask.origin[0]) / mask.resolution).astype(np.int64)
        iy = np.floor((ys - mask.origin[1]) / mask.resolution).astype(np.int64)
        inside_x = (ix >= 0) & (ix < mask.width)
        inside_y = (iy >= 0) & (iy < mask.height)
        costs = mask_costs(mask.data)
        self.costs = np.full(shape, NO_INFORMATION, dtype=np.uint8)
        sampled = costs[np.ix_(iy[inside_y], ix[inside_x])]
        self.costs[np.ix_(np.flatnonzero(inside_y), np.flatnonzero(inside_x))] = sampled
        if inflation is not None:
            inflated = inflation.inflate(self.costs == LETHAL_OBSTACLE, resolution)
            none = self.costs == NO_INFORMATION
            self.costs = np.where(
                none,
                np.where(inflated > 0, inflated, NO_INFORMATION),
                np.maximum(self.costs, inflated),
            ).astype(np.uint8)
        rows, cols = np.nonzero(self.costs != NO_INFORMATION)
        self.bounds = (
            (int(cols.min()), int(rows.min()), int(cols.max()) + 1, int(rows.max()) + 1)
            if len(rows)
            else None
        )
        """Lattice cells ``(ix0, iy0, ix1, iy1)`` the mask writes to, or None."""

    def overrides_at(self, lattice_x: int, lattice_y: int) -> bool:
        """Whether a robot in lattice cell (x, y) stands in the zone, so the override applies."""
        size_y, size_x = self.costs.shape
        if not (self.params.override_lethal_cost and 0 <= lattice_x < size_x):
            return False
        if not 0 <= lattice_y < size_y:
            return False
        cost = int(self.costs[lattice_y, lattice_x])
        return INSCRIBED_INFLATED_OBSTACLE <= cost < NO_INFORMATION

    def apply(self, master: np.ndarray, lattice_x0: int, lattice_y0: int, overriding: bool) -> None:
        """Write the mask over ``master``, whose cell (0, 0) is lattice cell (x0, y0);
        ``overriding``: the robot stands in the zone (:meth:`overrides_at`)."""
        size_y, size_x = self.costs.shape
        height, width = master.shape
        x0, y0 = max(lattice_x0, 0), max(lattice_y0, 0)
        x1, y1 = min(lattice_x0 + width, size_x), min(lattice_y0 + height, size_y)
        if x0 >= x1 or y0 >= y1:
            return
        costs = self.costs[y0:y1, x0:x1]
        old = master[y0 - lattice_y0 : y1 - lattice_y0, x0 - lattice_x0 : x1 - lattice_x0]
        if overriding:
            lethal = (costs >= INSCRIBED_INFLATED_OBSTACLE) & (costs != NO_INFORMATION)
            costs = np.where(lethal, np.uint8(self.params.lethal_override_cost), costs)
        write = (costs != NO_INFORMATION) & ((costs > old) | (old == NO_INFORMATION))
        old[write] = costs[write]


class SpeedFilter:
    """Nav2's SpeedFilter: the speed limit the mask gives at the robot's position.

    Args:
        mask: the speed mask.
        filter_type: 1 (percent) or 2 (absolute, m/s).
        base: ``CostmapFilterInfo.base``.
        multiplier: ``CostmapFilterInfo.multiplier``.
    """

    def __init__(
        self, mask: OccupancyMap, filter_type: int, base: float, multiplier: float
    ) -> None:
        self.mask = mask
        self.percentage = filter_type == SPEED_FILTER_PERCENT
        self.base = base
        self.multiplier = multiplier
        self.current: SpeedLimit | None = None
        """The last limit published (None before the first)."""

    def limit_at(self, x: float, y: float) -> SpeedLimit | None:
        """The limit the mask sets at map point ``(x, y)`` (m), or None (nothing to publish)."""
        return self.limit_of(self.mask.value_at(x, y))

    def limit_of(self, value: int | None) -> SpeedLimit | None:
        """The limit a mask value sets (None off the mask), or None (nothing to publish)."""
        if value is None or value < 0:
            return None
        if value == 0:
            return SpeedLimit(self.percentage, NO_SPEED_LIMIT)
        limit = self.base + self.multiplier * value
        out_of_range = not 0.0 <= limit <= 100.0 if self.percentage else limit < 0.0
        if out_of_range:
            limit = NO_SPEED_LIMIT
        return SpeedLimit(self.percentage, limit)

    def update(self, x: float, y: float) -> SpeedLimit | None:
        """The new limit at ``(x, y)`` when it differs from the last one published, else None."""
        limit = self.limit_at(x, y)
        if limit is None or limit == self.current:
            return None
        self.current = limit
        return limit


def applied_speed(limit: SpeedLimit | None, base_speed: float) -> float:
    """The controller's top speed (m/s) under ``limit``: RPP's ``setSpeedLimit``."""
    if limit is None or limit.speed_limit == NO_SPEED_LIMIT or math.isnan(limit.speed_limit):
        return base_speed
    if limit.percentage:
        return base_speed * limit.speed_limit / 100.0
    return limit.speed_limit


def keepout_filter(
    world: World,
    static: StaticLayer,
    inflation: InflationParams,
    params: KeepoutParams | None = None,
) -> KeepoutFilter | None:
    """The world's keepout filter on ``static``'s lattice, its zones inflated with
    ``inflation``; None without a keepout mask."""
    mask = world.masks.keepout
    if mask is None:
        return None
    origin = (static.origin_x, static.origin_y)
    shape = (static.size_y, static.size_x)
    layer = InflationLayer(inflation)
    return KeepoutFilter(mask, origin, static.resolution, shape, params, layer)


def speed_filter(world: World) -> SpeedFilter | None:
    """The world's speed filter, or None without a speed mask."""
    mask, settings = world.masks.speed, world.filters
    if mask is None or settings is None or settings.speed is None:
        return None
    info = settings.speed
    return SpeedFilter(mask, info.type, info.base, info.multiplier)
