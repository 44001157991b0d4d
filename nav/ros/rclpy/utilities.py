"""``rclpy.utilities``: the command-line helpers nodes use."""

from __future__ import annotations

import sys
from collections.abc import Sequence

from baobab.nav.ros.arguments import parse_ros_arguments
from baobab.nav.ros.rclpy.context import Context, get_default_context

__all__ = ["ok", "remove_ros_args", "try_shutdown"]


def remove_ros_args(args: Sequence[str] | None = None) -> list[str]:
    """``args`` (``sys.argv`` when None) without its ``--ros-args`` sections."""
    return parse_ros_arguments(list(sys.argv if args is None else args)).other


def ok(*, context: Context | None = None) -> bool:
    """True between ``rclpy.init()`` and ``rclpy.shutdown()``."""
    return (get_default_context() if context is None else context).ok()


def try_shutdown(*, context: Context | None = None) -> None:
    """Shut down unless already shut down."""
    (get_default_context(shutting_down=True) if context is None else context).try_shutdown()
