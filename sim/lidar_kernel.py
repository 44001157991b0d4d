"""The lidar's compiled ray caster: ``mj_multiRay``'s answers for a planar fan, with less work.

``mj_multiRay`` tests every beam against every geom whose bounding angles cover it; for a
planar fan most of those tests are misses or hits behind a nearer one. :func:`cast_fan` calls
MuJoCo's own primitive intersection (``mju_rayGeom``, the function ``mj_multiRay`` uses) for
each beam and geom that can matter, so every range is bit for bit the one ``mj_multiRay``
returns for the same beams; the tests compare the two on random poses of every bundled world
(``tests/test_lidar.py``). Compiled because the culling loops over geoms and beams: in
Python they would cost more than the rays they save. A (beam, geom) pair is skipped only when
no skip can change a reported range:

- geoms ``mj_multiRay`` eliminates: hidden ones (alpha 0) and those of excluded groups;
- beams outside the geom's bounding sphere: the fan lies in the sensor's x-y plane, so a
  beam can only hit a geom whose bounding sphere, projected onto that plane, it crosses;
- hits that cannot be nearer than the beam's best hit so far (geoms go nearest first);
- hits farther than ``reach``: they read ``inf`` anyway. (With range noise they would not
  all do so: ``mj_multiRay`` returns some hits beyond its cutoff, and noise can bring them
  back in range. A noisy scanner therefore uses ``mj_multiRay`` itself.)

The kernels read named records (:mod:`baobab.sim.records`): the scanner's figures
(:data:`FAN`), its beams and results (:class:`Fan`) and where MuJoCo's arrays live
(:data:`~baobab.sim.mujoco_native.GEOM_ARRAYS`, read as
:class:`~baobab.sim.mujoco_native.GeomArrays`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import mujoco
import numba
import numpy as np

from baobab.sim.mujoco_native import GeomArrays, geom_views, ray_geom
from baobab.sim.records import Record

_PLANE = int(mujoco.mjtGeom.mjGEOM_PLANE)
_CYLINDER = int(mujoco.mjtGeom.mjGEOM_CYLINDER)
_BOX = int(mujoco.mjtGeom.mjGEOM_BOX)
_LAST_PRIMITIVE = _BOX
"""Geom types ``mju_rayGeom`` handles: plane .. box (not hfield, mesh or sdf)."""

_GROUPS = int(mujoco.mjNGROUP)
_SLACK = 1e-6
"""Widening (m) of every bound, far above the rounding of the beam directions (~1e-16)."""

FAN = np.dtype(
    [
        ("angle_min", np.float64),  # sensor-frame angle of beam 0 (rad)
        ("angle_increment", np.float64),  # rad between beams
        ("range_min", np.float64),  # nearer hits read inf (m)
        ("range_max", np.float64),  # farther hits read inf (m)
    ]
)
"""A scanner's beam layout and range limits (:meth:`~baobab.sim.lidar.Lidar.pack`)."""


class Fan(NamedTuple):
    """A scanner's beams and the arrays the caster fills."""

    local: np.ndarray
    """The beams in the sensor frame (n, 3): unit vectors in its x-y plane."""
    geomgroup: np.ndarray
    """1 for each geom group the beams see (``mjNGROUP``,), ``uint8``."""
    origin: np.ndarray
    """Out: the fan's origin (3,), world frame (m)."""
    directions: np.ndarray
    """Out: the beams (n, 3), world frame."""
    best: np.ndarray
    """Out: distance (m) to each beam's nearest hit, -1 where it hits nothing (n,)."""


@numba.njit(cache=True, nogil=True)
def fan_directions(
    rotation: np.ndarray, local: np.ndarray, directions: np.ndarray
) -> None:  # pragma: no cover - compiled
    """``directions = local @ rotation.T``: the beams rotated into the world frame.

    Args:
        rotation: the sensor's rotation matrix (9,), row-major.
        local: the beams in the sensor frame (n, 3).
        directions: out (n, 3), world frame.
    """
    for beam in range(local.shape[0]):
        x, y, z = local[beam, 0], local[beam, 1], local[beam, 2]
        for row in range(3):
            r = rotation[3 * row : 3 * row + 3]
            directions[beam, row] = x * r[0] + y * r[1] + z * r[2]


@numba.njit(cache=True, nogil=True)
def _culled_like_mujoco(geom: int, geometry: GeomArrays) -> bool:  # pragma: no cover - compiled
    """Whether ``mj_multiRay``'s culling volumes still hold the geom (box and cylinder only).

    ``mj_multiRay`` culls with the geom's ``geom_aabb`` and its body's bounding-volume root,
    both set when the model is compiled. A geom resized at run time without them (obstacle
    slots bring theirs along) can outgrow them; ``mj_multiRay`` then misses part of it, and
    so must the scanner.

    The body's bounding sphere holds the geom when it holds the geom's bounding sphere with
    room to spare, or when it is centred on the geom, bit for bit, and is no smaller than the
    sphere ``mju_rayGeom`` itself tests first (:func:`_own_sphere_squared`): the one geom of
    an obstacle slot. Then every beam that hits the geom has passed the same test, on the same
    numbers, as the body's, and the body's culling drops no hit.
    """
    geom_xpos, geom_size, geom_type = geometry.geom_xpos, geometry.geom_size, geometry.geom_type
    geom_aabb, xipos, bvh_aabb = geometry.geom_aabb, geometry.xipos, geometry.bvh_aabb
    kind = geom_type[geom]
    if kind != _BOX and kind != _CYLINDER:
        return False
    size = geom_size[geom]
    extent_x, extent_y = size[0], (size[1] if kind == _BOX else size[0])
    extent_z = size[2] if kind == _BOX else size[1]
    box = geom_aabb[geom]
    if box[0] != 0 or box[1] != 0 or box[2] != 0:
        return False
    if box[3] < extent_x or box[4] < extent_y or box[5] < extent_z:
        return False
    body = geometry.geom_bodyid[geom]
    node = geometry.body_bvhadr[body]
    if node < 0:
        return True
    root = bvh_aabb[node]
    # As mj_multiRay computes the body's sphere: centre root + xipos, squared radius |half|^2.
    cx, cy, cz = root[0] + xipos[body, 0], root[1] + xipos[body, 1], root[2] + xipos[body, 2]
    radius_squared = root[3] * root[3] + root[4] * root[4] + root[5] * root[5]
    gx, gy, gz = geom_xpos[geom, 0], geom_xpos[geom, 1], geom_xpos[geom, 2]
    if cx == gx and cy == gy and cz == gz:
        return radius_squared >= _own_sphere_squared(kind, size)
    dx, dy, dz = gx - cx, gy - cy, gz - cz
    return (
        math.sqrt(dx * dx + dy * dy + dz * dz) + geometry.geom_rbound[geom]
        <= math.sqrt(radius_squared) - _SLACK
    )


@numba.njit(cache=True, nogil=True, inline="always")
def _own_sphere_squared(kind: int, size: np.ndarray) -> float:  # pragma: no cover - compiled
    """Squared radius (m^2) of the bounding sphere ``mju_rayGeom`` tests before a box or a
    cylinder, summed in the order MuJoCo sums it."""
    if kind == _BOX:
        return size[0] * size[0] + size[1] * size[1] + size[2] * size[2]
    return size[0] * size[0] + size[1] * size[1]


@numba.njit(cache=True, nogil=True, inline="always")
def _nearest_surface(
    kind: int, offset: np.ndarray, xmat: np.ndarray, size: np.ndarray, rbound: float
) -> float:  # pragma: no cover - compiled
    """Distance (m) from the fan's origin to the geom (0 inside), a bound for boxes and
    cylinders, less for other shapes. ``offset`` is origin minus geom centre (world frame)."""
    qx = xmat[0] * offset[0] + xmat[3] * offset[1] + xmat[6] * offset[2]
    qy = xmat[1] * offset[0] + xmat[4] * offset[1] + xmat[7] * offset[2]
    qz = xmat[2] * offset[0] + xmat[5] * offset[1] + xmat[8] * offset[2]
    if kind == _BOX:
        ex = max(abs(qx) - size[0], 0.0)
        ey = max(abs(qy) - size[1], 0.0)
        ez = max(abs(qz) - size[2], 0.0)
        return math.sqrt(ex * ex + ey * ey + ez * ez) - _SLACK
    if kind == _CYLINDER:
        radial = max(math.sqrt(qx * qx + qy * qy) - size[0], 0.0)
        axial = max(abs(qz) - size[1], 0.0)
        return math.sqrt(radial * radial + axial * axial) - _SLACK
    return math.sqrt(qx * qx + qy * qy + qz * qz) - rbound - _SLACK


@numba.njit(cache=True, nogil=True)
def _beam_span(
    kind: int,
    centre: np.ndarray,
    xmat: np.ndarray,
    size: np.ndarray,
    rbound: float,
    rotation: np.ndarray,
    corners: np.ndarray,
) -> tuple[float, float, bool]:  # pragma: no cover - compiled
    """The sensor-frame angles (rad) ``[start, start + width]`` the geom covers in the fan.

    ``centre`` is the geom centre less the fan's origin (world frame). Returns ``(0, 0,
    False)`` when the geom does not reach the fan's plane, ``(0, 2 pi, True)`` when every
    beam may hit it. ``corners`` is scratch (8, 2).
    """
    # The geom's centre and axes in the sensor frame; z is the fan's normal.
    cx = rotation[0] * centre[0] + rotation[3] * centre[1] + rotation[6] * centre[2]
    cy = rotation[1] * centre[0] + rotation[4] * centre[1] + rotation[7] * centre[2]
    cz = rotation[2] * centre[0] + rotation[5] * centre[1] + rotation[8] * centre[2]
    if kind == _BOX:
        count = 0
        support = 0.0
        for sx in (-1.0, 1.0):
            for sy in (-1.0, 1.0):
                for sz in (-1.0, 1.0):
                    # Corner offset from the centre, world frame, then sensor frame.
                    wx = sx * size[0] * xmat[0] + sy * size[1] * xmat[1] + sz * size[2] * xmat[2]
                    wy = sx * size[0] * xmat[3] + sy * size[1] * xmat[4] + sz * size[2] * xmat[5]
                    wz = sx * size[0] * xmat[6] + sy * size[1] * xmat[7] + sz * size[2] * xmat[8]
                    corners[count, 0] = cx + rotation[0] * wx + rotation[3] * wy + rotation[6] * wz
                    corners[count, 1] = cy + rotation[1] * wx + rotation[4] * wy + rotation[7] * wz
                    support = max(support, rotation[2] * wx + rotation[5] * wy + rotation[8] * wz)
                    count += 1
        if abs(cz) > support + _SLACK:
            return 0.0, 0.0, False
        return _corner_span(corners)
    if kind == _CYLINDER:
        # The axis in the sensor frame: the projection onto the fan plane lies within a disc.
        ax = rotation[0] * xmat[2] + rotation[3] * xmat[5] + rotation[6] * xmat[8]
        ay = rotation[1] * xmat[2] + rotation[4] * xmat[5] + rotation[7] * xmat[8]
        az = rotation[2] * xmat[2] + rotation[5] * xmat[5] + rotation[8] * xmat[8]
        tilt = math.sqrt(ax * ax + ay * ay)
        if abs(cz) > size[0] * tilt + size[1] * abs(az) + size[0] + _SLACK:
            return 0.0, 0.0, False
        radius = size[0] + size[1] * tilt
    else:
        if abs(cz) > rbound + _SLACK:
            return 0.0, 0.0, False
        radius = rbound
    radius += _SLACK
    planar = math.sqrt(cx * cx + cy * cy)
    if planar <= radius:
        return 0.0, 2.0 * math.pi, True
    half_width = math.asin(radius / planar)
    return math.atan2(cy, cx) - half_width, 2.0 * half_width, True


@numba.njit(cache=True, nogil=True)
def _corner_span(corners: np.ndarray) -> tuple[float, float, bool]:  # pragma: no cover
    """Angles covered by the convex hull of ``corners`` (sensor frame) seen from the origin."""
    count = corners.shape[0]
    angles = np.empty(count)
    for k in range(count):
        value = math.atan2(corners[k, 1], corners[k, 0])
        slot = k
        while slot > 0 and angles[slot - 1] > value:
            angles[slot] = angles[slot - 1]
            slot -= 1
        angles[slot] = value
    # The hull misses the origin iff some gap between neighbouring corner angles exceeds pi;
    # the hull then covers the rest of the turn.
    gap, start = angles[0] + 2.0 * math.pi - angles[count - 1], angles[0]
    for k in range(1, count):
        if angles[k] - angles[k - 1] > gap:
            gap, start = angles[k] - angles[k - 1], angles[k]
    if gap <= math.pi + 1e-9:
        return 0.0, 2.0 * math.pi, True
    return start, 2.0 * math.pi - gap, True


@numba.njit(cache=True, nogil=True)
def _geoms_in_view(
    fan: Fan, geometry: GeomArrays, reach: float, candidates: np.ndarray, nearest: np.ndarray
) -> int:  # pragma: no cover - compiled
    """The geoms a beam may hit within ``reach`` (m), nearest first, and how many there are.

    Writes the geom ids to ``candidates`` and their distances from the fan's origin (a lower
    bound, m) to ``nearest``. Returns -1 if one is of a type the caster does not handle or has
    outgrown ``mj_multiRay``'s culling volumes (see :func:`cast_fan`).
    """
    origin, geom_xpos, geom_type = fan.origin, geometry.geom_xpos, geometry.geom_type
    geom_matid, geom_rgba, mat_rgba = geometry.geom_matid, geometry.geom_rgba, geometry.mat_rgba
    offset = np.empty(3)
    count = 0
    for geom in range(geom_type.shape[0]):
        material = geom_matid[geom]
        if material < 0:
            if geom_rgba[geom, 3] == 0:
                continue
        elif mat_rgba[material, 3] == 0:
            continue
        if fan.geomgroup[min(_GROUPS - 1, max(0, geometry.geom_group[geom]))] == 0:
            continue
        kind = geom_type[geom]
        if kind > _LAST_PRIMITIVE:
            return -1
        near = 0.0
        if kind != _PLANE:
            # Beyond reach by its bounding sphere: skipped before the exact test (a map's
            # walls are thousands of boxes, nearly all far away).
            dx = origin[0] - geom_xpos[geom, 0]
            dy = origin[1] - geom_xpos[geom, 1]
            far = reach + geometry.geom_rbound[geom]
            if dx * dx + dy * dy > far * far:
                continue
            for axis in range(3):
                offset[axis] = origin[axis] - geom_xpos[geom, axis]
            near = _nearest_surface(
                kind,
                offset,
                geometry.geom_xmat[geom],
                geometry.geom_size[geom],
                geometry.geom_rbound[geom],
            )
            if near > reach:
                continue
            if not _culled_like_mujoco(geom, geometry):
                return -1
        # Insertion sort, nearest first: a few dozen geoms.
        slot = count
        while slot > 0 and nearest[slot - 1] > near:
            nearest[slot] = nearest[slot - 1]
            candidates[slot] = candidates[slot - 1]
            slot -= 1
        nearest[slot] = near
        candidates[slot] = geom
        count += 1
    return count


@numba.njit(cache=True, nogil=True)
def cast_fan(
    fan: Fan, rotation: np.ndarray, f: Record, geometry: GeomArrays, reach: float
) -> bool:  # pragma: no cover - compiled
    """Nearest hit along each beam, as ``mj_multiRay(flg_static=1, bodyexclude=-1)`` finds it.

    Args:
        fan: the beams: ``fan.origin`` and ``fan.directions`` (world frame) are read, beam
            ``i`` being the sensor-frame unit vector at angle ``angle_min + i *
            angle_increment`` (rad) rotated by ``rotation``; ``fan.best`` receives the
            distances (m), -1 where a beam hits nothing.
        rotation: the sensor's rotation matrix (9,), row-major; the beams lie in its x-y plane.
        f: the scanner's :data:`FAN` record.
        geometry: the model's and data's arrays.
        reach: hits farther than this (m) may be reported as misses.

    Returns:
        False (with ``fan.best`` undefined) if a geom in view is of a type this caster does
        not handle (hfield, mesh, sdf), or has outgrown the volumes ``mj_multiRay`` culls with
        (:func:`_culled_like_mujoco`): use ``mj_multiRay`` then.
    """
    origin, directions, best = fan.origin, fan.directions, fan.best
    geom_xpos, geom_xmat, geom_size = geometry.geom_xpos, geometry.geom_xmat, geometry.geom_size
    geom_rbound, geom_type = geometry.geom_rbound, geometry.geom_type
    angle_min, angle_increment = f.angle_min, f.angle_increment
    beams = directions.shape[0]
    best[:] = -1.0
    candidates = np.empty(geom_type.shape[0], dtype=np.int64)
    nearest = np.empty(geom_type.shape[0])
    count = _geoms_in_view(fan, geometry, reach, candidates, nearest)
    if count < 0:
        return False
    offset = np.empty(3)
    origin_address = origin.ctypes.data
    directions_address = directions.ctypes.data
    xpos_address, xmat_address = geom_xpos.ctypes.data, geom_xmat.ctypes.data
    size_address = geom_size.ctypes.data
    corners = np.empty((8, 2))
    nx = ny = nz = height = steepest = 0.0
    for k in range(count):
        geom, near = candidates[k], nearest[k]
        kind = geom_type[geom]
        first, last = 0, beams - 1
        if kind == _PLANE:
            # Only beams running down onto the plane hit it; a shallow one hits beyond reach.
            nx, ny, nz = geom_xmat[geom, 2], geom_xmat[geom, 5], geom_xmat[geom, 8]
            height = (
                nx * (origin[0] - geom_xpos[geom, 0])
                + ny * (origin[1] - geom_xpos[geom, 1])
                + nz * (origin[2] - geom_xpos[geom, 2])
            )
            if height < -_SLACK:
                continue
            steepest = 0.5 * height / reach
        else:
            for axis in range(3):
                offset[axis] = geom_xpos[geom, axis] - origin[axis]
            start, width, seen = _beam_span(
                kind,
                offset,
                geom_xmat[geom],
                geom_size[geom],
                geom_rbound[geom],
                rotation,
                corners,
            )
            if not seen:
                continue
            # One beam of padding on each side covers any rounding of the beam directions.
            first = math.floor((start - angle_min) / angle_increment) - 1
            last = math.ceil((start + width - angle_min) / angle_increment) + 1
            if last - first + 1 >= beams:
                first, last = 0, beams - 1
        for index in range(first, last + 1):
            beam = index % beams
            if kind == _PLANE:
                down = -(
                    nx * directions[beam, 0] + ny * directions[beam, 1] + nz * directions[beam, 2]
                )
                if height > _SLACK and down < steepest:
                    continue
            current = best[beam]
            if current >= 0 and current < near:
                continue
            hit = ray_geom(
                xpos_address + 24 * geom,
                xmat_address + 72 * geom,
                size_address + 24 * geom,
                origin_address,
                directions_address + 24 * beam,
                kind,
                0,
            )
            if hit >= 0 and (hit < current or current < 0):
                best[beam] = hit
    return True


@numba.njit(cache=True, nogil=True)
def ranges_from_hits(
    best: np.ndarray, noise: np.ndarray, range_min: float, range_max: float
) -> np.ndarray:  # pragma: no cover - compiled
    """LaserScan ranges (m): hit distance plus noise, ``inf`` for misses and out of range.

    ``noise`` is empty for a noiseless scanner, else one draw (m) per beam.
    """
    ranges = np.empty(best.shape[0])
    noisy = noise.shape[0] > 0
    for beam in range(best.shape[0]):
        value = best[beam]
        if noisy:
            value = value + noise[beam]
        if best[beam] < 0 or value > range_max or value < range_min:
            value = math.inf
        ranges[beam] = value
    return ranges


@numba.njit(cache=True, nogil=True)
def scan_fan(
    site_xpos: np.ndarray,
    site_xmat: np.ndarray,
    fan: Fan,
    settings: np.ndarray,
    geom: np.ndarray,
) -> np.ndarray:  # pragma: no cover - compiled
    """A whole noiseless scan from the site's pose: LaserScan ranges (m), new array.

    Fills ``fan.origin`` and ``fan.directions`` from the site (see :func:`fan_directions`)
    and ``fan.best`` with the hit distances (see :func:`cast_fan`). ``settings`` is the
    scanner's :data:`FAN` record, ``geom`` the model's
    :data:`~baobab.sim.mujoco_native.GEOM_ARRAYS` record. Returns an empty array when
    :func:`cast_fan` cannot handle the view (``fan.origin`` and ``fan.directions`` are filled
    anyway).
    """
    f = settings[0]
    geometry = geom_views(geom)
    fan.origin[:] = site_xpos
    fan_directions(site_xmat, fan.local, fan.directions)
    if not cast_fan(fan, site_xmat, f, geometry, f.range_max + _SLACK):
        return np.empty(0)
    return ranges_from_hits(fan.best, np.empty(0), f.range_min, f.range_max)
