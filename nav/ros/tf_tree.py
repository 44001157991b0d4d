"""The transform tree behind ``tf2_ros.Buffer``: stored transforms, lookups and TF's errors.

Each frame has at most one parent. A dynamic transform (from ``/tf``) is kept as timed samples
for the cache time (10 s by default); a static one (``/tf_static``) holds at every time. A
lookup walks both frames up to their common ancestor and composes the edges, each evaluated at
the requested time: between two samples by linear interpolation of the translation and slerp
of the rotation, as tf2 does. Time 0 asks for the latest time all the chain's dynamic edges
share. The errors are tf2's, with tf2's wording: an unknown frame is a ``LookupException``,
frames in two trees a ``ConnectivityException``, a time outside the samples an
``ExtrapolationException``.
"""

from __future__ import annotations

import bisect
import math
from collections import deque
from dataclasses import dataclass

Vector = tuple[float, float, float]
Quat = tuple[float, float, float, float]
"""x, y, z, w."""


class TransformException(Exception):
    """Base of tf2's errors (``tf2.TransformException``)."""


class LookupException(TransformException):
    """A frame is not in the tree."""


class ConnectivityException(TransformException):
    """The frames are in different trees."""


class ExtrapolationException(TransformException):
    """The requested time lies outside the stored samples."""


class InvalidArgumentException(TransformException):
    """A transform or frame name that cannot be used."""


class TimeoutException(TransformException):
    """A wait for a transform ran out of time."""


@dataclass(frozen=True)
class Edge:
    """A transform from ``parent`` to a child frame at ``stamp_ns``: the child's pose in it."""

    stamp_ns: int
    parent: str
    translation: Vector
    rotation: Quat


def quat_multiply(a: Quat, b: Quat) -> Quat:
    """The rotation ``a`` after ``b`` (Hamilton product)."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )


def quat_rotate(q: Quat, v: Vector) -> Vector:
    """``v`` rotated by the unit quaternion ``q``."""
    x, y, z, w = q
    vx, vy, vz = v
    tx, ty, tz = 2 * (y * vz - z * vy), 2 * (z * vx - x * vz), 2 * (x * vy - y * vx)
    return (
        vx + w * tx + y * tz - z * ty,
        vy + w * ty + z * tx - x * tz,
        vz + w * tz + x * ty - y * tx,
    )


def compose(first: tuple[Vector, Quat], second: tuple[Vector, Quat]) -> tuple[Vector, Quat]:
    """The transform ``first * second`` (apply ``second``, then ``first``)."""
    t1, q1 = first
    t2, q2 = second
    rotated = quat_rotate(q1, t2)
    return (t1[0] + rotated[0], t1[1] + rotated[1], t1[2] + rotated[2]), quat_multiply(q1, q2)


def invert(transform: tuple[Vector, Quat]) -> tuple[Vector, Quat]:
    """The inverse transform."""
    (tx, ty, tz), (x, y, z, w) = transform
    inverse: Quat = (-x, -y, -z, w)
    rx, ry, rz = quat_rotate(inverse, (tx, ty, tz))
    return (-rx, -ry, -rz), inverse


def _normalized(q: Quat) -> Quat:
    norm = math.sqrt(sum(c * c for c in q))
    if not math.isfinite(norm) or norm < 1e-12:
        raise InvalidArgumentException(f"quaternion {q} has zero or non-finite norm")
    return (q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm)


def _slerp(a: Quat, b: Quat, ratio: float) -> Quat:
    dot = sum(x * y for x, y in zip(a, b, strict=True))
    if dot < 0.0:
        b, dot = (-b[0], -b[1], -b[2], -b[3]), -dot
    if dot > 0.9995:
        mixed = tuple(x + ratio * (y - x) for x, y in zip(a, b, strict=True))
        return _normalized(mixed)  # type: ignore[arg-type]
    angle = math.acos(min(dot, 1.0))
    first, second = math.sin((1 - ratio) * angle), math.sin(ratio * angle)
    scale = math.sin(angle)
    return _normalized(
        tuple((first * x + second * y) / scale for x, y in zip(a, b, strict=True))  # type: ignore[arg-type]
    )


def _seconds(stamp_ns: int) -> str:
    return f"{stamp_ns / 1e9:.6f}"


class TransformTree:
    """Stored transforms and lookups (module docstring).

    Args:
        cache_time_ns: how long dynamic samples are kept behind the newest (ns).
    """

    def __init__(self, cache_time_ns: int = 10 * 10**9) -> None:
        self.cache_time_ns = cache_time_ns
        self._dynamic: dict[str, deque[Edge]] = {}
        self._static: dict[str, Edge] = {}

    def set(self, child: str, edge: Edge, *, static: bool) -> None:
        """Store that ``child``'s pose in ``edge.parent`` is ``edge`` (at its stamp).

        Raises:
            InvalidArgumentException: empty or equal frame names, or a zero quaternion.
        """
        child, parent = child.lstrip("/"), edge.parent.lstrip("/")
        if not child or not parent or child == parent:
            raise InvalidArgumentException(
                f"frame ids must be non-empty and differ, got '{parent}' -> '{child}'"
            )
        edge = Edge(edge.stamp_ns, parent, edge.translation, _normalized(edge.rotation))
        if static:
            self._static[child] = edge
            self._dynamic.pop(child, None)
            return
        samples = self._dynamic.setdefault(child, deque())
        if samples and edge.stamp_ns < samples[-1].stamp_ns:
            stamps = [sample.stamp_ns for sample in samples]
            samples.insert(bisect.bisect_right(stamps, edge.stamp_ns), edge)
        elif samples and edge.stamp_ns == samples[-1].stamp_ns:
            samples[-1] = edge
        else:
            samples.append(edge)
        oldest = samples[-1].stamp_ns - self.cache_time_ns
        while samples and samples[0].stamp_ns < oldest:
            samples.popleft()

    def frames(self) -> list[str]:
        """Every frame named so far, sorted."""
        names = set(self._static) | set(self._dynamic)
        names |= {edge.parent for edge in self._static.values()}
        names |= {samples[-1].parent for samples in self._dynamic.values() if samples}
        return sorted(names)

    def _parent_of(self, frame: str) -> str | None:
        if frame in self._static:
            return self._static[frame].parent
        samples = self._dynamic.get(frame)
        return samples[-1].parent if samples else None

    def _chain(self, frame: str) -> list[str]:
        chain = [frame]
        while (parent := self._parent_of(chain[-1])) is not None:
            if parent in chain:
                raise ConnectivityException(f"the transform tree has a loop through '{parent}'")
            chain.append(parent)
        return chain

    def _edge_at(self, frame: str, time_ns: int) -> tuple[Vector, Quat]:
        if frame in self._static:
            edge = self._static[frame]
            return edge.translation, edge.rotation
        samples = self._dynamic[frame]
        first, last = samples[0], samples[-1]
        if time_ns == last.stamp_ns:
            return last.translation, last.rotation
        if time_ns > last.stamp_ns or time_ns < first.stamp_ns:
            direction, data = ("future", last) if time_ns > last.stamp_ns else ("past", first)
            raise ExtrapolationException(
                f"Lookup would require extrapolation into the {direction}.  Requested time "
                f"{_seconds(time_ns)} but the {'latest' if direction == 'future' else 'earliest'}"
                f" data is at time {_seconds(data.stamp_ns)}, when looking up transform from "
                f"frame [{frame}] to frame [{data.parent}]"
            )
        stamps = [sample.stamp_ns for sample in samples]
        index = bisect.bisect_left(stamps, time_ns)
        after = samples[index]
        if after.stamp_ns == time_ns or index == 0:
            return after.translation, after.rotation
        before = samples[index - 1]
        ratio = (time_ns - before.stamp_ns) / (after.stamp_ns - before.stamp_ns)
        translation = tuple(
            a + ratio * (b - a) for a, b in zip(before.translation, after.translation, strict=True)
        )
        return translation, _slerp(before.rotation, after.rotation, ratio)  # type: ignore[return-value]

    def lookup(self, target: str, source: str, time_ns: int) -> tuple[Vector, Quat, int]:
        """The transform taking ``source``-frame data into ``target`` at ``time_ns`` (0: the
        latest common time), and the time it holds at.

        Raises:
            LookupException, ConnectivityException, ExtrapolationException: as tf2.
        """
        target, source = target.lstrip("/"), source.lstrip("/")
        known = set(self.frames())
        for frame, argument in ((target, "target_frame"), (source, "source_frame")):
            if frame not in known:
                raise LookupException(
                    f'"{frame}" passed to lookupTransform argument {argument} does not exist. '
                )
        if target == source:
            return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), time_ns
        up_source, up_target = self._chain(source), self._chain(target)
        common = next((frame for frame in up_source if frame in up_target), None)
        if common is None:
            raise ConnectivityException(
                f"Could not find a connection between '{target}' and '{source}' because they "
                "are not part of the same tree.Tf has two or more unconnected trees."
            )
        source_path = up_source[: up_source.index(common)]
        target_path = up_target[: up_target.index(common)]
        if time_ns == 0:
            latest = [
                self._dynamic[frame][-1].stamp_ns
                for frame in (*source_path, *target_path)
                if frame in self._dynamic
            ]
            time_ns = min(latest) if latest else 0
        return (*self._compose(source_path, target_path, time_ns), time_ns)

    def _compose(
        self, source_path: list[str], target_path: list[str], time_ns: int
    ) -> tuple[Vector, Quat]:
        identity: tuple[Vector, Quat] = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
        common_from_source = identity
        for frame in reversed(source_path):  # from the common ancestor down to the source
            common_from_source = compose(common_from_source, self._edge_at(frame, time_ns))
        common_from_target = identity
        for frame in reversed(target_path):
            common_from_target = compose(common_from_target, self._edge_at(frame, time_ns))
        return compose(invert(common_from_target), common_from_source)

    def can_lookup(self, target: str, source: str, time_ns: int) -> tuple[bool, str]:
        """Whether :meth:`lookup` would succeed, and its error message if not."""
        try:
            self.lookup(target, source, time_ns)
        except TransformException as exc:
            return False, str(exc)
        return True, ""
