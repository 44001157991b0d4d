"""Camera poses: where MuJoCo's free camera stands, what it sees, and a pose that frames a scene.

A :class:`CameraPose` is what MuJoCo's free camera (``mjCAMERA_FREE``) is set from: a look-at
point, a distance, an azimuth and an elevation. Its eye and axes follow ``mjv_updateCamera``
(forward ``(cos el cos az, cos el sin az, sin el)``, the eye ``distance`` behind the look-at
point), so what is computed here is what the renderer shows.

:func:`framing` computes a fixed pose once, before filming: the one that looks along a given
direction and fits a set of points in the frame. :class:`LineOfSight` asks MuJoCo's ray cast
(``mj_ray``) whether anything but a body's own geoms stands between an eye and a point; the
per-frame chase camera (:mod:`baobab.sim.chase_camera`) uses it to keep the body in view.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import mujoco
import numpy as np

from baobab.sim.errors import RenderingError

ALL_GEOM_GROUPS = (0, 1, 2, 3, 4, 5)
"""MuJoCo's six geom groups: videos draw them all, so robots (often group 3) show."""


@dataclass(frozen=True)
class CameraPose:
    """A free camera looking at ``lookat`` (m) from ``distance`` (m), ``azimuth`` and ``elevation``.

    Attributes:
        lookat: the point at the centre of the frame (m, world frame).
        distance: from the eye to ``lookat`` (m).
        azimuth: heading of the viewing direction around the vertical (deg, 0 looks along +x).
        elevation: angle of the viewing direction above the horizontal (deg, negative: down).
    """

    lookat: tuple[float, float, float]
    distance: float
    azimuth: float
    elevation: float

    def axes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Unit vectors forward, right and up of the view (world frame), as MuJoCo sets them."""
        azimuth, elevation = math.radians(self.azimuth), math.radians(self.elevation)
        ca, sa = math.cos(azimuth), math.sin(azimuth)
        ce, se = math.cos(elevation), math.sin(elevation)
        forward = np.array([ce * ca, ce * sa, se])
        right = np.array([sa, -ca, 0.0])  # forward x up
        up = np.array([-se * ca, -se * sa, ce])
        return forward, right, up

    @property
    def eye(self) -> np.ndarray:
        """Where the camera stands (m, world frame)."""
        azimuth, elevation = math.radians(self.azimuth), math.radians(self.elevation)
        reach = self.distance * math.cos(elevation)
        x, y, z = self.lookat
        return np.array(
            [
                x - reach * math.cos(azimuth),
                y - reach * math.sin(azimuth),
                z - self.distance * math.sin(elevation),
            ]
        )

    def project(self, points: np.ndarray, fovy: float, aspect: float) -> np.ndarray:
        """Image coordinates of world points (N, 3) (m): (N, 2), -1..1 across the frame.

        x grows to the right, y upwards; a point behind the eye gets NaN.

        Args:
            points: world points (m).
            fovy: vertical field of view (deg), MuJoCo's ``vis.global_.fovy``.
            aspect: frame width over height.
        """
        forward, right, up = self.axes()
        relative = np.atleast_2d(np.asarray(points, dtype=float)) - self.eye
        depth = relative @ forward
        depth = np.where(depth > 0.0, depth, np.nan)
        half_height = math.tan(math.radians(fovy) / 2.0)
        x = relative @ right / (depth * half_height * aspect)
        y = relative @ up / (depth * half_height)
        return np.stack([x, y], axis=1)


class CameraOperator(Protocol):
    """Decides the camera pose of each frame."""

    def pose(self, data: mujoco.MjData, time: float) -> CameraPose:
        """The pose for the frame of ``data``'s state at sim time ``time`` (s)."""
        ...


@dataclass(frozen=True)
class StillOperator:
    """A camera that never moves: every frame has the same pose, computed beforehand."""

    fixed: CameraPose

    def pose(self, data: mujoco.MjData, time: float) -> CameraPose:
        """The fixed pose."""
        return self.fixed


def framing(
    points: np.ndarray,
    *,
    azimuth: float,
    elevation: float,
    fovy: float,
    aspect: float,
    margin: float = 0.05,
) -> CameraPose:
    """The pose looking along ``azimuth``/``elevation`` (deg) that fits ``points`` in the frame.

    The points (N, 3) (m) fill the frame along its tighter axis, ``margin`` (a fraction of the
    half frame) left at each edge, and are centred along the other. For a fixed viewing
    direction every point bounds the eye's position linearly, which gives the distance in
    closed form; the sideways offsets that centre the points are found by bisection.

    Args:
        points: world points (m) that must be in view.
        azimuth: heading of the view (deg).
        elevation: angle of the view above the horizontal (deg).
        fovy: vertical field of view (deg).
        aspect: frame width over height.
        margin: free fraction of the half frame at the edges, 0 to 0.5.
    """
    if len(points) == 0:
        raise RenderingError("cannot frame an empty set of points")
    probe = CameraPose((0.0, 0.0, 0.0), 1.0, azimuth, elevation)
    forward, right, up = probe.axes()
    points = np.asarray(points, dtype=float)
    along = points @ forward
    half_height = math.tan(math.radians(fovy) / 2.0) * (1.0 - margin)
    # A point is in view when |side - eye_side| <= slope * (along - eye_along) on each axis.
    slopes = ((points @ right, half_height * aspect), (points @ up, half_height))
    back = max(
        0.5 * (np.max(side / slope - along) - np.min(side / slope + along))
        for side, slope in slopes
    )
    eye_along = -back  # the eye stands ``back`` behind the origin along ``forward``
    depth = along - eye_along
    centre = [_centred(side, slope * depth) for side, slope in slopes]
    eye = eye_along * forward + centre[0] * right + centre[1] * up
    distance = float(np.mean(along) - eye_along)
    lookat = eye + distance * forward
    return CameraPose(
        (float(lookat[0]), float(lookat[1]), float(lookat[2])), distance, azimuth, elevation
    )


def _centred(side: np.ndarray, room: np.ndarray) -> float:
    """The eye's offset along one image axis that centres points there.

    ``side`` is each point's offset along the axis and ``room`` its half width of view at its
    depth (m); a point's image coordinate is ``(side - eye) / room``. The sum of the largest
    and the smallest image coordinates falls as the eye moves: bisect it to zero.
    """
    low, high = float(np.min(side - room)), float(np.max(side + room))
    for _ in range(60):
        eye = 0.5 * (low + high)
        image = (side - eye) / room
        low, high = (eye, high) if image.max() + image.min() > 0.0 else (low, eye)
    return 0.5 * (low + high)


def geom_box_corners(model: mujoco.MjModel, data: mujoco.MjData, geoms: list[int]) -> np.ndarray:
    """The 8 corners of each geom's bounding box in the world (8 * len(geoms), 3) (m).

    A plane's box is its drawn size; use ``data``'s current kinematics.
    """
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    corners = []
    for geom in geoms:
        centre, half = model.geom_aabb[geom, :3], model.geom_aabb[geom, 3:]
        local = centre + signs * half
        rotation = data.geom_xmat[geom].reshape(3, 3)
        corners.append(data.geom_xpos[geom] + local @ rotation.T)
    return np.concatenate(corners) if corners else np.empty((0, 3))


class LineOfSight:
    """Whether a body shows from an eye or another geom hides it (MuJoCo's ``mj_ray``).

    The sight line from the eye to a point is cast as MuJoCo's ray: it stops at the first geom
    in ``geom_groups`` whose colour is not fully transparent (what the renderer draws). A hit
    on any geom of the body's kinematic tree (a robot: chassis, wheels, sensors) means the body
    shows there; a hit on another geom before the point means that geom hides it.

    Args:
        model: the compiled model.
        body: name of the body (any body of its tree).
        geom_groups: the geom groups drawn.

    Raises:
        RenderingError: for a body the model does not have.
    """

    def __init__(
        self, model: mujoco.MjModel, body: str, geom_groups: tuple[int, ...] = ALL_GEOM_GROUPS
    ) -> None:
        body_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body)
        if body_id < 0:
            raise RenderingError(f"no body named '{body}' to follow")
        self.model = model
        self.body_id = body_id
        self._root = model.body_rootid[body_id]
        self._groups = np.zeros(6, dtype=np.uint8)
        self._groups[list(geom_groups)] = 1
        self._hit = np.zeros(1, dtype=np.int32)

    def owns(self, geom: int) -> bool:
        """True when ``geom`` belongs to the body's kinematic tree."""
        return bool(self.model.body_rootid[self.model.geom_bodyid[geom]] == self._root)

    def blocker(self, data: mujoco.MjData, eye: np.ndarray, point: np.ndarray) -> int:
        """The geom that hides ``point`` (m) from ``eye`` (m), or -1 if none does."""
        span = np.asarray(point, dtype=float) - eye
        fraction = mujoco.mj_ray(self.model, data, eye, span, self._groups, 1, -1, self._hit)
        geom = int(self._hit[0])
        if fraction < 0.0 or fraction >= 1.0 or self.owns(geom):
            return -1
        return geom

    def clear(self, data: mujoco.MjData, eye: np.ndarray, point: np.ndarray) -> bool:
        """True when no geom but the body's own stands between ``eye`` and ``point``."""
        return self.blocker(data, eye, point) < 0
