"""A map_server map as Nav2's static layer reads it: occupancy values -> costs.

Nav2's ``StaticLayer`` turns each ``OccupancyGrid`` value ``v`` (read as unsigned: unknown -1
is 255) into a cost, in this order (reference/nav2_ros_facts.md §1):

1. ``v == unknown_cost_value`` -> NO_INFORMATION (255) with ``track_unknown_space``, else
   FREE (0);
2. ``v == inscribed_obstacle_cost_value`` (99) -> INSCRIBED (253);
3. ``v >= lethal_cost_threshold`` -> LETHAL (254);
4. ``trinary_costmap`` -> FREE;
5. otherwise ``trunc(v / lethal_cost_threshold * 254)``.

The costmap takes the map's cells as they are (Nav2 resizes a static costmap to the map): no
re-rasterisation of the walls the physics builds from it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from baobab.nav.costmap import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
)


@dataclass(frozen=True)
class StaticLayerParams:
    """How the static layer reads a map: Nav2's costmap defaults.

    Attributes:
        track_unknown_space: unknown cells stay unknown (255) instead of free.
        lethal_cost_threshold: occupancy value (0..100, clamped) from which a cell is lethal.
        unknown_cost_value: the (unsigned) occupancy value that means unknown.
        inscribed_obstacle_cost_value: the occupancy value read as an inscribed cost.
        trinary_costmap: values below the lethal threshold are free (else scaled to costs).
    """

    track_unknown_space: bool = False
    lethal_cost_threshold: int = 100
    unknown_cost_value: int = 255
    inscribed_obstacle_cost_value: int = 99
    trinary_costmap: bool = True


def map_costs(values: np.ndarray, params: StaticLayerParams | None = None) -> np.ndarray:
    """The static layer's cost (``uint8``) of each occupancy value (``int8``, -1..100)."""
    p = params or StaticLayerParams()
    v = values.astype(np.uint8)  # -1 reads as 255, as Nav2's unsigned char does
    lethal = min(max(int(p.lethal_cost_threshold), 0), 100)
    if p.trinary_costmap:
        below = np.zeros(v.shape, dtype=np.uint8)
    else:
        below = (v.astype(np.float64) / max(lethal, 1) * LETHAL_OBSTACLE).astype(np.uint8)
    costs = np.where(v >= lethal, np.uint8(LETHAL_OBSTACLE), below)
    costs = np.where(v == p.inscribed_obstacle_cost_value, INSCRIBED_INFLATED_OBSTACLE, costs)
    unknown = NO_INFORMATION if p.track_unknown_space else FREE_SPACE
    costs = np.where(v == p.unknown_cost_value, unknown, costs)
    return np.ascontiguousarray(costs, dtype=np.uint8)
