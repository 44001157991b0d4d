"""``tf2_ros.buffer``: the buffer nodes look transforms up in, with timeouts on sim time."""

from __future__ import annotations

from typing import Any

from baobab.nav.msgs import Header, Quaternion, Vector3
from baobab.nav.ros import waiting
from baobab.nav.ros.geometry_msgs.msg import Transform, TransformStamped
from baobab.nav.ros.tf_tree import Edge, TransformTree, compose
from baobab.nav.rostime import S_TO_NS, Duration, Time, TimeMsg, sim_time_ns

__all__ = ["Buffer"]


def _time_ns(time: Any) -> int:
    if isinstance(time, Time):
        return time.nanoseconds
    if isinstance(time, TimeMsg):
        return time.sec * S_TO_NS + time.nanosec
    raise TypeError(f"time must be an rclpy Time or a builtin_interfaces Time, got {time!r}")


def _timeout_ns(timeout: Any) -> int:
    if timeout is None:
        return 0
    if isinstance(timeout, Duration):
        return timeout.nanoseconds
    raise TypeError(f"timeout must be an rclpy Duration, got {timeout!r}")


class Buffer:
    """Stores transforms and answers lookups (``tf2_ros.Buffer``).

    A lookup with a timeout waits on sim time for the transform to become available (the
    listener keeps filling the buffer meanwhile), then raises what tf2 raises.

    Args:
        cache_time: how long dynamic transforms are kept (default 10 s).
        node: accepted (rclpy uses it for the node's clock and a service).
    """

    def __init__(self, cache_time: Duration | None = None, node: object = None, **kwargs: Any):
        cache = 10 * S_TO_NS if cache_time is None else cache_time.nanoseconds
        self._tree = TransformTree(cache)

    def set_transform(self, transform: TransformStamped, authority: str) -> bool:
        """Store a dynamic transform."""
        return self._store(transform, static=False)

    def set_transform_static(self, transform: TransformStamped, authority: str) -> bool:
        """Store a static transform (valid at every time)."""
        return self._store(transform, static=True)

    def _store(self, transform: TransformStamped, *, static: bool) -> bool:
        t, r = transform.transform.translation, transform.transform.rotation
        edge = Edge(
            _time_ns(transform.header.stamp),
            transform.header.frame_id,
            (t.x, t.y, t.z),
            (r.x, r.y, r.z, r.w),
        )
        self._tree.set(transform.child_frame_id, edge, static=static)
        return True

    def _wait(self, ready: Any, timeout: Any, what: str) -> None:
        limit = _timeout_ns(timeout)
        if limit > 0 and not ready() and waiting.can_wait():
            waiting.wait(sim_time_ns() + limit, ready, what=what)

    def lookup_transform(
        self, target_frame: str, source_frame: str, time: Any, timeout: Any = None
    ) -> TransformStamped:
        """The transform taking ``source_frame`` data into ``target_frame`` at ``time``
        (``Time()``: the latest available), waiting up to ``timeout`` for it.

        Raises:
            LookupException, ConnectivityException, ExtrapolationException: as tf2.
        """
        at = _time_ns(time)
        self._wait(
            lambda: self._tree.can_lookup(target_frame, source_frame, at)[0],
            timeout,
            "Buffer.lookup_transform()",
        )
        translation, rotation, stamp = self._tree.lookup(target_frame, source_frame, at)
        return _stamped(target_frame, source_frame, translation, rotation, stamp)

    def lookup_transform_full(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
        timeout: Any = None,
    ) -> TransformStamped:
        """``source_frame`` at ``source_time`` into ``target_frame`` at ``target_time``,
        through ``fixed_frame``."""
        self._wait(
            lambda: self.can_transform_full(
                target_frame, target_time, source_frame, source_time, fixed_frame
            ),
            timeout,
            "Buffer.lookup_transform_full()",
        )
        fixed_from_source = self._tree.lookup(fixed_frame, source_frame, _time_ns(source_time))
        target_from_fixed = self._tree.lookup(target_frame, fixed_frame, _time_ns(target_time))
        translation, rotation = compose(target_from_fixed[:2], fixed_from_source[:2])
        return _stamped(target_frame, source_frame, translation, rotation, target_from_fixed[2])

    def can_transform(
        self,
        target_frame: str,
        source_frame: str,
        time: Any,
        timeout: Any = None,
        return_debug_tuple: bool = False,
    ) -> Any:
        """True when the transform is available, waiting up to ``timeout`` for it."""
        at = _time_ns(time)

        def ready() -> bool:
            return self._tree.can_lookup(target_frame, source_frame, at)[0]

        self._wait(ready, timeout, "Buffer.can_transform()")
        possible, reason = self._tree.can_lookup(target_frame, source_frame, at)
        return (possible, reason) if return_debug_tuple else possible

    def can_transform_full(
        self,
        target_frame: str,
        target_time: Any,
        source_frame: str,
        source_time: Any,
        fixed_frame: str,
        timeout: Any = None,
        return_debug_tuple: bool = False,
    ) -> Any:
        """:meth:`can_transform` for :meth:`lookup_transform_full`."""
        first = self._tree.can_lookup(fixed_frame, source_frame, _time_ns(source_time))
        second = self._tree.can_lookup(target_frame, fixed_frame, _time_ns(target_time))
        possible = first[0] and second[0]
        reason = first[1] or second[1]
        return (possible, reason) if return_debug_tuple else possible

    def all_frames_as_string(self) -> str:
        """One line per frame: ``Frame child exists with parent parent.``."""
        lines = []
        for frame in self._tree.frames():
            parent = self._tree._parent_of(frame)
            if parent is not None:
                lines.append(f"Frame {frame} exists with parent {parent}.")
        return "\n".join(lines) + ("\n" if lines else "")

    def all_frames_as_yaml(self) -> str:
        """The frames and their parents as YAML."""
        return "".join(
            f"{frame}: \n  parent: '{self._tree._parent_of(frame)}'\n"
            for frame in self._tree.frames()
            if self._tree._parent_of(frame) is not None
        )

    def clear(self) -> None:
        """Forget every stored transform."""
        self._tree = TransformTree(self._tree.cache_time_ns)


def _stamped(
    target: str, source: str, translation: Any, rotation: Any, stamp_ns: int
) -> TransformStamped:
    sec, nanosec = divmod(stamp_ns, S_TO_NS)
    x, y, z = (float(value) for value in translation)
    qx, qy, qz, qw = (float(value) for value in rotation)
    return TransformStamped(
        header=Header(stamp=TimeMsg(sec=sec, nanosec=nanosec), frame_id=target),
        child_frame_id=source,
        transform=Transform(
            translation=Vector3(x=x, y=y, z=z), rotation=Quaternion(x=qx, y=qy, z=qz, w=qw)
        ),
    )
