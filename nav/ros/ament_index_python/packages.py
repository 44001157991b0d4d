"""``ament_index_python.packages``: refused, as baobab runs local files, not installed packages."""

from __future__ import annotations

from typing import Any

from baobab.nav.ros.launch._entities import unsupported

__all__ = ["get_package_share_directory"]

get_package_share_directory = unsupported(
    "ament_index_python.packages", "get_package_share_directory"
)


def __getattr__(name: str) -> Any:
    return unsupported("ament_index_python.packages", name)
