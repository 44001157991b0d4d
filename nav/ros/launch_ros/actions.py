"""``launch_ros.actions``: nodes."""

from __future__ import annotations

from typing import Any

from baobab.nav.ros.launch._entities import Node, unsupported

__all__ = ["Node"]


def __getattr__(name: str) -> Any:
    return unsupported("launch_ros.actions", name)
