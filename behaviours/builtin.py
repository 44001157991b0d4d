"""The built-in node types: every node module's ``NODE_TYPES``, registered in one order.

The order is that of ``baobab list``, the JSON Schema's node variants and the BT.CPP
``TreeNodesModel``. A new node module goes into :data:`NODE_MODULES`.
"""

from __future__ import annotations

import functools
from types import ModuleType

from baobab.behaviours import (
    arm_nodes,
    collision_monitor_nodes,
    common_nodes,
    control_nodes,
    dock_nodes,
    follow_nodes,
    gps_nodes,
    navigation_nodes,
    progress_nodes,
    ros_nodes,
    route_nodes,
)
from baobab.behaviours.registry import Registry

NODE_MODULES: tuple[ModuleType, ...] = (
    control_nodes,
    common_nodes,
    navigation_nodes,
    dock_nodes,
    follow_nodes,
    collision_monitor_nodes,
    route_nodes,
    gps_nodes,
    progress_nodes,
    arm_nodes,
    ros_nodes,
)
"""The modules whose ``NODE_TYPES`` make the built-in vocabulary, in registration order."""


@functools.cache
def default_registry() -> Registry:
    """The registry of every built-in node type (built once per process)."""
    registry = Registry()
    for module in NODE_MODULES:
        for behaviour_type in module.NODE_TYPES:
            registry.register(behaviour_type)
    return registry
