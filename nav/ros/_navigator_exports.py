"""The names Nav2's ``robot_navigator`` module exports, fetched from baobab's navigator lazily.

Importing the shim modules must not build a navigator (or even import its module): a script's
``from robot_navigator import BasicNavigator`` is what loads ``baobab.nav.navigator``.
"""

from __future__ import annotations

import importlib

NAVIGATOR_MODULE = "baobab.nav.navigator"
"""Where ``BasicNavigator`` and its enums live."""

NAVIGATOR_NAMES = ("BasicNavigator", "NavigationResult", "RunningTask", "TaskResult")
"""What ``robot_navigator`` exports (``NavigationResult`` is the pre-Galactic ``TaskResult``)."""


def navigator_export(module_name: str, name: str) -> object:
    """The navigator's ``name``, for the module-level ``__getattr__`` of ``module_name``.

    Raises:
        AttributeError: ``name`` is not one of :data:`NAVIGATOR_NAMES`.
    """
    if name not in NAVIGATOR_NAMES:
        shown = module_name.removeprefix(f"{__package__}.")
        raise AttributeError(f"module {shown!r} has no attribute {name!r}")
    return getattr(importlib.import_module(NAVIGATOR_MODULE), name)
