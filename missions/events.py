"""Timed mission events: cancel, obstacles that appear or move, teleop input, and faults.

The run loop asks :class:`TimedEvents` for the next due time, advances the simulation exactly
there (rounded up to a physics step) and applies what is due. Obstacles go into the world's
movable mocap slots (``movable_0..3``, see :mod:`baobab.sim.builder`): the slot's box is
resized (``model.geom_size`` and the bounding radius ``geom_rbound`` that collision and
clearance culling read) and moved (``data.mocap_pos``/``mocap_quat``), so physics, the lidar
and clearance all see it from that step on. Teleop input is held in a :class:`TeleopChannel`
for ``duration`` seconds; the assisted-teleop capability reads it from there. Faults go to a
:class:`~baobab.missions.faults.FaultInjector`; a lasting one ends after its ``duration``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import mujoco
import numpy as np

from baobab.missions.schema import (
    CancelEvent,
    Event,
    FaultEvent,
    MoveObstacleEvent,
    PublishEvent,
    SpawnObstacleEvent,
    TeleopEvent,
)
from baobab.sim.builder import movable_slot_name
from baobab.sim.errors import BaobabError
from baobab.sim.simulation import Simulation
from baobab.sim.world import MOVABLE_SLOT_COUNT

if TYPE_CHECKING:
    from baobab.missions.faults import FaultInjector
    from baobab.nav.ros.mission_nodes import MissionNodes


class EventError(BaobabError):
    """An event cannot be applied to this run (no free obstacle slot, no mobile world)."""


TeleopListener = Callable[[tuple[float, float] | None], None]
"""Told the new teleop twist (m/s, rad/s), or None when the input ends."""


class TeleopChannel:
    """The teleop twist that events hold, for the assisted-teleop capability to read.

    ``twist`` is ``(linear m/s, angular rad/s)`` while a teleop event is active, else None.
    A reader (the navigation server's assisted teleop) polls it at its own rate; listeners
    registered with :meth:`subscribe` are also told of each change.
    """

    def __init__(self) -> None:
        self._twist: tuple[float, float] | None = None
        self._listeners: list[TeleopListener] = []

    @property
    def twist(self) -> tuple[float, float] | None:
        """The active command (m/s, rad/s), or None."""
        return self._twist

    def set(self, linear: float, angular: float) -> None:
        """Hold ``(linear, angular)`` (m/s, rad/s) until :meth:`clear`."""
        self._twist = (linear, angular)
        for listener in list(self._listeners):
            listener(self._twist)

    def clear(self) -> None:
        """No teleop input any more."""
        self._twist = None
        for listener in list(self._listeners):
            listener(None)

    def subscribe(self, listener: TeleopListener) -> None:
        """Call ``listener(twist_or_none)`` on every change."""
        self._listeners.append(listener)


@dataclass(frozen=True)
class PlacedObstacle:
    """A run-time obstacle where it stands now: centre (m), yaw (rad), full size (m), slot."""

    name: str
    slot: str
    x: float
    y: float
    yaw: float
    size: tuple[float, float, float]


class ObstacleSlots:
    """Places run-time box obstacles into the movable mocap slots of the model.

    Args:
        sim: a simulation whose model was built by :func:`~baobab.sim.builder.world_spec`.
    """

    def __init__(self, sim: Simulation) -> None:
        self.sim = sim
        self._free = [
            movable_slot_name(i)
            for i in range(MOVABLE_SLOT_COUNT)
            if mujoco.mj_name2id(sim.model, mujoco.mjtObj.mjOBJ_BODY, movable_slot_name(i)) >= 0
        ]
        self.placed: dict[str, PlacedObstacle] = {}
        """Obstacles placed so far, by name."""

    def spawn(
        self, name: str, x: float, y: float, yaw: float, size: Sequence[float]
    ) -> PlacedObstacle:
        """Put a new box of full ``size`` (m) at (x, y) (m) heading ``yaw`` (rad), on the floor.

        Raises:
            EventError: if the name is taken or every slot is in use.
        """
        if name in self.placed:
            raise EventError(f"obstacle '{name}' is already placed")
        if not self._free:
            raise EventError(f"no free obstacle slot for '{name}' (at most {MOVABLE_SLOT_COUNT})")
        slot = self._free.pop(0)
        sx, sy, sz = (float(v) for v in size)
        model = self.sim.model
        geom = model.geom(slot)
        half = np.array([sx, sy, sz]) / 2
        geom.size[:] = half
        model.geom_rbound[geom.id] = float(np.linalg.norm(half))
        return self._put(PlacedObstacle(name, slot, x, y, yaw, (sx, sy, sz)))

    def move(self, name: str, x: float, y: float, yaw: float | None) -> PlacedObstacle:
        """Move a placed obstacle to (x, y) (m); keep its heading when ``yaw`` is None.

        Raises:
            EventError: if no obstacle of that name was placed.
        """
        old = self.placed.get(name)
        if old is None:
            raise EventError(f"no obstacle '{name}' to move (spawn it first)")
        heading = old.yaw if yaw is None else yaw
        return self._put(PlacedObstacle(name, old.slot, x, y, heading, old.size))

    def _put(self, obstacle: PlacedObstacle) -> PlacedObstacle:
        model, data = self.sim.model, self.sim.data
        mocap = int(model.body(obstacle.slot).mocapid[0])
        data.mocap_pos[mocap] = [obstacle.x, obstacle.y, obstacle.size[2] / 2]
        data.mocap_quat[mocap] = [math.cos(obstacle.yaw / 2), 0.0, 0.0, math.sin(obstacle.yaw / 2)]
        self.sim.forward()
        self.placed[obstacle.name] = obstacle
        return obstacle


@dataclass(frozen=True)
class _Due:
    time: float
    order: int
    event: Event
    ends: bool = False
    """True for the end of a lasting event (teleop input, a fault with a duration)."""


class TimedEvents:
    """The mission's events in time order, applied by the run loop when they fall due.

    Args:
        events: the mission's events (any order; ties keep their file order).
        obstacles: where spawn and move events put obstacles (None for fixed robots).
        teleop: where teleop events put their command (None without teleop).
        faults: what injects fault events (None: a fault event raises EventError).
        ros: where publish events send their messages (None: a publish event raises
            EventError); every message is built and checked here, before the run.

    Raises:
        EventError: a publish event whose message type or fields do not fit.
    """

    def __init__(
        self,
        events: Sequence[Event],
        obstacles: ObstacleSlots | None,
        teleop: TeleopChannel | None,
        faults: FaultInjector | None = None,
        ros: MissionNodes | None = None,
    ) -> None:
        due = [_Due(event.at, index, event) for index, event in enumerate(events)]
        due += [
            _Due(event.at + event.duration, index, event, ends=True)
            for index, event in enumerate(events)
            if isinstance(event, TeleopEvent | FaultEvent) and event.duration is not None
        ]
        self._pending = sorted(due, key=lambda d: (d.time, d.ends is False, d.order))
        self.obstacles = obstacles
        self.teleop = teleop
        self.faults = faults
        self.ros = ros
        self._messages = {
            index: _message(index, event)
            for index, event in enumerate(events)
            if isinstance(event, PublishEvent) and ros is not None
        }
        self.canceled_by: CancelEvent | None = None
        """The cancel event that fired, if any."""

    def next_time(self) -> float | None:
        """When the next pending event falls due (s of sim time), or None."""
        return self._pending[0].time if self._pending else None

    def apply_due(self, now: float) -> list[dict[str, Any]]:
        """Apply every event due at or before ``now`` (s); returns one trace record each.

        Raises:
            EventError: if an obstacle event cannot be applied to this run.
        """
        records: list[dict[str, Any]] = []
        while self._pending and self._pending[0].time <= now + 1e-9:
            due = self._pending.pop(0)
            records.append(self._apply(due))
            if self.canceled_by is not None:
                break
        return records

    def _apply(self, due: _Due) -> dict[str, Any]:
        event = due.event
        record: dict[str, Any] = {"event_index": due.order, "at": event.at}
        if isinstance(event, CancelEvent):
            self.canceled_by = event
            return {"event": "cancel", **record}
        if isinstance(event, TeleopEvent):
            if self.teleop is None:
                raise EventError("teleop events need a robot with teleop")
            if due.ends:
                self.teleop.clear()
                return {"event": "teleop_end", **record}
            self.teleop.set(event.teleop.linear, event.teleop.angular)
            return {
                "event": "teleop",
                **record,
                "linear": event.teleop.linear,
                "angular": event.teleop.angular,
                "duration": event.duration,
            }
        if isinstance(event, FaultEvent):
            return self._fault(event, due.ends, record)
        if isinstance(event, PublishEvent):
            if self.ros is None:
                raise EventError("publish events need a run with ROS topics")
            self.ros.publish_at_once(_topic(event.publish.topic), self._messages[due.order])
            return {"event": "publish", **record, "topic": event.publish.topic}
        if self.obstacles is None:
            raise EventError("obstacle events need a mobile robot in a 2D world")
        if isinstance(event, SpawnObstacleEvent):
            spec = event.spawn_obstacle
            placed = self.obstacles.spawn(spec.name, spec.x, spec.y, spec.yaw, spec.size)
            kind = "spawn_obstacle"
        elif isinstance(event, MoveObstacleEvent):
            move = event.move_obstacle
            placed = self.obstacles.move(move.name, move.x, move.y, move.yaw)
            kind = "move_obstacle"
        else:  # pragma: no cover - the schema has no other kinds
            raise EventError(f"unknown event {event!r}")
        return {
            "event": kind,
            **record,
            "name": placed.name,
            "slot": placed.slot,
            "x": placed.x,
            "y": placed.y,
            "yaw": placed.yaw,
            "size": list(placed.size),
        }

    def _fault(self, event: FaultEvent, ends: bool, record: dict[str, Any]) -> dict[str, Any]:
        if self.faults is None:
            raise EventError("fault events need a robot that faults can be injected into")
        kind = event.fault.kind
        if ends:
            self.faults.end(event)
            return {"event": "fault_end", **record, "fault": kind}
        details = self.faults.start(event)
        return {"event": "fault", **record, "fault": kind, "duration": event.duration, **details}


def _topic(name: str) -> str:
    return name if name.startswith("/") else f"/{name}"


def _message(index: int, event: PublishEvent) -> Any:
    """The message of a publish event, built from its fields.

    Raises:
        EventError: an unknown message type, or fields that do not fit it.
    """
    from baobab.nav.ros import load_message_types
    from baobab.nav.rosmsg import MessageFieldError, fill_message, message_class

    load_message_types()
    spec = event.publish
    where = f"events[{index}].publish"
    try:
        message = message_class(spec.type)()
    except KeyError:
        raise EventError(f"{where}: unknown message type '{spec.type}'") from None
    try:
        return fill_message(message, spec.message)
    except MessageFieldError as exc:
        raise EventError(f"{where}.message: {exc}") from None
