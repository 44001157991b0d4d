"""Every setting of the navigation stack, in one record: :class:`NavigationParams`.

Its parts are the records of the pieces that use them (costmaps, planner, smoother, controller,
behaviours, navigators, velocity smoother, keepout filter); a Nav2 parameter file sets them
(:mod:`baobab.nav.nav2_configuration`), and :class:`~baobab.nav.server.NavigationServer` builds
the stack from them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from baobab.nav.behaviors import BehaviorParams
from baobab.nav.controller_server import ControllerParams
from baobab.nav.costmap_filters import KeepoutParams
from baobab.nav.layered_costmap import CostmapParams
from baobab.nav.navigate import NavigatorParams
from baobab.nav.planner import PlannerParams
from baobab.nav.plugged_servers import PluggedParams
from baobab.nav.smoother import SimpleSmoother
from baobab.nav.velocity_smoother import VelocitySmootherParams


@dataclass(frozen=True)
class NavigationParams:
    """Every navigation setting: Nav2's defaults with a robot's figures
    (:func:`~baobab.nav.robot_params.navigation_params`; the default robot's when built bare)."""

    global_costmap: CostmapParams = field(default_factory=CostmapParams)
    local_costmap: CostmapParams = field(default_factory=CostmapParams)
    local_costmap_size: tuple[float, float] = (3.0, 3.0)
    local_costmap_update_hz: float = 5.0
    global_costmap_update_hz: float = 1.0
    planner: PlannerParams = field(default_factory=PlannerParams)
    smoother: SimpleSmoother = field(default_factory=SimpleSmoother)
    controller: ControllerParams = field(default_factory=ControllerParams)
    behaviors: BehaviorParams = field(default_factory=BehaviorParams)
    navigator: NavigatorParams = field(default_factory=NavigatorParams)
    waypoint_loop_rate: float = 20.0
    waypoint_stop_on_failure: bool = True
    """FollowWaypoints ends at the first missed waypoint unless its caller says otherwise."""
    waypoint_pause: float = 0.0
    """Pause (s, sim time) at each reached waypoint unless its caller says otherwise."""
    velocity_smoother: VelocitySmootherParams = field(default_factory=VelocitySmootherParams)
    plugged: PluggedParams = field(default_factory=PluggedParams)
    keepout: KeepoutParams = field(default_factory=KeepoutParams)
