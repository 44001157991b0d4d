"""``builtin_interfaces.msg``: the ``Time`` and ``Duration`` messages (``sec``, ``nanosec``)."""

from __future__ import annotations

from baobab.nav.rostime import DurationMsg as Duration
from baobab.nav.rostime import TimeMsg as Time

__all__ = ["Duration", "Time"]
