"""What a mobile base's run measures, from sim callbacks: path, clearance, contacts, visits.

Every figure is a function of the sim alone: ground-truth path length (50 Hz), minimum
clearance of the footprint to any obstacle (20 Hz, ``mj_geomDistance`` on the obstacles its
bounds cannot rule out), robot-obstacle contacts (100 Hz, from one contact sensor per obstacle
geom; a map's walls count as one obstacle, ``map_walls``), locations entered in order, start
and final pose. Positions and contacts are sampled by
the base's compiled loop inside the physics step (:meth:`DiffDriveBase.start_probe`) and taken
in here every :data:`DRAIN_PERIOD` and before any read.
"""

from __future__ import annotations

import math
from array import array
from collections.abc import Mapping, Sequence

from baobab.missions.run.metrics import MetricRegistry
from baobab.robots.diff_drive.base import DiffDriveBase
from baobab.sim.simulation import Simulation

VISIT_RADIUS = 0.3
"""A location counts as visited when the robot comes within this distance (m)."""
CLEARANCE_RANGE = 2.0
"""Obstacles farther than this (m) are not measured; no closer obstacle reads as None."""
DRAIN_PERIOD = 5.0
"""How often (s of sim time) a mobile probe takes in the samples of the compiled loop: 250
positions at a time (6 kB), as a drain costs about as much for one second's samples as for
five (its cost is mostly the call; the result does not depend on the period)."""


class MobileProbe:
    """Measures a mobile base from sim callbacks (see the module docstring).

    Args:
        sim: the simulation.
        base: the robot's base (ground-truth pose, clearance).
        locations: named points (m) whose visits are recorded.
        visit_radius: entering this distance (m) of a location counts as a visit.
        pose_period: path and visit sampling period (s).
        clearance_period: clearance sampling period (s).
        contact_period: contact sampling period (s).
    """

    def __init__(
        self,
        sim: Simulation,
        base: DiffDriveBase,
        locations: Mapping[str, tuple[float, float]],
        *,
        visit_radius: float = VISIT_RADIUS,
        pose_period: float = 0.02,
        clearance_period: float = 0.05,
        contact_period: float = 0.01,
    ) -> None:
        self.sim = sim
        self.base = base
        self.visit_radius = visit_radius
        self._locations = [(name, float(x), float(y)) for name, (x, y) in locations.items()]
        self._inside = [False] * len(self._locations)
        self._visits: list[tuple[float, str]] = []
        start = base.pose()
        self.start = (start.x, start.y, start.yaw)
        self._root_qpos = sim.data.joint(base.names.root_joint).qpos
        # 50 Hz for hours: packed doubles take a third of the memory of a list of floats.
        self._times = array("d")
        self._xs = array("d")
        self._ys = array("d")
        self._path_length = 0.0
        self.min_clearance = math.inf
        self.min_clearance_at: tuple[float, float, float] | None = None
        """(t, x, y) where the clearance was smallest."""
        # Positions and contacts are sampled compiled, inside the physics step; the samples
        # are taken in here at least every DRAIN_PERIOD.
        self._samples = base.start_probe(
            pose_period=pose_period, contact_period=contact_period, drain_period=DRAIN_PERIOD
        )
        sim.every(clearance_period, self._sample_clearance, name="metrics clearance")
        sim.every(DRAIN_PERIOD, self._drain, name="metrics drain")

    def register(self, metrics: MetricRegistry) -> None:
        """Add this probe's metrics."""
        metrics.add(
            "path_length",
            lambda: self.path_length,
            unit="m",
            description="ground-truth distance driven",
        )
        metrics.add(
            "straight_line_distance",
            self.straight_line_distance,
            unit="m",
            description="from the start to the final position",
        )
        metrics.add(
            "min_clearance",
            self.clearance,
            unit="m",
            description=f"footprint to nearest obstacle; null beyond {CLEARANCE_RANGE} m",
        )
        metrics.add(
            "contacts",
            lambda: self._samples.contact_samples,
            description="100 Hz samples with a robot-obstacle contact",
        )
        metrics.add(
            "contact_objects",
            lambda: sorted(self._samples.touched()),
            description="obstacles the robot touched",
            number=False,
        )
        metrics.add("start_pose", lambda: _pose_dict(self.start), unit="m, rad", number=False)
        metrics.add("final_pose", self.final_pose, unit="m, rad", number=False)
        metrics.add(
            "visited",
            lambda: [name for _, name in self.visits],
            description=f"locations entered within {self.visit_radius:g} m, in order",
            number=False,
        )

    def straight_line_distance(self) -> float:
        """Distance (m) from the start to the current position."""
        pose = self.base.pose()
        return math.hypot(pose.x - self.start[0], pose.y - self.start[1])

    def clearance(self) -> float | None:
        """Smallest sampled clearance (m), or None if no obstacle came within range."""
        return None if math.isinf(self.min_clearance) else self.min_clearance

    def final_pose(self) -> dict[str, float]:
        """The ground-truth pose now: ``{x, y, yaw}`` (m, rad)."""
        pose = self.base.pose()
        return _pose_dict((pose.x, pose.y, pose.yaw))

    @property
    def times(self) -> array[float]:
        """Sim times (s) of the position samples."""
        self._drain()
        return self._times

    @property
    def xs(self) -> array[float]:
        """Ground-truth x (m) of the position samples."""
        self._drain()
        return self._xs

    @property
    def ys(self) -> array[float]:
        """Ground-truth y (m) of the position samples."""
        self._drain()
        return self._ys

    @property
    def path_length(self) -> float:
        """Ground-truth distance driven so far (m), from the position samples."""
        self._drain()
        return self._path_length

    @property
    def visits(self) -> list[tuple[float, str]]:
        """(sim time s, location name) of every entry, in order."""
        self._drain()
        return self._visits

    def _drain(self, _now: float = 0.0) -> None:
        times, xs, ys = self._samples.drain_columns()
        if not times:
            return
        self._path_length = _path_length(self._path_length, self._xs, self._ys, xs, ys)
        self._times.extend(times)
        self._xs.extend(xs)
        self._ys.extend(ys)
        radius = self.visit_radius
        entered: list[tuple[float, str]] = []
        low_x, high_x, low_y, high_y = min(xs), max(xs), min(ys), max(ys)
        for index, (name, lx, ly) in enumerate(self._locations):
            # Float subtraction is monotonic and hypot(a, b) >= |a|: a location farther than
            # the radius along x or y from the batch's box is outside for every sample.
            if lx - high_x > radius or low_x - lx > radius or ly - high_y > radius:
                self._inside[index] = False
                continue
            if low_y - ly > radius:
                self._inside[index] = False
                continue
            was_inside = self._inside[index]
            for now, x, y in zip(times, xs, ys, strict=True):
                inside = math.hypot(lx - x, ly - y) <= radius
                if inside and not was_inside:
                    entered.append((now, name))
                was_inside = inside
            self._inside[index] = was_inside
        entered.sort(key=lambda visit: visit[0])  # stable: same time, location order
        self._visits.extend(entered)

    def _sample_clearance(self, now: float) -> None:
        # Only a clearance below the least so far counts: nearer obstacles alone are measured.
        clearance = self.base.min_clearance(CLEARANCE_RANGE, below=self.min_clearance)
        if clearance < self.min_clearance:
            self.min_clearance = clearance
            self.min_clearance_at = (now, float(self._root_qpos[0]), float(self._root_qpos[1]))


def _path_length(
    length: float,
    old_xs: Sequence[float],
    old_ys: Sequence[float],
    xs: Sequence[float],
    ys: Sequence[float],
) -> float:
    """``length`` (m) plus the polyline from the last old point through the new ones, each
    step added in order (the first point ever starts the line)."""
    if old_xs:
        last_x, last_y = old_xs[-1], old_ys[-1]
        start = 0
    else:
        last_x, last_y = xs[0], ys[0]
        start = 1
    hypot = math.hypot
    for x, y in zip(xs[start:], ys[start:], strict=True):
        length += hypot(x - last_x, y - last_y)
        last_x, last_y = x, y
    return length


def _pose_dict(pose: tuple[float, float, float]) -> dict[str, float]:
    return {"x": pose[0], "y": pose[1], "yaw": pose[2]}
