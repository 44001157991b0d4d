"""The Nav2 plugins a parameter file may name: the ones baobab runs, and stated substitutes.

A Nav2 server loads plugins by instance name (``controller_plugins: [FollowPath]``) and class
(``FollowPath.plugin: nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController``).
:data:`PLUGIN_LISTS` says where each server lists its instances and which instances it has
when the file lists none; :data:`PLUGINS` says, per class, whether baobab runs it (its rows
are in :mod:`baobab.nav.nav2_param_table`) or what it runs instead when the user accepts a
substitute (``--nav2-substitute``): Regulated Pure Pursuit with an MPPI or DWB controller's
speed limits, the 2D grid planner for Smac Hybrid-A*, Lattice or Theta*, and so on. A class
baobab does not know at all (a custom plugin) gets its kind's substitute.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from baobab.nav.nav2_param_rows import Mapped, non_negative, positive
from baobab.nav.nav2_param_table import PLUGIN_ROWS

_RPP_CLASS = "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController"


@dataclass(frozen=True)
class PluginKind:
    """One kind of plugin a server loads.

    Attributes:
        label: what the kind is called in messages ("controller").
        node: the server node that lists the instances.
        list_names: the list parameter's name, then older names Nav2 still reads.
        defaults: instance name -> class, what Nav2 loads when the file lists none.
        single: baobab runs one instance of this kind (the first listed, or the one named
            like Nav2's default); the others' parameters are unused.
        substitute: what baobab runs instead of a plugin of this kind it does not have.
        disabled: ``NavigationParams`` fields an instance with ``enabled: false`` sets.
    """

    label: str
    node: str
    list_names: tuple[str, ...]
    defaults: dict[str, str]
    single: bool
    substitute: str
    disabled: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class PluginInfo:
    """A plugin class baobab knows.

    Attributes:
        kind: the kind's label.
        native: baobab runs it as Nav2 does.
        rows: the parameters baobab reads from its instance (native: its own; substituted:
            the ones the substitute takes over, e.g. MPPI's ``vx_max``).
        substitute: for a non-native class, what runs instead (shown in the error and the
            report).
    """

    kind: str
    native: bool
    rows: tuple[Mapped, ...] = ()
    substitute: str = ""


def canonical_class(name: str) -> str:
    """A plugin class as ``package::Class`` (Humble and older write ``package/Class``)."""
    return name.strip().replace("/", "::")


_COSTMAP_LAYERS = {
    "static_layer": "nav2_costmap_2d::StaticLayer",
    "obstacle_layer": "nav2_costmap_2d::ObstacleLayer",
    "inflation_layer": "nav2_costmap_2d::InflationLayer",
}


def _costmap_kinds(node: str) -> tuple[PluginKind, PluginKind]:
    layers = PluginKind(
        "costmap layer", node, ("plugins",), _COSTMAP_LAYERS, False, "the layer is left out"
    )
    filters = PluginKind("costmap filter", node, ("filters",), {}, False, "the filter is left out")
    return layers, filters


PLUGIN_LISTS: tuple[PluginKind, ...] = (
    PluginKind(
        "controller",
        "controller_server",
        ("controller_plugins",),
        {"FollowPath": _RPP_CLASS},
        True,
        "Regulated Pure Pursuit",
    ),
    PluginKind(
        "goal checker",
        "controller_server",
        ("goal_checker_plugins", "goal_checker_plugin"),
        {"goal_checker": "nav2_controller::SimpleGoalChecker"},
        True,
        "SimpleGoalChecker",
    ),
    PluginKind(
        "progress checker",
        "controller_server",
        ("progress_checker_plugins", "progress_checker_plugin"),
        {"progress_checker": "nav2_controller::SimpleProgressChecker"},
        True,
        "SimpleProgressChecker",
    ),
    PluginKind(
        "planner",
        "planner_server",
        ("planner_plugins",),
        {"GridBased": "nav2_navfn_planner::NavfnPlanner"},
        True,
        "baobab's 2D grid A* (Smac 2D's costs)",
    ),
    PluginKind(
        "smoother",
        "smoother_server",
        ("smoother_plugins",),
        {"simple_smoother": "nav2_smoother::SimpleSmoother"},
        True,
        "SimpleSmoother",
    ),
    PluginKind(
        "behavior",
        "behavior_server",
        ("behavior_plugins", "recovery_plugins"),
        {
            "spin": "nav2_behaviors::Spin",
            "backup": "nav2_behaviors::BackUp",
            "drive_on_heading": "nav2_behaviors::DriveOnHeading",
            "wait": "nav2_behaviors::Wait",
            "assisted_teleop": "nav2_behaviors::AssistedTeleop",
        },
        False,
        "the behaviour is left out",
    ),
    PluginKind(
        "navigator",
        "bt_navigator",
        ("navigators",),
        {
            "navigate_to_pose": "nav2_bt_navigator::NavigateToPoseNavigator",
            "navigate_through_poses": "nav2_bt_navigator::NavigateThroughPosesNavigator",
        },
        False,
        "the navigator is left out",
    ),
    PluginKind(
        "waypoint task executor",
        "waypoint_follower",
        ("waypoint_task_executor_plugin",),
        {"wait_at_waypoint": "nav2_waypoint_follower::WaitAtWaypoint"},
        True,
        "no task at the waypoints",
        {"waypoint_pause": 0.0},
    ),
    *_costmap_kinds("global_costmap"),
    *_costmap_kinds("local_costmap"),
)
"""Every plugin list baobab reads, per server."""

_RPP = "controller.rpp."


def _speed(name: str, target: str, unit: str, meaning: str) -> Mapped:
    return Mapped(name, (_RPP + target,), float, unit, None, meaning, positive)


def _planner_rows(tolerance_default: float) -> tuple[Mapped, ...]:
    return (
        Mapped(
            "tolerance",
            ("planner.tolerance",),
            float,
            "m",
            tolerance_default,
            "goal tolerance",
            non_negative,
        ),
        Mapped("allow_unknown", ("planner.allow_unknown",), bool, "", True, "plan through unknown"),
    )


def _goal_checker_rows() -> tuple[Mapped, ...]:
    rows = PLUGIN_ROWS["nav2_controller::SimpleGoalChecker"]
    return tuple(row for row in rows if row.name != "stateful")


def _native(kind: str, rows: tuple[Mapped, ...] = ()) -> PluginInfo:
    return PluginInfo(kind, True, rows)


def _substituted(kind: str, substitute: str, rows: tuple[Mapped, ...] = ()) -> PluginInfo:
    return PluginInfo(kind, False, rows, substitute)


def _rpp_substitute(linear: str, angular: str) -> PluginInfo:
    """A controller Regulated Pure Pursuit stands in for, taking its top speed and turn rate
    from its parameters ``linear`` (m/s) and ``angular`` (rad/s)."""
    return _substituted(
        "controller",
        f"Regulated Pure Pursuit with its {linear} and {angular}",
        (
            _speed(linear, "desired_linear_vel", "m/s", "top forward speed"),
            _speed(angular, "max_angular_vel", "rad/s", "top turn rate"),
        ),
    )


_BEHAVIORS = ("Spin", "BackUp", "DriveOnHeading", "Wait", "AssistedTeleop")

PLUGINS: dict[str, PluginInfo] = {
    _RPP_CLASS: _native("controller", PLUGIN_ROWS[_RPP_CLASS]),
    "nav2_mppi_controller::MPPIController": _rpp_substitute("vx_max", "wz_max"),
    "dwb_core::DWBLocalPlanner": _rpp_substitute("max_vel_x", "max_vel_theta"),
    "nav2_graceful_controller::GracefulController": _rpp_substitute(
        "v_linear_max", "v_angular_max"
    ),
    "nav2_rotation_shim_controller::RotationShimController": _substituted(
        "controller",
        "Regulated Pure Pursuit (its rotate-to-heading) with the shim's turn rate",
        (
            _speed(
                "rotate_to_heading_angular_vel",
                "rotate_to_heading_angular_vel",
                "rad/s",
                "turn rate",
            ),
        ),
    ),
    "nav2_controller::SimpleGoalChecker": _native(
        "goal checker", PLUGIN_ROWS["nav2_controller::SimpleGoalChecker"]
    ),
    "nav2_controller::StoppedGoalChecker": _substituted(
        "goal checker", "SimpleGoalChecker with its tolerances", _goal_checker_rows()
    ),
    "nav2_controller::PositionGoalChecker": _substituted(
        "goal checker", "SimpleGoalChecker with its xy tolerance", _goal_checker_rows()[:1]
    ),
    "nav2_controller::SimpleProgressChecker": _native(
        "progress checker", PLUGIN_ROWS["nav2_controller::SimpleProgressChecker"]
    ),
    "nav2_controller::PoseProgressChecker": _substituted(
        "progress checker",
        "SimpleProgressChecker with its radius and time",
        PLUGIN_ROWS["nav2_controller::SimpleProgressChecker"],
    ),
    "nav2_navfn_planner::NavfnPlanner": _native(
        "planner", PLUGIN_ROWS["nav2_navfn_planner::NavfnPlanner"]
    ),
    "nav2_smac_planner::SmacPlanner2D": _native(
        "planner", PLUGIN_ROWS["nav2_smac_planner::SmacPlanner2D"]
    ),
    "nav2_smac_planner::SmacPlannerHybrid": _substituted(
        "planner", "the 2D grid A* with its tolerance and allow_unknown", _planner_rows(0.25)
    ),
    "nav2_smac_planner::SmacPlannerLattice": _substituted(
        "planner", "the 2D grid A* with its tolerance and allow_unknown", _planner_rows(0.25)
    ),
    "nav2_theta_star_planner::ThetaStarPlanner": _substituted(
        "planner", "the 2D grid A* with its allow_unknown", _planner_rows(0.5)[1:]
    ),
    "nav2_smoother::SimpleSmoother": _native(
        "smoother", PLUGIN_ROWS["nav2_smoother::SimpleSmoother"]
    ),
    "nav2_smoother::SavitzkyGolaySmoother": _substituted("smoother", "SimpleSmoother"),
    "nav2_constrained_smoother::ConstrainedSmoother": _substituted("smoother", "SimpleSmoother"),
    **{f"nav2_behaviors::{name}": _native("behavior") for name in _BEHAVIORS},
    "nav2_bt_navigator::NavigateToPoseNavigator": _native("navigator"),
    "nav2_bt_navigator::NavigateThroughPosesNavigator": _native("navigator"),
    "nav2_waypoint_follower::WaitAtWaypoint": _native(
        "waypoint task executor", PLUGIN_ROWS["nav2_waypoint_follower::WaitAtWaypoint"]
    ),
    "nav2_waypoint_follower::PhotoAtWaypoint": _substituted(
        "waypoint task executor", "no task at the waypoints"
    ),
    "nav2_waypoint_follower::InputAtWaypoint": _substituted(
        "waypoint task executor", "no task at the waypoints"
    ),
    "nav2_costmap_2d::StaticLayer": _native("costmap layer"),
    "nav2_costmap_2d::ObstacleLayer": _native("costmap layer"),
    "nav2_costmap_2d::VoxelLayer": _native("costmap layer"),
    "nav2_costmap_2d::InflationLayer": _native(
        "costmap layer", PLUGIN_ROWS["nav2_costmap_2d::InflationLayer"]
    ),
    **{
        f"nav2_costmap_2d::{name}": _substituted("costmap layer", "the layer is left out")
        for name in ("RangeSensorLayer", "DenoiseLayer", "PluginContainerLayer")
    },
    "nav2_costmap_2d::KeepoutFilter": _native(
        "costmap filter", PLUGIN_ROWS["nav2_costmap_2d::KeepoutFilter"]
    ),
    "nav2_costmap_2d::SpeedFilter": _native("costmap filter"),
    **{
        f"nav2_costmap_2d::{name}": _substituted("costmap filter", "the filter is left out")
        for name in ("BinaryFilter", "ZoneParameterFilter")
    },
}
"""Plugin classes baobab knows, by canonical name."""


def native_classes(kind: str) -> list[str]:
    """The classes of ``kind`` baobab runs (listed in an unsupported plugin's error)."""
    return sorted(cls for cls, info in PLUGINS.items() if info.kind == kind and info.native)
