"""Where timed events act: the world's movable obstacle slots and the teleop channel.

Obstacles go into the world's movable mocap slots (``movable_0..3``, see
:mod:`baobab.sim.builder`): the slot's box is resized (``model.geom_size``, and the bounding
radius ``geom_rbound`` and boxes ``geom_aabb`` and ``bvh_aabb`` that collision, ray and
clearance culling read, as MuJoCo compiles them for that size) and moved
(``data.mocap_pos``/``mocap_quat``), so physics, the lidar and clearance all see all of it from
that step on. Teleop input is held in a :class:`TeleopChannel`; the assisted-teleop capability
reads it from there. A rig provides both; :class:`~baobab.missions.run.events.TimedEvents`
fills them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import mujoco
import numpy as np

from baobab.missions.run.plot_data import PlacedObstacle
from baobab.sim.builder import movable_slot_name
from baobab.sim.errors import BaobabError
from baobab.sim.simulation import Simulation
from baobab.sim.world import MOVABLE_SLOT_COUNT


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
        # MuJoCo culls contacts and rays with the compiled bounding boxes too: the geom's own
        # and its body's bounding-volume root (the slot's body holds just this geom, centred).
        model.geom_aabb[geom.id, 3:] = half
        model.bvh_aabb[model.body_bvhadr[geom.bodyid[0]], 3:] = half
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
