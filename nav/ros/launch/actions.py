"""``launch.actions``: arguments, includes and log messages."""

from __future__ import annotations

from typing import Any

from baobab.nav.ros.launch._entities import (
    DeclareLaunchArgument,
    IncludeLaunchDescription,
    LogInfo,
    unsupported,
)

__all__ = ["DeclareLaunchArgument", "IncludeLaunchDescription", "LogInfo"]


def __getattr__(name: str) -> Any:
    return unsupported("launch.actions", name)
