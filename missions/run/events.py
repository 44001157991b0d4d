"""Timed mission events: cancel, obstacles that appear or move, teleop input, faults, and
messages published on ROS topics.

The run loop asks :class:`TimedEvents` for the next due time, advances the simulation exactly
there (rounded up to a physics step) and applies what is due. Obstacles go into the world's
movable slots and teleop input into the rig's teleop channel
(:mod:`baobab.missions.run.event_targets`); teleop input is held for ``duration`` seconds.
Faults go to a :class:`~baobab.missions.run.faults.FaultInjector`; a lasting one ends after
its ``duration``. A published message goes to the run's ROS runtime
(:class:`~baobab.nav.ros.mission_nodes.MissionNodes`), for the nodes the tree runs.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from baobab.missions.language.models import (
    CancelEvent,
    Event,
    FaultEvent,
    MoveObstacleEvent,
    PublishEvent,
    SpawnObstacleEvent,
    TeleopEvent,
)
from baobab.missions.run.event_targets import EventError, ObstacleSlots, TeleopChannel
from baobab.missions.run.faults import FaultInjector

if TYPE_CHECKING:
    from baobab.nav.ros.mission_nodes import MissionNodes

__all__ = ["EventError", "TimedEvents"]


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
