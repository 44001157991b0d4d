"""A chase camera: one pose a frame, behind a moving body and above whatever would hide it.

The camera looks at a point ``lead`` ahead of the centre of mass of the body's subtree, from
``distance`` behind that point. Its
azimuth swings round behind the body's heading with a first-order lag, never faster than
``max_turn_rate``: the view looks where the body is going, and a turn on the spot does not
whirl it round.

Occluders are seen coming. Each frame casts MuJoCo's ray
(:class:`~baobab.sim.camera.LineOfSight`) to the body's centre and to its lowest point, to
where its velocity takes it within ``lookahead``, and from where the camera is swinging to;
the camera eases up (at most ``max_rise_rate``) to the lowest elevation from which all of
these are clear, and back down once they are. The body's centre shows in every frame: when
the eased pose would not see it, the camera jumps to the lowest pose that does, higher up to
straight down and then closer.

It rises rather than making occluders transparent: the world stays drawn as it is, so a video
shows what the robot is between (a wall it passes is still a wall), and the view from above
is the one a person would take to see a robot among walls.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from baobab.sim.camera import ALL_GEOM_GROUPS, CameraPose, LineOfSight, geom_box_corners

_ELEVATION_STEP = 5.0
"""Spacing (deg) of the elevations tried when a view is blocked."""
_STEEPEST = -89.0
"""The highest the camera goes (deg): straight down, short of MuJoCo's singular -90."""
_PULL_IN = (0.7, 0.5, 0.35, 0.25)
"""Fractions of ``distance`` tried from straight above when no elevation sees the body."""
_FEET_CLEARANCE = 0.02
"""How far above the body's lowest point the camera tries to see it too (m)."""


@dataclass(frozen=True)
class ChaseCamera:
    """How a chase camera follows a body (see the module docstring).

    Attributes:
        body: name of the body to follow (e.g. ``robot/base_link``).
        distance: from the camera to the look-at point (m).
        lead: how far ahead of the body the look-at point is, along the view (m): the body
            sits below the frame's centre and the frame shows more of the way ahead.
        elevation: the camera's lowest angle, looking down at the body (deg, negative).
        lag: time constant of the swing round behind the body's heading (s).
        max_turn_rate: fastest swing round (deg/s).
        max_rise_rate: fastest rise ahead of an occluder, and settling back (deg/s).
        lookahead: how far ahead along the body's velocity occluders are looked for (s).
    """

    body: str
    distance: float = 2.5
    lead: float = 0.5
    elevation: float = -30.0
    lag: float = 0.7
    max_turn_rate: float = 90.0
    max_rise_rate: float = 45.0
    lookahead: float = 1.0


class ChaseOperator:
    """Poses a :class:`ChaseCamera` frame after frame; call :meth:`pose` in time order.

    Args:
        model: the compiled model.
        camera: how to follow.
        geom_groups: the geom groups drawn (only these hide the body).

    Raises:
        RenderingError: for a body the model does not have.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        camera: ChaseCamera,
        geom_groups: tuple[int, ...] = ALL_GEOM_GROUPS,
    ) -> None:
        self.camera = camera
        self.sight = LineOfSight(model, camera.body, geom_groups)
        count = int((camera.elevation - _STEEPEST) // _ELEVATION_STEP) + 1
        elevations = [camera.elevation - k * _ELEVATION_STEP for k in range(count)]
        self._elevations = [*elevations, _STEEPEST] if elevations[-1] > _STEEPEST else elevations
        self._own = [g for g in range(model.ngeom) if self.sight.owns(g)]
        self._feet_drop = 0.0
        self._time: float | None = None
        self._target = np.zeros(3)
        self._azimuth = 0.0
        self._elevation = camera.elevation

    def pose(self, data: mujoco.MjData, time: float) -> CameraPose:
        """The pose for the frame of ``data``'s state at sim time ``time`` (s)."""
        body = self.sight.body_id
        target = data.subtree_com[body].copy()
        axis = data.xmat[body]  # row-major rotation: its first column is the body's x axis
        heading = math.degrees(math.atan2(axis[3], axis[0]))
        first = self._time is None
        if self._time is None:  # straight behind the body, as high as needed
            self._azimuth = heading
            lowest = geom_box_corners(self.sight.model, data, self._own)[:, 2].min()
            self._feet_drop = target[2] - lowest
            dt, velocity = 0.0, np.zeros(3)
        else:
            dt = time - self._time
            velocity = (target - self._target) / dt if dt > 0.0 else np.zeros(3)
            self._swing(heading, dt)
        wanted = self._wanted_elevation(data, target, velocity, heading)
        rise = _clamp(wanted - self._elevation, self.camera.max_rise_rate * dt)
        eased = wanted if first else self._elevation + rise
        pose = self._seeing(data, target, eased)
        self._time, self._target, self._elevation = time, target, pose.elevation
        return pose

    def _swing(self, heading: float, dt: float) -> None:
        """Turn the azimuth towards ``heading`` (deg) over ``dt`` (s): first-order lag, capped."""
        camera = self.camera
        swing = math.remainder(heading - self._azimuth, 360.0) * -math.expm1(-dt / camera.lag)
        turned = self._azimuth + _clamp(swing, camera.max_turn_rate * dt)
        self._azimuth = math.remainder(turned, 360.0)

    def _at(
        self, point: np.ndarray, elevation: float, distance: float, azimuth: float | None = None
    ) -> CameraPose:
        """The pose that sees ``point`` (m) from ``distance`` (m), its look-at point ahead."""
        azimuth = self._azimuth if azimuth is None else azimuth
        lead = self.camera.lead * distance / self.camera.distance  # closer: less ahead
        x, y, z = (float(v) for v in point)
        lookat = (
            x + lead * math.cos(math.radians(azimuth)),
            y + lead * math.sin(math.radians(azimuth)),
            z,
        )
        return CameraPose(lookat, distance, azimuth, elevation)

    def _lowest_clear(
        self, data: mujoco.MjData, point: np.ndarray, azimuth: float | None = None
    ) -> float | None:
        """The lowest elevation (deg) from which ``point`` is in sight, None if none is."""
        distance = self.camera.distance
        for elevation in self._elevations:
            if self.sight.clear(data, self._at(point, elevation, distance, azimuth).eye, point):
                return elevation
        return None

    def _wanted_elevation(
        self, data: mujoco.MjData, target: np.ndarray, velocity: np.ndarray, heading: float
    ) -> float:
        """The lowest elevation (deg) that sees the body now, along its way ahead, and from
        behind its heading (where the camera is swinging to)."""
        wanted = self._lowest_clear(data, target)
        if wanted is None:
            return _STEEPEST
        lookahead = self.camera.lookahead
        feet = target - np.array([0.0, 0.0, self._feet_drop - _FEET_CLEARANCE])
        more = [
            self._lowest_clear(data, feet),
            self._lowest_clear(data, target + velocity * (0.5 * lookahead)),
            self._lowest_clear(data, target + velocity * lookahead),
            self._lowest_clear(data, target, heading),
        ]
        # A point inside an obstacle is seen from nowhere: it says nothing, skip it.
        return min([wanted, *(e for e in more if e is not None)])

    def _seeing(self, data: mujoco.MjData, target: np.ndarray, elevation: float) -> CameraPose:
        """The pose at ``elevation`` if it sees the body, else the lowest above it that does."""
        distance = self.camera.distance
        steeper = [(e, distance) for e in self._elevations if e < elevation]
        closer = [(_STEEPEST, distance * fraction) for fraction in _PULL_IN]
        for elevation_, distance_ in [(elevation, distance), *steeper, *closer]:
            pose = self._at(target, elevation_, distance_)
            if self.sight.clear(data, pose.eye, target):
                return pose
        return pose  # nothing sees it (it is under a roof): the closest from above


def _clamp(value: float, limit: float) -> float:
    """``value`` limited to ``[-limit, limit]``."""
    return min(limit, max(-limit, value))
