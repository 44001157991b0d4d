"""``rclpy.clock``: clocks reading simulation time."""

from __future__ import annotations

from baobab.nav.rostime import Clock, ClockType

__all__ = ["Clock", "ClockType"]
