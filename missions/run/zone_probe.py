"""What a mobile run measures against its world's costmap filter masks: keepout and speed zones.

Sampled from the ground truth every :data:`SAMPLE_PERIOD` (20 Hz), only on a world with masks:

- ``min_keepout_clearance`` (m): the smallest distance from the robot's footprint circle to a
  keepout zone, negative when the footprint reached into one (by that much). The zone is the
  mask's cells that Nav2's KeepoutFilter makes lethal (value 100); distances are exact, to
  the cells' squares.
- ``speed_limit_excess`` (m/s): the most the ground-truth forward speed exceeded the speed
  mask's limit (Nav2's SpeedFilter semantics; a percentage of the controller's
  ``desired_linear_vel``) wherever the robot's whole footprint lay under that limit, 0 when
  it never did. Where the footprint straddles a zone's edge the loosest limit under it
  counts, so the robot has the time Nav2 gives it to slow down: its centre enters the zone
  first, then the filter's next update (5 Hz) lowers the controller's speed.

Both are None on a world without the mask.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from baobab.missions.run.metrics import MetricRegistry
from baobab.missions.run.plot_data import ZoneImage
from baobab.robots.diff_drive.base import DiffDriveBase
from baobab.sim.map_geometry import signed_distance_to_cells
from baobab.sim.map_image import OCCUPIED
from baobab.sim.simulation import Simulation
from baobab.sim.world import World

if TYPE_CHECKING:
    from baobab.sim.occupancy_map import OccupancyMap
    from baobab.sim.world_map import SpeedSettings

SAMPLE_PERIOD = 0.05
"""How often (s of sim time) the zones are checked."""
MAX_PLOTTED_LIMITS = 6
"""The plot draws the zones of this many distinct speed limits, the slowest first."""


class ZoneProbe:
    """Measures the robot against the keepout and speed masks (see the module docstring).

    Args:
        sim: the simulation.
        base: the robot's base (ground-truth pose and speed).
        world: the world and its masks.
        footprint_radius: the robot's footprint circle (m).
        max_speed: the controller's top speed (m/s), what a percentage limit is a part of.
    """

    def __init__(
        self,
        sim: Simulation,
        base: DiffDriveBase,
        world: World,
        footprint_radius: float,
        max_speed: float,
    ) -> None:
        self.base = base
        self.radius = footprint_radius
        masks, filters = world.masks, world.filters
        self._keepout = None if masks.keepout is None else _KeepoutZone(masks.keepout)
        speed = None if filters is None else filters.speed
        self._speed = None
        if masks.speed is not None and speed is not None:
            self._speed = _SpeedZones(masks.speed, speed, footprint_radius, max_speed)
        self.speed_excess = -math.inf
        """The largest (forward speed - limit) of the samples under a limit (m/s)."""
        self.samples_under_limit = 0
        if self._keepout is not None or self._speed is not None:
            sim.every(SAMPLE_PERIOD, self._sample, name="metrics filter zones")

    def register(self, metrics: MetricRegistry) -> None:
        """Add this probe's metrics (None on a world without the mask)."""
        metrics.add(
            "min_keepout_clearance",
            self.keepout_clearance,
            unit="m",
            description="footprint to the nearest keepout zone (negative: inside); "
            "null without a keepout mask",
        )
        metrics.add(
            "speed_limit_excess",
            self.speed_limit_excess,
            unit="m/s",
            description="most the speed exceeded the speed mask's limit with the whole "
            "footprint under it; null without a speed mask",
        )

    def keepout_clearance(self) -> float | None:
        """Smallest footprint clearance (m) to a keepout zone; None without a keepout mask
        (or a zone in it)."""
        nearest = None if self._keepout is None else self._keepout.nearest()
        if nearest is None or math.isinf(nearest):
            return None
        return nearest - self.radius

    def speed_limit_excess(self) -> float | None:
        """Largest excess over a speed limit (m/s), 0 if never; None without a speed mask."""
        if self._speed is None:
            return None
        return max(self.speed_excess, 0.0)

    def zone_images(self) -> list[ZoneImage]:
        """The keepout zone and each speed limit's zone, for the plot."""
        images: list[ZoneImage] = []
        if self._keepout is not None and self._keepout.any:
            mask = self._keepout.mask
            cells = self._keepout.cells
            images.append(ZoneImage("keepout zone", cells, mask.origin, mask.resolution, True))
        if self._speed is not None:
            mask, limits = self._speed.mask, self._speed.limits
            for limit in np.unique(limits[np.isfinite(limits)]).tolist()[:MAX_PLOTTED_LIMITS]:
                label = f"speed limit {limit:.2f} m/s"
                images.append(
                    ZoneImage(label, limits == limit, mask.origin, mask.resolution, False)
                )
        return images

    def _sample(self, _now: float) -> None:
        pose = self.base.pose()
        if self._keepout is not None:
            self._keepout.add(pose.x, pose.y)
        if self._speed is not None:
            limit = self._speed.limit_at(pose.x, pose.y)
            if limit is None:
                return
            self.samples_under_limit += 1
            speed = abs(self.base.body_velocity()[0])
            self.speed_excess = max(self.speed_excess, speed - limit)


class _KeepoutZone:
    """A keepout mask's lethal cells and the robot's least signed distance to them.

    Exact distances cost a search of the mask, so samples are kept as candidates: each cell
    has a lower bound of the distance from any of its points to the zone (from cell-centre
    distance transforms), at most :data:`_SLACK` cells below the exact one. Only samples
    whose bound is within that slack of the least bound can hold the minimum; their exact
    distances are taken when the minimum is read.
    """

    def __init__(self, mask: OccupancyMap) -> None:
        from scipy.ndimage import distance_transform_edt

        self.mask = mask
        self.cells = mask.data == OCCUPIED
        self.any = bool(self.cells.any())
        if self.any:
            # From a point of a cell: the nearest zone square (or, inside the zone, the nearest
            # free square) is within (centres + sqrt(2)/2) cells and beyond (centres - sqrt 2).
            outside = distance_transform_edt(~self.cells) - math.sqrt(2)
            inside = -(distance_transform_edt(self.cells) + math.sqrt(2))
            self._lower = np.where(self.cells, inside, outside) * mask.resolution
        else:
            self._lower = np.full(self.cells.shape, np.inf)
        self._least = math.inf
        self._candidates: list[tuple[float, float, float]] = []
        """(lower bound m, x m, y m) of the samples that may be the nearest."""
        self._nearest: float | None = None

    def add(self, x: float, y: float) -> None:
        """Take the robot's position ``(x, y)`` (m) as a sample."""
        if not self.any:
            return
        cell = self.mask.cell(x, y)
        # Off the mask there is no bound: the exact distance stands in for it.
        lower = self._distance(x, y) if cell is None else float(self._lower[cell[1], cell[0]])
        slack = _SLACK * self.mask.resolution
        if lower > self._least + slack:
            return
        self._nearest = None
        self._candidates.append((lower, x, y))
        if lower < self._least:
            self._least = lower
            if len(self._candidates) > _MAX_CANDIDATES:
                limit = self._least + slack
                self._candidates = [c for c in self._candidates if c[0] <= limit]

    def nearest(self) -> float | None:
        """The least signed distance (m) from a sample to the zone; None before any."""
        if self._nearest is None and self._candidates:
            limit = self._least + _SLACK * self.mask.resolution
            self._nearest = min(
                self._distance(x, y) for lower, x, y in self._candidates if lower <= limit
            )
        return self._nearest

    def _distance(self, x: float, y: float) -> float:
        mask, cells = self.mask, 4
        cell = mask.cell(x, y)
        if cell is not None and not self.cells[cell[1], cell[0]]:
            # The nearest zone square lies within sqrt(2) cells of the nearest zone centre.
            lower = float(self._lower[cell[1], cell[0]]) / mask.resolution
            cells = math.ceil(lower + 2 * math.sqrt(2)) + 1
        return signed_distance_to_cells(self.cells, mask.origin, mask.resolution, x, y, cells)


_SLACK = 2 * math.sqrt(2)
"""Cells by which a keepout distance's lower bound may fall short of the exact distance."""
_MAX_CANDIDATES = 256
"""Candidate samples kept before those that can no longer be the nearest are dropped."""


class _SpeedZones:
    """Per mask cell, the loosest speed limit (m/s) a footprint over that cell's points meets."""

    def __init__(
        self, mask: OccupancyMap, info: SpeedSettings, radius: float, max_speed: float
    ) -> None:
        from scipy.ndimage import maximum_filter

        from baobab.nav.costmap_filters import SpeedFilter, applied_speed

        self.mask = mask
        speed_filter = SpeedFilter(mask, info.type, info.base, info.multiplier)
        limits = np.full(mask.data.shape, np.inf)
        self.limits = limits
        """The limit (m/s) of each mask cell, inf where there is none."""
        for value in np.unique(mask.data).tolist():
            limit = speed_filter.limit_of(int(value))
            if limit is not None and limit.speed_limit != 0.0:
                limits[mask.data == value] = applied_speed(limit, max_speed)
        # A footprint point is within radius + sqrt(2)/2 cell of its cell's centre, and the
        # centre of the robot's cell within sqrt(2)/2 cell of the robot: cells whose centres
        # lie within radius + sqrt(2) cells of the robot's cell cover every footprint point.
        reach = radius / mask.resolution + math.sqrt(2)
        span = math.floor(reach)
        offsets = np.arange(-span, span + 1)
        disk = offsets[:, None] ** 2 + offsets[None, :] ** 2 <= reach * reach
        self.loosest = maximum_filter(limits, footprint=disk, mode="constant", cval=np.inf)

    def limit_at(self, x: float, y: float) -> float | None:
        """The limit (m/s) on the whole footprint at ``(x, y)``, or None (no limit there)."""
        cell = self.mask.cell(x, y)
        if cell is None:
            return None
        limit = float(self.loosest[cell[1], cell[0]])
        return None if math.isinf(limit) else limit
