"""``nav2_simple_commander.robot_navigator``: ``BasicNavigator`` and its result enums."""

from __future__ import annotations

from baobab.nav.ros._navigator_exports import NAVIGATOR_NAMES, navigator_export

__all__ = list(NAVIGATOR_NAMES)


def __getattr__(name: str) -> object:
    return navigator_export(__name__, name)


def __dir__() -> list[str]:
    return sorted({*globals(), *NAVIGATOR_NAMES})
