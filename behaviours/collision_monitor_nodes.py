"""The collision monitor's leaf: ``toggle_collision_monitor``, Nav2's ToggleCollisionMonitor.

``toggle_collision_monitor: false`` turns the monitor's zones off (commands then pass as the
controller sends them, and only its own collision checks act); ``true`` turns them on again.
The leaf calls the ``collision_monitor/toggle`` service once per activation and succeeds when
the service does. It needs a collision monitor: a ``collision_monitor:`` block in the
mission, its world or its robot.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pydantic import Field

from baobab.behaviours.ports import COLLISION_MONITOR
from baobab.behaviours.registry import BehaviourType, BuildRequest, NodeKind, NodeParams

if TYPE_CHECKING:  # imported by the factory, when a tree is built (validation needs none)
    import py_trees


class ToggleCollisionMonitorParams(NodeParams):
    """Turn the collision monitor's zones on (``enable: true``) or off."""

    enable: bool = Field(default=True, description="true: zones on; false: commands pass")

    def summary(self) -> str:
        """``on`` or ``off``."""
        return "on" if self.enable else "off"


def _toggle_collision_monitor(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    from baobab.behaviours.actions import ServiceCall

    enable = request.params_as(ToggleCollisionMonitorParams).enable
    caps = request.capabilities
    return ServiceCall(request.name, lambda: caps.collision_monitor_port().toggle(enable))


NODE_TYPES = (
    BehaviourType(
        "toggle_collision_monitor",
        NodeKind.ACTION,
        ToggleCollisionMonitorParams,
        "turn the collision monitor's zones on or off",
        _toggle_collision_monitor,
        capability=COLLISION_MONITOR,
        shorthand="enable",
    ),
)
"""The collision monitor's node types."""
