"""Run metrics: a small registry, and the probes that measure a robot inside sim callbacks.

A metric is a name, a unit and a function that reads its value at the end of the run; the
``metrics:`` bounds of an ``expect:`` block may name any metric whose value is a number. The
probes sample in periodic sim callbacks, so every figure is a function of the sim alone:

- :class:`MobileProbe`: ground-truth path length (50 Hz), minimum clearance of the footprint
  to any obstacle (20 Hz, ``mj_geomDistance`` on the obstacles its bounds cannot rule out),
  robot-obstacle contacts (100 Hz, from one contact sensor per obstacle geom), locations
  entered in order, start and final pose. Positions and contacts are sampled by the base's
  compiled loop inside the physics step (:meth:`DiffDriveBase.start_probe`) and taken in
  here every :data:`DRAIN_PERIOD` and before any read.
- :class:`ArmProbe`: the tool path, and for each free object of the scene its highest lift
  above its start and its final position (100 Hz); contacts of the arm with the world's own
  geoms, the table and the floor (every physics step, from ``data.contact``; the grasped
  object is a free body, so holding it is no contact).
"""

from __future__ import annotations

import functools
import math
from array import array
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from baobab.robots.turtlebot3.base import DiffDriveBase
from baobab.sim.errors import BaobabError
from baobab.sim.simulation import Simulation

MetricValue = float | int | str | bool | list[Any] | dict[str, Any] | None
"""A metric's value: a number, or structured data (poses, lists of names); None if unknown."""

VISIT_RADIUS = 0.3
"""A location counts as visited when the robot comes within this distance (m)."""
CLEARANCE_RANGE = 2.0
"""Obstacles farther than this (m) are not measured; no closer obstacle reads as None."""
DRAIN_PERIOD = 1.0
"""How often (s of sim time) a mobile probe takes in the samples of the compiled loop."""


class MetricError(BaobabError):
    """A metric name registered twice."""


@dataclass(frozen=True)
class Metric:
    """One registered metric.

    Attributes:
        name: the key in ``metrics`` of result.json and in ``expect: metrics:``.
        read: returns the value (called when the run ends).
        unit: SI unit, or ``""``.
        description: one line.
        number: True when the value is a number (or None when not measured), so that
            ``expect: metrics:`` can bound it; False for structured data (poses, names).
    """

    name: str
    read: Callable[[], MetricValue]
    unit: str = ""
    description: str = ""
    number: bool = True


class MetricRegistry:
    """The metrics of one run, by name, in registration order."""

    def __init__(self) -> None:
        self._metrics: dict[str, Metric] = {}

    def add(
        self,
        name: str,
        read: Callable[[], MetricValue],
        *,
        unit: str = "",
        description: str = "",
        number: bool = True,
    ) -> None:
        """Register a metric (see :class:`Metric` for the arguments).

        Raises:
            MetricError: if ``name`` is taken.
        """
        if name in self._metrics:
            raise MetricError(f"metric '{name}' is registered twice")
        self._metrics[name] = Metric(name, read, unit, description, number)

    def __contains__(self, name: object) -> bool:
        return name in self._metrics

    def names(self) -> list[str]:
        """Registered names, in order."""
        return list(self._metrics)

    def number_names(self) -> list[str]:
        """Names of the metrics whose values are numbers (the ones bounds may name)."""
        return [name for name, metric in self._metrics.items() if metric.number]

    def values(self) -> dict[str, MetricValue]:
        """Every metric's current value."""
        return {name: metric.read() for name, metric in self._metrics.items()}

    def units(self) -> dict[str, str]:
        """Each metric's unit."""
        return {name: metric.unit for name, metric in self._metrics.items()}


def numeric(value: MetricValue) -> float | None:
    """``value`` as a float when it is a number (not a bool), else None."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value)


class ContactSampler:
    """Counts the sampled steps in which a geom of one set touches a geom of another.

    Args:
        sim: the simulation whose ``data.contact`` is read.
        mine: per geom id, True for the geoms whose contacts count (the robot's).
        others: per geom id, True for the geoms they must not touch.
    """

    def __init__(self, sim: Simulation, mine: Sequence[bool], others: Sequence[bool]) -> None:
        self.sim = sim
        # Plain lists: for the few contacts of a step, list lookups beat numpy masks.
        self._mine = list(mine)
        self._others = list(others)
        self.samples = 0
        """Samples with at least one such contact."""
        self.objects: set[str] = set()
        """Names of the geoms that were touched."""

    def sample(self, _now: float) -> None:
        """Look at the current contacts once (a periodic sim callback)."""
        data = self.sim.data
        if data.ncon == 0:
            return
        touched = False
        mine, others = self._mine, self._others
        for first, second in data.contact.geom[: data.ncon].tolist():
            if mine[first] and others[second]:
                other = second
            elif mine[second] and others[first]:
                other = first
            else:
                continue
            touched = True
            self.objects.add(self.sim.model.geom(other).name)
        if touched:
            self.samples += 1


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
        rows = self._samples.drain()
        if not rows:
            return
        for now, x, y in rows:
            if self._xs:
                self._path_length += math.hypot(x - self._xs[-1], y - self._ys[-1])
            self._times.append(now)
            self._xs.append(x)
            self._ys.append(y)
        radius = self.visit_radius
        entered: list[tuple[float, str]] = []
        _, xs, ys = zip(*rows, strict=True)
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
            for now, x, y in rows:
                inside = math.hypot(lx - x, ly - y) <= radius
                if inside and not self._inside[index]:
                    entered.append((now, name))
                self._inside[index] = inside
        entered.sort(key=lambda visit: visit[0])  # stable: same time, location order
        self._visits.extend(entered)

    def _sample_clearance(self, now: float) -> None:
        clearance = self.base.min_clearance(CLEARANCE_RANGE)
        if clearance < self.min_clearance:
            self.min_clearance = clearance
            self.min_clearance_at = (now, float(self._root_qpos[0]), float(self._root_qpos[1]))


class ArmProbe:
    """Measures an arm scene from sim callbacks: the tool path, the free objects, and the
    arm's contacts with the world body's geoms (the table and the floor).

    Args:
        sim: the simulation.
        tcp_position: returns the tool centre point (m, world frame).
        objects: names of the free bodies to follow (e.g. ``cube``).
        robot_prefix: name prefix of the arm's bodies; their geoms touching a geom of the
            world body count as contacts.
        period: sampling period of the tool and objects (s).
        contact_period: sampling period of the contacts (s); default: every physics step.
        contact_count: when given, the exact number of physics steps with an arm-world
            contact so far (the arm's own contact sensor); it is the ``contacts`` metric, and
            the contacts are then only sampled every ``contact_period`` for the names of what
            was touched.
    """

    def __init__(
        self,
        sim: Simulation,
        tcp_position: Callable[[], Sequence[float]],
        objects: Sequence[str],
        *,
        robot_prefix: str,
        period: float = 0.01,
        contact_period: float | None = None,
        contact_count: Callable[[], int] | None = None,
    ) -> None:
        self.sim = sim
        self._contact_count = contact_count
        self._tcp_position = tcp_position
        self.objects = list(objects)
        model = sim.model
        body_names = [model.body(int(b)).name for b in model.geom_bodyid]
        is_arm = [name.startswith(robot_prefix) for name in body_names]
        if not any(is_arm):
            raise BaobabError(f"the scene has no bodies named '{robot_prefix}...'")
        self.contacts = ContactSampler(
            sim, mine=is_arm, others=[int(b) == 0 for b in model.geom_bodyid]
        )
        self._bodies = [sim.data.body(name) for name in self.objects]
        self.object_start = {
            n: b.xpos.copy() for n, b in zip(self.objects, self._bodies, strict=True)
        }
        self.max_lift = dict.fromkeys(self.objects, 0.0)
        self.tcp_path: list[tuple[float, float, float]] = []
        self.object_paths: dict[str, list[tuple[float, float, float]]] = {
            n: [] for n in self.objects
        }
        self.tcp_path_length = 0.0
        self.contact_period = sim.physics_dt if contact_period is None else contact_period
        sim.every(period, self._sample, name="metrics arm")
        sim.every(self.contact_period, self.contacts.sample, name="metrics arm contacts")

    def register(self, metrics: MetricRegistry, place_target: Sequence[float] | None) -> None:
        """Add this probe's metrics; ``placement_error`` when the scene has a place target."""
        metrics.add(
            "tcp_path_length",
            lambda: self.tcp_path_length,
            unit="m",
            description="distance travelled by the tool centre point",
        )
        metrics.add(
            "object_max_lift",
            lambda: max(self.max_lift.values(), default=0.0),
            unit="m",
            description="highest lift of any object above its start",
        )
        counted = self._contact_count
        if counted is not None:
            metrics.add(
                "contacts",
                counted,
                description="physics steps with an arm-table (or floor) contact",
            )
        else:
            metrics.add(
                "contacts",
                lambda: self.contacts.samples,
                description=(
                    f"{1 / self.contact_period:g} Hz samples with an arm-table (or floor) contact"
                ),
            )
        metrics.add(
            "contact_objects",
            lambda: sorted(self.contacts.objects),
            description="world geoms the arm touched",
            number=False,
        )
        for name in self.objects:
            metrics.add(
                f"{name}_max_lift",
                functools.partial(self.max_lift.__getitem__, name),
                unit="m",
                description=f"highest lift of {name} above its start",
            )
            metrics.add(
                f"{name}_final_position",
                functools.partial(self.position, name),
                unit="m",
                number=False,
            )
        if place_target is not None and self.objects:
            target = np.asarray(place_target, dtype=float)
            first = self.objects[0]
            metrics.add(
                "placement_error",
                lambda: float(np.linalg.norm(np.asarray(self.position(first))[:2] - target[:2])),
                unit="m",
                description=f"horizontal distance from {first} to the scene's place target",
            )

    def position(self, name: str) -> list[float]:
        """An object's current position (m)."""
        return [float(v) for v in self.sim.data.body(name).xpos]

    def _sample(self, _now: float) -> None:
        tcp = tuple(float(v) for v in self._tcp_position())
        if self.tcp_path:
            self.tcp_path_length += math.dist(tcp, self.tcp_path[-1])
        self.tcp_path.append((tcp[0], tcp[1], tcp[2]))
        for name, body in zip(self.objects, self._bodies, strict=True):
            x, y, z = (float(v) for v in body.xpos)
            self.object_paths[name].append((x, y, z))
            lift = z - float(self.object_start[name][2])
            if lift > self.max_lift[name]:
                self.max_lift[name] = lift


class TrackingProbe:
    """How closely the tool follows its set-point: both positions, sampled at a modest rate.

    The set-point is what the Cartesian impedance controller is told to reach at that moment
    (the trajectory sample); the distance to it is the tracking error plotted for arm runs.

    Args:
        sim: the simulation.
        read: returns (tool centre point, set-point) positions (m, world frame).
        period: sampling period (s).
    """

    def __init__(
        self,
        sim: Simulation,
        read: Callable[[], tuple[Sequence[float] | np.ndarray, Sequence[float] | np.ndarray]],
        *,
        period: float = 0.02,
    ) -> None:
        self._read = read
        self.times: list[float] = []
        self.tcp: list[tuple[float, float, float]] = []
        self.setpoint: list[tuple[float, float, float]] = []
        self.errors: list[float] = []
        """Distance (m) from the tool to the set-point at each sample."""
        sim.every(period, self._sample, name="metrics tracking")

    def register(self, metrics: MetricRegistry) -> None:
        """Add ``max_tracking_error``."""
        metrics.add(
            "max_tracking_error",
            lambda: max(self.errors, default=0.0),
            unit="m",
            description="largest sampled distance from the tool to its impedance set-point",
        )

    def _sample(self, now: float) -> None:
        tcp, setpoint = self._read()
        a = (float(tcp[0]), float(tcp[1]), float(tcp[2]))
        b = (float(setpoint[0]), float(setpoint[1]), float(setpoint[2]))
        self.times.append(now)
        self.tcp.append(a)
        self.setpoint.append(b)
        self.errors.append(math.dist(a, b))


class TeleopTotals(Protocol):
    """What assisted teleop counts (``baobab.nav.behaviors.AssistedTeleopStats``)."""

    min_scaling: float | None
    slowed_cycles: int
    max_linear: float
    costmap_clears: int


def register_teleop_metrics(
    metrics: MetricRegistry, totals: Callable[[], TeleopTotals | None]
) -> None:
    """Add the assisted teleop metrics; ``totals()`` is None when the robot has no teleop."""

    def read(name: str) -> MetricValue:
        found = totals()
        return None if found is None else getattr(found, name)

    for metric, attribute, unit, description in (
        (
            "teleop_min_scaling",
            "min_scaling",
            "",
            "smallest factor assisted teleop applied to a teleop command (1: never slowed, "
            "0: stopped); null without one",
        ),
        (
            "teleop_slowed_cycles",
            "slowed_cycles",
            "",
            "assisted teleop cycles that scaled the command by a factor between 0 and 1",
        ),
        ("teleop_max_speed", "max_linear", "m/s", "largest forward speed assisted teleop sent"),
        ("teleop_costmap_clears", "costmap_clears", "", "costmap clearings by assisted teleop"),
    ):
        metrics.add(metric, functools.partial(read, attribute), unit=unit, description=description)


def _pose_dict(pose: tuple[float, float, float]) -> dict[str, float]:
    return {"x": pose[0], "y": pose[1], "yaw": pose[2]}
