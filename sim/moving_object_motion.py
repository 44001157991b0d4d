"""Moving objects in a running simulation: mocap cylinders moved along their scripts.

Each of the world's moving objects is a mocap body (:func:`moving_object_body`) holding one
cylinder geom in ``MOVABLE_GROUP``, so the lidar sees it and the robot bumps into it (a mocap
body is immovable: it pushes, it is not pushed). :class:`MovingObjects` moves every body to
where its :class:`~baobab.sim.moving_objects.Script` says at every
:data:`MOTION_PERIOD`; :meth:`MovingObjects.walk` gives an object a new route from where it
stands (a mission event).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from baobab.sim.moving_objects import MovingObject, Script, Waypoint
from baobab.sim.simulation import PeriodicHandle, Simulation
from baobab.sim.world import Pose2D, World

MOTION_PERIOD = 0.02
"""s between two moves of the objects: 6 mm at a brisk 0.3 m/s walk."""
BODY_PREFIX = "moving/"


def moving_object_body(name: str) -> str:
    """Name of the mocap body (and its geom) of the moving object ``name``."""
    return f"{BODY_PREFIX}{name}"


def moving_object_pose(sim: Simulation, name: str) -> Pose2D:
    """Where the moving object ``name``'s body stands in ``sim`` now (m, rad).

    Raises:
        KeyError: the model has no moving object ``name``.
    """
    try:
        body = sim.model.body(moving_object_body(name))
    except KeyError:
        raise KeyError(f"no moving object '{name}' in the model") from None
    mocap = int(body.mocapid[0])
    x, y = (float(v) for v in sim.data.mocap_pos[mocap][:2])
    qw, _, _, qz = (float(v) for v in sim.data.mocap_quat[mocap])
    return Pose2D(x=x, y=y, yaw=math.remainder(2.0 * math.atan2(qz, qw), math.tau))


class MovingObjects:
    """Moves the world's moving objects in ``sim`` (built from ``world``) from now on.

    Args:
        sim: a simulation whose model was built by :func:`~baobab.sim.builder.world_spec`.
        world: the world it was built from.
    """

    def __init__(self, sim: Simulation, world: World) -> None:
        self._sim = sim
        self.objects = {item.name: item for item in world.moving_objects}
        self._scripts = {item.name: Script.of(item) for item in world.moving_objects}
        self._mocap = {
            name: int(sim.model.body(moving_object_body(name)).mocapid[0]) for name in self.objects
        }
        self._handle: PeriodicHandle | None = None
        if self.objects:
            self._move(sim.time)
            self._handle = sim.every(MOTION_PERIOD, self._move, name="moving objects")

    def pose(self, name: str) -> Pose2D:
        """Where the object ``name`` is by its script now (m, rad)."""
        x, y, yaw = self._scripts[name].pose(self._sim.time)
        return Pose2D(x=x, y=y, yaw=math.remainder(yaw, 2 * math.pi))

    def velocity(self, name: str) -> tuple[float, float]:
        """Its forward speed (m/s) and turn rate (rad/s) now."""
        return self._scripts[name].state(self._sim.time)[3:]

    def walk(self, name: str, waypoints: Sequence[tuple[float, float]], speed: float) -> None:
        """Send ``name`` from where it stands through ``waypoints`` (m) at ``speed`` (m/s).

        Raises:
            KeyError: no moving object is called ``name``.
        """
        here = self.pose(name)
        points = [Waypoint(x=here.x, y=here.y), *(Waypoint(x=x, y=y) for x, y in waypoints)]
        item = self.objects[name].model_copy(
            update={"waypoints": points, "speed": speed, "loop": False}
        )
        self._scripts[name] = Script.of(item, start_time=self._sim.time)

    def close(self) -> None:
        """Stop moving the objects (they stand where they are)."""
        if self._handle is not None:
            self._handle.cancel()
            self._handle = None

    def _move(self, now: float) -> None:
        data = self._sim.data
        for name, script in self._scripts.items():
            x, y, yaw = script.pose(now)
            mocap = self._mocap[name]
            data.mocap_pos[mocap] = [x, y, self.objects[name].height / 2]
            data.mocap_quat[mocap] = [math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)]


def start_moving_objects(sim: Simulation, world: World) -> MovingObjects | None:
    """Move ``world``'s moving objects in ``sim``; None when it has none."""
    return MovingObjects(sim, world) if world.moving_objects else None


__all__ = [
    "MOTION_PERIOD",
    "MovingObject",
    "MovingObjects",
    "moving_object_body",
    "moving_object_pose",
]
