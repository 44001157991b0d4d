"""``rclpy.duration``: spans of time."""

from __future__ import annotations

from baobab.nav.rostime import Duration, Infinite

__all__ = ["Duration", "Infinite"]
