"""baobab's Nav2-style navigation stack: costmaps, planner, controller, recoveries, tasks.

The public names below load on first use (PEP 562), so importing a light module such as
``baobab.nav.msgs`` does not pull in numba, py_trees and the whole server.

- :class:`NavigationServer` and :func:`build_navigation`: the server a mission or a script
  drives, and the factory that wires it to an already-built robot.
- :class:`NavigationParams` and its parts; :class:`NavigationMetrics`.
- :class:`MobileBase` and :class:`ScanSource`: what the server needs from a robot.
- ``BasicNavigator``, ``TaskResult`` (and ``NavigationResult``, ``RunningTask``): the Nav2
  Simple Commander facade in :mod:`baobab.nav.navigator`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from baobab.sim.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from baobab.nav.behaviors import BehaviorParams
    from baobab.nav.controller_server import ControllerParams
    from baobab.nav.errors import NavigationError
    from baobab.nav.interfaces import MobileBase, ScanSource
    from baobab.nav.layered_costmap import CostmapParams
    from baobab.nav.navigate import NavigationMetrics, NavigatorParams
    from baobab.nav.navigation_params import NavigationParams
    from baobab.nav.path import Path
    from baobab.nav.planner import PlannerParams
    from baobab.nav.server import NavigationServer, build_navigation
    from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus

_EXPORTS = {
    "BehaviorParams": "baobab.nav.behaviors",
    "ControllerParams": "baobab.nav.controller_server",
    "CostmapParams": "baobab.nav.layered_costmap",
    "MobileBase": "baobab.nav.interfaces",
    "NavigationError": "baobab.nav.errors",
    "NavigationMetrics": "baobab.nav.navigate",
    "NavigationParams": "baobab.nav.navigation_params",
    "NavigationServer": "baobab.nav.server",
    "NavigatorParams": "baobab.nav.navigate",
    "Path": "baobab.nav.path",
    "PlannerParams": "baobab.nav.planner",
    "ScanSource": "baobab.nav.interfaces",
    "TaskHandle": "baobab.sim.tasks",
    "TaskOutcome": "baobab.sim.tasks",
    "TaskStatus": "baobab.sim.tasks",
    "build_navigation": "baobab.nav.server",
}
_NAVIGATOR_EXPORTS = ("BasicNavigator", "NavigationResult", "RunningTask", "TaskResult")
"""Defined by :mod:`baobab.nav.navigator`."""

__all__ = [
    "BehaviorParams",
    "ControllerParams",
    "CostmapParams",
    "MobileBase",
    "NavigationError",
    "NavigationMetrics",
    "NavigationParams",
    "NavigationServer",
    "NavigatorParams",
    "Path",
    "PlannerParams",
    "ScanSource",
    "TaskHandle",
    "TaskOutcome",
    "TaskStatus",
    "build_navigation",
]


__getattr__, __dir__ = lazy_exports(
    __name__,
    {**_EXPORTS, **dict.fromkeys(_NAVIGATOR_EXPORTS, "baobab.nav.navigator")},
    [*__all__, *_NAVIGATOR_EXPORTS],
)
