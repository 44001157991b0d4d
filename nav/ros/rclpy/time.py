"""``rclpy.time``: time points."""

from __future__ import annotations

from baobab.nav.rostime import Time

__all__ = ["Time"]
