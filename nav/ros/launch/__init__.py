"""``launch``: launch descriptions (see :mod:`.entities` for what is supported)."""

from __future__ import annotations

from typing import Any

from baobab.nav.ros.launch._entities import LaunchDescription, Substitution, unsupported

__all__ = ["LaunchDescription", "Substitution"]


def __getattr__(name: str) -> Any:
    return unsupported("launch", name)
