"""ROS time, with rclpy's semantics: time points, durations, clocks, and their messages.

Two families, as in ROS 2:

* the ``builtin_interfaces`` messages :class:`TimeMsg` and :class:`DurationMsg` — plain ``sec`` /
  ``nanosec`` fields, the form stamps and feedback fields (``navigation_time``) take;
* rclpy's rich :class:`Time` and :class:`Duration` — integer nanoseconds, arithmetic and
  comparisons, ``to_msg()`` / ``from_msg()``, the same ``TypeError``/``ValueError`` cases as
  ``rclpy.time`` and ``rclpy.duration`` (Rolling).

baobab has one time base, the simulation clock. Every :class:`Clock` reads it: either a source
given at construction (a navigator's own simulation) or the context-local source that
:func:`set_sim_time_source` registers — as ROS nodes with ``use_sim_time`` all follow ``/clock``.
Before any source is registered the time is 0, like a ROS node waiting for its first ``/clock``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from contextvars import ContextVar
from enum import IntEnum
from typing import overload

from baobab.nav import time_waiting
from baobab.nav.rosmsg import Message

S_TO_NS = 1_000_000_000
"""Nanoseconds per second."""

_INT64_MAX = 2**63 - 1

SimTimeSource = Callable[[], float]
"""A callable returning the current simulation time in seconds."""


class TimeMsg(Message):
    """``builtin_interfaces/msg/Time``: a time point as whole seconds plus nanoseconds."""

    _type_name = "builtin_interfaces/msg/Time"
    _fields_and_field_types = {"sec": "int32", "nanosec": "uint32"}
    sec: int
    nanosec: int


class DurationMsg(Message):
    """``builtin_interfaces/msg/Duration``: a span as whole seconds plus nanoseconds.

    A negative span has a negative ``sec`` and a ``nanosec`` in ``0..999999999``
    (``-1.5 s`` is ``sec=-2, nanosec=500000000``), as rclpy writes it.
    """

    _type_name = "builtin_interfaces/msg/Duration"
    _fields_and_field_types = {"sec": "int32", "nanosec": "uint32"}
    sec: int
    nanosec: int


class ClockType(IntEnum):
    """rclpy's clock types; time points only combine with time points of the same type."""

    UNINITIALIZED = 0
    ROS_TIME = 1
    SYSTEM_TIME = 2
    STEADY_TIME = 3


class Duration:
    """A signed span of time with nanosecond precision (``rclpy.duration.Duration``).

    Args:
        seconds: whole or fractional seconds.
        nanoseconds: added to ``seconds``; a fractional part is discarded.

    Raises:
        OverflowError: the total does not fit a signed 64-bit nanosecond count.
    """

    __slots__ = ("_nanoseconds",)

    def __init__(self, *, seconds: int | float = 0, nanoseconds: int | float = 0) -> None:
        total = int(seconds * S_TO_NS) + int(nanoseconds)
        if total > _INT64_MAX or total < -(2**63):
            raise OverflowError("Total nanoseconds value is too large to store in C duration.")
        self._nanoseconds = total

    @property
    def nanoseconds(self) -> int:
        """The span in nanoseconds."""
        return self._nanoseconds

    def __repr__(self) -> str:
        return f"Duration(nanoseconds={self._nanoseconds})"

    def __str__(self) -> str:
        if self._nanoseconds == _INT64_MAX:
            return "Infinite"
        return f"{self._nanoseconds} nanoseconds"

    def __add__(self, other: Duration) -> Duration:
        if isinstance(other, Duration):
            return Duration(nanoseconds=self._nanoseconds + other._nanoseconds)
        return NotImplemented

    def __sub__(self, other: Duration) -> Duration:
        if isinstance(other, Duration):
            return Duration(nanoseconds=self._nanoseconds - other._nanoseconds)
        return NotImplemented

    def __mul__(self, factor: int | float) -> Duration:
        if isinstance(factor, int):
            return Duration(nanoseconds=self._nanoseconds * factor)
        if isinstance(factor, float):
            if not math.isfinite(factor):
                if factor == math.inf:
                    return Infinite
                raise ValueError("Can't multiply duration with nan")
            return Duration(nanoseconds=int(self._nanoseconds * factor))
        return NotImplemented

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Duration):
            return self._nanoseconds == other._nanoseconds
        return NotImplemented

    def __lt__(self, other: Duration) -> bool:
        if isinstance(other, Duration):
            return self._nanoseconds < other._nanoseconds
        return NotImplemented

    def __le__(self, other: Duration) -> bool:
        if isinstance(other, Duration):
            return self._nanoseconds <= other._nanoseconds
        return NotImplemented

    def __gt__(self, other: Duration) -> bool:
        if isinstance(other, Duration):
            return self._nanoseconds > other._nanoseconds
        return NotImplemented

    def __ge__(self, other: Duration) -> bool:
        if isinstance(other, Duration):
            return self._nanoseconds >= other._nanoseconds
        return NotImplemented

    def to_msg(self) -> DurationMsg:
        """The span as a ``builtin_interfaces/Duration`` message."""
        sec, nanosec = divmod(self._nanoseconds, S_TO_NS)
        return DurationMsg(sec=sec, nanosec=nanosec)

    @classmethod
    def from_msg(cls, msg: DurationMsg) -> Duration:
        """The span a ``builtin_interfaces/Duration`` message holds.

        Raises:
            TypeError: ``msg`` is not a :class:`DurationMsg` (rclpy's check).
        """
        if not isinstance(msg, DurationMsg):
            raise TypeError("Must pass a builtin_interfaces.msg.Duration object")
        return cls(seconds=msg.sec, nanoseconds=msg.nanosec)


Infinite = Duration(nanoseconds=_INT64_MAX)
"""rclpy's constant for an unbounded span (``RMW_DURATION_INFINITE``)."""


class Time:
    """A non-negative time point since a clock's epoch (``rclpy.time.Time``).

    Args:
        seconds: whole or fractional seconds.
        nanoseconds: added to ``seconds``; a fractional part is discarded.
        clock_type: the clock the point belongs to.

    Raises:
        ValueError: ``seconds`` or ``nanoseconds`` is negative.
        OverflowError: the total does not fit a signed 64-bit nanosecond count.
        TypeError: ``clock_type`` is not a :class:`ClockType`.
    """

    __slots__ = ("_clock_type", "_nanoseconds")

    def __init__(
        self,
        *,
        seconds: int | float = 0,
        nanoseconds: int | float = 0,
        clock_type: ClockType = ClockType.SYSTEM_TIME,
    ) -> None:
        if not isinstance(clock_type, ClockType):
            raise TypeError("Clock type must be a ClockType enum")
        if seconds < 0:
            raise ValueError("Seconds value must not be negative")
        if nanoseconds < 0:
            raise ValueError("Nanoseconds value must not be negative")
        total = int(seconds * S_TO_NS) + int(nanoseconds)
        if total > _INT64_MAX:
            raise OverflowError("Total nanoseconds value is too large to store in C time point.")
        self._nanoseconds = total
        self._clock_type = clock_type

    @property
    def nanoseconds(self) -> int:
        """Nanoseconds since the clock's epoch."""
        return self._nanoseconds

    @property
    def clock_type(self) -> ClockType:
        """The clock this point belongs to."""
        return self._clock_type

    def seconds_nanoseconds(self) -> tuple[int, int]:
        """The point as ``(whole seconds, remaining nanoseconds)``."""
        return divmod(self._nanoseconds, S_TO_NS)

    def __repr__(self) -> str:
        return f"Time(nanoseconds={self._nanoseconds}, clock_type={self._clock_type.name})"

    def __add__(self, other: Duration) -> Time:
        if isinstance(other, Duration):
            try:
                return Time(
                    nanoseconds=self._nanoseconds + other.nanoseconds,
                    clock_type=self._clock_type,
                )
            except OverflowError as exc:
                raise OverflowError("Addition leads to overflow in C storage.") from exc
        return NotImplemented

    def __radd__(self, other: Duration) -> Time:
        return self.__add__(other)

    @overload
    def __sub__(self, other: Time) -> Duration: ...

    @overload
    def __sub__(self, other: Duration) -> Time: ...

    def __sub__(self, other: Time | Duration) -> Time | Duration:
        if isinstance(other, Time):
            self._check_same_clock(other, "subtract")
            return Duration(nanoseconds=self._nanoseconds - other._nanoseconds)
        if isinstance(other, Duration):
            try:
                return Time(
                    nanoseconds=self._nanoseconds - other.nanoseconds,
                    clock_type=self._clock_type,
                )
            except ValueError as exc:
                raise ValueError("Subtraction leads to negative time.") from exc
        return NotImplemented

    def _check_same_clock(self, other: Time, verb: str) -> None:
        if self._clock_type != other._clock_type:
            raise TypeError(f"Can't {verb} times with different clock types")

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Time):
            self._check_same_clock(other, "compare")
            return self._nanoseconds == other._nanoseconds
        return NotImplemented

    def __lt__(self, other: Time) -> bool:
        if isinstance(other, Time):
            self._check_same_clock(other, "compare")
            return self._nanoseconds < other._nanoseconds
        return NotImplemented

    def __le__(self, other: Time) -> bool:
        if isinstance(other, Time):
            self._check_same_clock(other, "compare")
            return self._nanoseconds <= other._nanoseconds
        return NotImplemented

    def __gt__(self, other: Time) -> bool:
        if isinstance(other, Time):
            self._check_same_clock(other, "compare")
            return self._nanoseconds > other._nanoseconds
        return NotImplemented

    def __ge__(self, other: Time) -> bool:
        if isinstance(other, Time):
            self._check_same_clock(other, "compare")
            return self._nanoseconds >= other._nanoseconds
        return NotImplemented

    def to_msg(self) -> TimeMsg:
        """The point as a ``builtin_interfaces/Time`` message (a header stamp)."""
        sec, nanosec = self.seconds_nanoseconds()
        return TimeMsg(sec=sec, nanosec=nanosec)

    @classmethod
    def from_msg(cls, msg: TimeMsg, clock_type: ClockType = ClockType.ROS_TIME) -> Time:
        """The point a ``builtin_interfaces/Time`` message holds (ROS time by default).

        Raises:
            TypeError: ``msg`` is not a :class:`TimeMsg` (rclpy's check).
        """
        if not isinstance(msg, TimeMsg):
            raise TypeError("Must pass a builtin_interfaces.msg.Time object")
        return cls(seconds=msg.sec, nanoseconds=msg.nanosec, clock_type=clock_type)


_sim_time_source: ContextVar[SimTimeSource | None] = ContextVar("sim_time_source", default=None)


def set_sim_time_source(source: SimTimeSource | None) -> None:
    """Make ``source`` (simulation seconds) the time every source-less :class:`Clock` reads.

    A navigator calls this when it creates its simulation, so that plain ``rclpy`` nodes in
    the same script stamp messages with the same sim time. The setting is context-local;
    ``run_nav2_script`` runs each script in its own context, so nothing leaks between runs.
    """
    _sim_time_source.set(source)


def sim_time_source() -> SimTimeSource | None:
    """The registered simulation time source (None when there is none)."""
    return _sim_time_source.get()


def sim_time_ns() -> int:
    """The registered simulation time in nanoseconds, 0 when no source is registered."""
    source = _sim_time_source.get()
    return 0 if source is None else round(source() * S_TO_NS)


class Clock:
    """A clock reading simulation time (``rclpy.clock.Clock``'s interface).

    Args:
        clock_type: the type stamped on the points :meth:`now` returns; rclpy's default is
            ``SYSTEM_TIME``, a node's clock is ``ROS_TIME``. baobab has no wall clock in its
            logic, so every type reads the simulation time.
        source: simulation seconds; ``None`` reads the context-local source
            (:func:`set_sim_time_source`) at each call.
    """

    def __init__(
        self,
        *,
        clock_type: ClockType = ClockType.SYSTEM_TIME,
        source: SimTimeSource | None = None,
    ) -> None:
        if not isinstance(clock_type, ClockType):
            raise TypeError("Clock type must be a ClockType enum")
        self._clock_type = clock_type
        self._source = source

    @property
    def clock_type(self) -> ClockType:
        """The type of the points this clock returns."""
        return self._clock_type

    def __repr__(self) -> str:
        return f"Clock(clock_type={self._clock_type.name})"

    def now(self) -> Time:
        """The current simulation time as a :class:`Time` of this clock's type."""
        nanoseconds = sim_time_ns() if self._source is None else round(self._source() * S_TO_NS)
        return Time(nanoseconds=nanoseconds, clock_type=self._clock_type)

    def sleep_until(self, until: Time, context: object = None) -> bool:
        """Wait until this clock reads ``until``: sim time advances meanwhile (rclpy's
        ``Clock.sleep_until``); True once it is reached.

        Raises:
            TypeError: ``until`` is not a :class:`Time`.
            ValueError: ``until`` belongs to another clock type.
            UnsupportedRosFeatureError: nothing can advance sim time here (no navigator or ROS
                runtime in this script, or another thread).
        """
        if not isinstance(until, Time):
            raise TypeError("until must be a Time instance")
        if until.clock_type != self._clock_type:
            raise ValueError("until's clock type does not match this clock's type")
        if until > self.now():
            time_waiting.wait(until.nanoseconds, None, what="Clock.sleep_until()")
        return True

    def sleep_for(self, rel_time: Duration, context: object = None) -> bool:
        """Wait ``rel_time`` of this clock's time (rclpy's ``Clock.sleep_for``); see
        :meth:`sleep_until`."""
        if not isinstance(rel_time, Duration):
            raise TypeError("rel_time must be a Duration instance")
        return self.sleep_until(self.now() + rel_time, context)
