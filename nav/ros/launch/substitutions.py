"""``launch.substitutions``: launch argument values and fixed texts."""

from __future__ import annotations

from typing import Any

from baobab.nav.ros.launch._entities import LaunchConfiguration, TextSubstitution, unsupported

__all__ = ["LaunchConfiguration", "TextSubstitution"]


def __getattr__(name: str) -> Any:
    return unsupported("launch.substitutions", name)
