"""``launch_ros.parameter_descriptions``: a parameter value with an explicit type."""

from __future__ import annotations

from typing import Any

from baobab.nav.ros.launch._entities import ParameterValue, unsupported

__all__ = ["ParameterValue"]


def __getattr__(name: str) -> Any:
    return unsupported("launch_ros.parameter_descriptions", name)
