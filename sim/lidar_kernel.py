"""The lidar's compiled ray caster: ``mj_multiRay``'s answers for a planar fan, with less work.

``mj_multiRay`` tests every beam against every geom whose bounding angles cover it; for a
planar fan most of those tests are misses or hits behind a nearer one. :func:`cast_fan` calls
MuJoCo's own primitive intersection (``mju_rayGeom``, the function ``mj_multiRay`` uses) for
each beam and geom that can matter, so every range is bit for bit the one ``mj_multiRay``
returns. A (beam, geom) pair is skipped only when no skip can change a reported range:

- geoms ``mj_multiRay`` eliminates: hidden ones (alpha 0) and those of excluded groups;
- beams outside the geom's bounding sphere: the fan lies in the sensor's x-y plane, so a
  beam can only hit a geom whose bounding sphere, projected onto that plane, it crosses;
- hits that cannot be nearer than the beam's best hit so far (geoms go nearest first);
- hits farther than ``reach``: they read ``inf`` anyway. (With range noise they would not
  all do so: ``mj_multiRay`` returns some hits beyond its cutoff, and noise can bring them
  back in range. A noisy scanner therefore uses ``mj_multiRay`` itself.)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, TypeAlias, cast

import llvmlite.ir
import mujoco
import numba
import numpy as np
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from baobab.sim.mujoco_native import ray_geom

_PLANE = int(mujoco.mjtGeom.mjGEOM_PLANE)
_CYLINDER = int(mujoco.mjtGeom.mjGEOM_CYLINDER)
_BOX = int(mujoco.mjtGeom.mjGEOM_BOX)
_LAST_PRIMITIVE = _BOX
"""Geom types ``mju_rayGeom`` handles: plane .. box (not hfield, mesh or sdf)."""

_GROUPS = int(mujoco.mjNGROUP)
_SLACK = 1e-6
"""Widening (m) of every bound, far above the rounding of the beam directions (~1e-16)."""


@intrinsic
def _fma_intrinsic(typingctx: Any, a: Any, b: Any, c: Any) -> Any:  # pragma: no cover
    signature = types.float64(types.float64, types.float64, types.float64)

    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        double = llvmlite.ir.DoubleType()
        function_type = llvmlite.ir.FunctionType(double, [double, double, double])
        fma = cgutils.get_or_insert_function(builder.module, function_type, "llvm.fma.f64")
        return builder.call(fma, args)

    return signature, codegen


_fma = cast(Callable[[float, float, float], float], _fma_intrinsic)
"""``a * b + c`` with one rounding (compiled code only)."""


Geometry: TypeAlias = tuple[np.ndarray, ...]
"""MuJoCo's arrays the caster reads, in this order: ``data.geom_xpos``, ``data.geom_xmat``,
``model.geom_size``, ``geom_rbound``, ``geom_type``, ``geom_group``, ``geom_matid``,
``geom_rgba``, ``mat_rgba``, ``geom_aabb``, ``geom_bodyid``, ``body_bvhadr``, ``bvh_aabb``,
``data.xipos``."""


@numba.njit(cache=True, nogil=True)
def fan_directions(
    rotation: np.ndarray, local: np.ndarray, directions: np.ndarray
) -> None:  # pragma: no cover - compiled
    """``directions = local @ rotation.T``, bit for bit as NumPy's matmul computes it.

    NumPy hands the product to OpenBLAS, whose kernels accumulate the three terms of each
    entry with fused multiply-adds in order; the same operations here keep every beam
    direction, hence every range, identical to the NumPy-built scanner's.

    Args:
        rotation: the sensor's rotation matrix (9,), row-major.
        local: the beams in the sensor frame (n, 3).
        directions: out (n, 3), world frame.
    """
    for beam in range(local.shape[0]):
        x, y, z = local[beam, 0], local[beam, 1], local[beam, 2]
        for row in range(3):
            r = rotation[3 * row : 3 * row + 3]
            directions[beam, row] = _fma(z, r[2], _fma(y, r[1], x * r[0]))


@numba.njit(cache=True, nogil=True)
def _culled_like_mujoco(
    geom: int,
    geom_xpos: np.ndarray,
    geom_size: np.ndarray,
    geom_rbound: np.ndarray,
    geom_type: np.ndarray,
    geom_aabb: np.ndarray,
    geom_bodyid: np.ndarray,
    body_bvhadr: np.ndarray,
    bvh_aabb: np.ndarray,
    xipos: np.ndarray,
) -> bool:  # pragma: no cover - compiled
    """Whether ``mj_multiRay``'s culling volumes still hold the geom (box and cylinder only).

    ``mj_multiRay`` culls with the geom's ``geom_aabb`` and its body's bounding-volume root,
    both set when the model is compiled. A geom resized at run time (an obstacle slot) can
    outgrow them; ``mj_multiRay`` then misses part of it, and so must the scanner.
    """
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
    body = geom_bodyid[geom]
    node = body_bvhadr[body]
    if node < 0:
        return True
    root = bvh_aabb[node]
    dx = geom_xpos[geom, 0] - (root[0] + xipos[body, 0])
    dy = geom_xpos[geom, 1] - (root[1] + xipos[body, 1])
    dz = geom_xpos[geom, 2] - (root[2] + xipos[body, 2])
    radius = math.sqrt(root[3] * root[3] + root[4] * root[4] + root[5] * root[5])
    return math.sqrt(dx * dx + dy * dy + dz * dz) + geom_rbound[geom] <= radius - _SLACK


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
def cast_fan(
    origin: np.ndarray,
    rotation: np.ndarray,
    directions: np.ndarray,
    angle_min: float,
    angle_increment: float,
    geometry: Geometry,
    geomgroup: np.ndarray,
    reach: float,
    best: np.ndarray,
) -> bool:  # pragma: no cover - compiled
    """Nearest hit along each beam, as ``mj_multiRay(flg_static=1, bodyexclude=-1)`` finds it.

    Args:
        origin: the fan's origin (3,), world frame (m).
        rotation: the sensor's rotation matrix (9,), row-major; the beams lie in its x-y plane.
        directions: the beams (n, 3), world frame; beam ``i`` is the sensor-frame unit vector
            at angle ``angle_min + i * angle_increment`` (rad) rotated by ``rotation``.
        geometry: the model's and data's arrays :data:`Geometry` names, in its order.
        geomgroup: 1 for each geom group the beams see (``mjNGROUP``,).
        reach: hits farther than this (m) may be reported as misses.
        best: out (n,): distance to the nearest hit, -1 where the beam hits nothing.

    Returns:
        False (with ``best`` undefined) if a geom in view is of a type this caster does not
        handle (hfield, mesh, sdf), or has outgrown the volumes ``mj_multiRay`` culls with
        (:func:`_culled_like_mujoco`): use ``mj_multiRay`` then.
    """
    (
        geom_xpos,
        geom_xmat,
        geom_size,
        geom_rbound,
        geom_type,
        geom_group,
        geom_matid,
        geom_rgba,
        mat_rgba,
        geom_aabb,
        geom_bodyid,
        body_bvhadr,
        bvh_aabb,
        xipos,
    ) = geometry
    beams = directions.shape[0]
    ngeom = geom_type.shape[0]
    best[:] = -1.0
    candidates = np.empty(ngeom, dtype=np.int64)
    nearest = np.empty(ngeom)
    offset = np.empty(3)
    count = 0
    for geom in range(ngeom):
        material = geom_matid[geom]
        if material < 0:
            if geom_rgba[geom, 3] == 0:
                continue
        elif mat_rgba[material, 3] == 0:
            continue
        if geomgroup[min(_GROUPS - 1, max(0, geom_group[geom]))] == 0:
            continue
        kind = geom_type[geom]
        if kind > _LAST_PRIMITIVE:
            return False
        near = 0.0
        if kind != _PLANE:
            # Beyond reach by its bounding sphere: skipped before the exact test (a map's
            # walls are thousands of boxes, nearly all far away).
            dx = origin[0] - geom_xpos[geom, 0]
            dy = origin[1] - geom_xpos[geom, 1]
            far = reach + geom_rbound[geom]
            if dx * dx + dy * dy > far * far:
                continue
            for axis in range(3):
                offset[axis] = origin[axis] - geom_xpos[geom, axis]
            near = _nearest_surface(
                kind, offset, geom_xmat[geom], geom_size[geom], geom_rbound[geom]
            )
            if near > reach:
                continue
            if not _culled_like_mujoco(
                geom,
                geom_xpos,
                geom_size,
                geom_rbound,
                geom_type,
                geom_aabb,
                geom_bodyid,
                body_bvhadr,
                bvh_aabb,
                xipos,
            ):
                return False
        # Insertion sort, nearest first: a few dozen geoms.
        slot = count
        while slot > 0 and nearest[slot - 1] > near:
            nearest[slot] = nearest[slot - 1]
            candidates[slot] = candidates[slot - 1]
            slot -= 1
        nearest[slot] = near
        candidates[slot] = geom
        count += 1

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
    local: np.ndarray,
    origin: np.ndarray,
    directions: np.ndarray,
    angle_min: float,
    angle_increment: float,
    geometry: Geometry,
    geomgroup: np.ndarray,
    range_min: float,
    range_max: float,
    best: np.ndarray,
) -> np.ndarray:  # pragma: no cover - compiled
    """A whole noiseless scan from the site's pose: LaserScan ranges (m), new array.

    Fills ``origin`` (3,) and ``directions`` (n, 3) from the site (see :func:`fan_directions`)
    and ``best`` with the hit distances (see :func:`cast_fan`). Returns an empty array when
    :func:`cast_fan` cannot handle the view (``origin`` and ``directions`` are filled anyway).
    """
    origin[:] = site_xpos
    fan_directions(site_xmat, local, directions)
    handled = cast_fan(
        origin,
        site_xmat,
        directions,
        angle_min,
        angle_increment,
        geometry,
        geomgroup,
        range_max + _SLACK,
        best,
    )
    if not handled:
        return np.empty(0)
    return ranges_from_hits(best, np.empty(0), range_min, range_max)
