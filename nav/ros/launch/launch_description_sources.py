"""``launch.launch_description_sources``: Python launch files to include."""

from __future__ import annotations

from typing import Any

from baobab.nav.ros.launch._entities import PythonLaunchDescriptionSource, unsupported

__all__ = ["PythonLaunchDescriptionSource"]


def __getattr__(name: str) -> Any:
    return unsupported("launch.launch_description_sources", name)
