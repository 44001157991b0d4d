"""What an arm's run measures, from sim callbacks: the tool path, lifts, contacts, tracking.

The tool path, and for each free object of the scene its highest lift above its start and its
final position (100 Hz); contacts of the arm with the world's own geoms, the table and the
floor (every physics step, from ``data.contact``; the grasped object is a free body, so holding
it is no contact); the distance from the tool to the impedance controller's set-point.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence

import numpy as np

from baobab.missions.run.metrics import MetricRegistry
from baobab.sim.errors import BaobabError
from baobab.sim.simulation import Simulation


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
