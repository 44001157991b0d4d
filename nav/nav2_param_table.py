"""Which Nav2 parameters baobab's navigation stack has an equivalent for, and where they go.

Each :class:`Mapped` row names a Nav2 parameter as a node or a plugin declares it, with Nav2's
meaning, unit and default (reference/nav2_ros_facts.md §11, docs.nav2.org's configuration
guide), its type and range, and the :class:`~baobab.nav.server.NavigationParams` fields it sets
(dotted paths; ``{costmap}`` stands for ``global_costmap`` or ``local_costmap``). Rows are
grouped per node (:data:`NODE_ROWS`) and per plugin class (:data:`PLUGIN_ROWS`, keyed by the
class's canonical ``package::Class`` name); a plugin's rows apply to the parameters under its
instance name (``FollowPath.desired_linear_vel``).

Parameters that only wire ROS together (``use_sim_time``, frames, topics, QoS, timeouts of
servers baobab does not run) are accepted and ignored: :func:`is_ros_only`.
"""

from __future__ import annotations

from baobab.nav.nav2_param_rows import (
    Mapped,
    axes,
    each_non_negative,
    each_non_positive,
    milliseconds,
    non_negative,
    non_positive,
    one_of,
    positive,
    row,
    same_names,
    tolerance_or_unlimited,
    unlimited,
)

_COSTMAP_ROWS = (
    row("resolution", "{costmap}.resolution", float, "m/cell", 0.1, "cell size", positive),
    row(
        "update_frequency",
        "{costmap}_update_hz",
        float,
        "Hz",
        5.0,
        "how often the layers take new sensor data",
        positive,
    ),
)
_STATIC_ROWS = (
    row(
        "track_unknown_space",
        "{costmap}.static.track_unknown_space",
        bool,
        "",
        False,
        "unknown map cells stay unknown instead of free",
    ),
    *same_names(
        "{costmap}.static.",
        ("lethal_cost_threshold", int, "", 100, "occupancy from which a cell is lethal", positive),
        ("unknown_cost_value", int, "", 255, "occupancy value read as unknown", non_negative),
        ("trinary_costmap", bool, "", True, "below lethal is free (else scaled)", None),
    ),
)
_LOCAL_COSTMAP_ROWS = (
    row("width", "local_costmap_size.0", float, "m", 5.0, "rolling window width", positive),
    row("height", "local_costmap_size.1", float, "m", 5.0, "rolling window height", positive),
)
_RPP = "controller.rpp."

NODE_ROWS: dict[str, tuple[Mapped, ...]] = {
    "global_costmap": _COSTMAP_ROWS + _STATIC_ROWS,
    "local_costmap": _COSTMAP_ROWS + _STATIC_ROWS + _LOCAL_COSTMAP_ROWS,
    "controller_server": (
        row(
            "controller_frequency",
            ("controller.controller_frequency", _RPP + "controller_frequency"),
            float,
            "Hz",
            20.0,
            "control loop rate",
            positive,
        ),
        row(
            "failure_tolerance",
            "controller.failure_tolerance",
            float,
            "s",
            0.0,
            "how long the controller may fail before FollowPath fails (-1: forever)",
            tolerance_or_unlimited,
            convert=unlimited,
        ),
    ),
    "behavior_server": same_names(
        "behaviors.",
        ("cycle_frequency", float, "Hz", 10.0, "behaviour loop rate", positive),
        ("simulate_ahead_time", float, "s", 2.0, "collision look-ahead", non_negative),
        ("max_rotational_vel", float, "rad/s", 1.0, "Spin's top speed", positive),
        ("min_rotational_vel", float, "rad/s", 0.4, "Spin's slowest speed", positive),
        ("rotational_acc_lim", float, "rad/s^2", 3.2, "Spin's acceleration", positive),
        ("acceleration_limit", float, "m/s^2", 2.5, "BackUp/DriveOnHeading accel.", positive),
        ("deceleration_limit", float, "m/s^2", -2.5, "BackUp/DriveOnHeading decel.", non_positive),
        ("minimum_speed", float, "m/s", 0.10, "BackUp/DriveOnHeading min speed", non_negative),
        ("projection_time", float, "s", 1.0, "AssistedTeleop look-ahead", positive),
        ("simulation_time_step", float, "s", 0.1, "AssistedTeleop look-ahead step", positive),
    ),
    "waypoint_follower": (
        row("loop_rate", "waypoint_loop_rate", float, "Hz", 20.0, "waypoint loop rate", positive),
        row(
            "stop_on_failure",
            "waypoint_stop_on_failure",
            bool,
            "",
            True,
            "end FollowWaypoints at the first missed waypoint",
        ),
    ),
    "velocity_smoother": (
        *(
            row(
                name,
                f"velocity_smoother.{name}",
                tuple,
                unit,
                default,
                meaning,
                check,
                convert=axes,
            )
            for name, unit, default, meaning, check in (
                (
                    "max_velocity",
                    "m/s, rad/s",
                    [0.5, 0.0, 2.5],
                    "highest command",
                    each_non_negative,
                ),
                (
                    "min_velocity",
                    "m/s, rad/s",
                    [-0.5, 0.0, -2.5],
                    "lowest command",
                    each_non_positive,
                ),
                ("max_accel", "m/s^2, rad/s^2", [2.5, 0.0, 3.2], "speeding up", each_non_negative),
                (
                    "max_decel",
                    "m/s^2, rad/s^2",
                    [-2.5, 0.0, -3.2],
                    "slowing down",
                    each_non_positive,
                ),
                (
                    "deadband_velocity",
                    "m/s, rad/s",
                    [0.0, 0.0, 0.0],
                    "speeds set to 0 below",
                    each_non_negative,
                ),
            )
        ),
        row(
            "scale_velocities",
            "velocity_smoother.scale_velocities",
            bool,
            "",
            False,
            "keep the curvature when limiting",
        ),
        row(
            "feedback",
            "velocity_smoother.feedback",
            str,
            "",
            "OPEN_LOOP",
            "ramp from the last command or from odometry",
            one_of("OPEN_LOOP", "CLOSED_LOOP"),
        ),
    ),
}
"""Rows of each node's own parameters (not a plugin's)."""

_RPP_ROWS = (
    row(
        "desired_linear_vel",
        _RPP + "desired_linear_vel",
        float,
        "m/s",
        0.5,
        "cruising speed",
        positive,
        aliases=("max_linear_vel",),
    ),
    *same_names(
        _RPP,
        ("max_angular_vel", float, "rad/s", 2.5, "turn rate limit", positive),
        ("lookahead_dist", float, "m", 0.6, "carrot distance", positive),
        ("min_lookahead_dist", float, "m", 0.3, "shortest scaled lookahead", positive),
        ("max_lookahead_dist", float, "m", 0.9, "longest scaled lookahead", positive),
        ("lookahead_time", float, "s", 1.5, "speed x this = lookahead", positive),
        (
            "use_velocity_scaled_lookahead_dist",
            bool,
            "",
            False,
            "lookahead grows with speed",
            None,
        ),
        ("use_interpolation", bool, "", True, "carrot interpolated on the path", None),
        ("use_rotate_to_heading", bool, "", True, "turn in place toward the path", None),
        (
            "rotate_to_heading_min_angle",
            float,
            "rad",
            0.785,
            "error that turns in place",
            non_negative,
        ),
        ("rotate_to_heading_angular_vel", float, "rad/s", 1.8, "in-place turn rate", positive),
        ("max_angular_accel", float, "rad/s^2", 3.2, "in-place turn acceleration", positive),
        ("use_regulated_linear_velocity_scaling", bool, "", True, "slow on tight curves", None),
        (
            "regulated_linear_scaling_min_radius",
            float,
            "m",
            0.9,
            "radius where slowing starts",
            positive,
        ),
        (
            "regulated_linear_scaling_min_speed",
            float,
            "m/s",
            0.25,
            "slowest regulated speed",
            non_negative,
        ),
        (
            "use_cost_regulated_linear_velocity_scaling",
            bool,
            "",
            True,
            "slow near obstacles",
            None,
        ),
        ("cost_scaling_dist", float, "m", 0.6, "obstacle distance where slowing starts", positive),
        ("cost_scaling_gain", float, "", 1.0, "how hard obstacles slow it", positive),
        ("inflation_cost_scaling_factor", float, "1/m", 3.0, "inflation's factor", positive),
        ("min_approach_linear_velocity", float, "m/s", 0.05, "slowest near the goal", non_negative),
        (
            "approach_velocity_scaling_dist",
            float,
            "m",
            0.6,
            "goal distance where slowing starts",
            non_negative,
        ),
        ("use_collision_detection", bool, "", True, "check the projected motion", None),
        (
            "max_allowed_time_to_collision_up_to_carrot",
            float,
            "s",
            1.0,
            "motion checked ahead",
            positive,
        ),
    ),
    row(
        "max_robot_pose_search_dist",
        _RPP + "max_robot_pose_search_dist",
        float,
        "m",
        0.0,
        "how far along the path the robot is looked for (<= 0: half the costmap)",
        convert=lambda value: value if value > 0 else None,
    ),
)
_SIMPLE_GOAL_ROWS = (
    row(
        "xy_goal_tolerance",
        ("controller.xy_goal_tolerance", _RPP + "goal_dist_tol"),
        float,
        "m",
        0.25,
        "distance within which the goal is reached",
        non_negative,
    ),
    *same_names(
        "controller.",
        ("yaw_goal_tolerance", float, "rad", 0.25, "heading error of a reached goal", non_negative),
        ("stateful", bool, "", True, "once within xy, only the heading is checked", None),
    ),
)
_SIMPLE_PROGRESS_ROWS = same_names(
    "controller.",
    ("required_movement_radius", float, "m", 0.5, "distance the robot must move", non_negative),
    ("movement_time_allowance", float, "s", 10.0, "time it has to move that far", positive),
)
_SHARED_PLANNER_ROWS = (
    ("allow_unknown", bool, "", True, "plan through unknown space", None),
    ("use_final_approach_orientation", bool, "", False, "last pose faces along the path", None),
)
_NAVFN_ROWS = same_names(
    "planner.",
    ("tolerance", float, "m", 0.5, "how far a blocked goal's substitute may be", non_negative),
    *_SHARED_PLANNER_ROWS,
)
_SMAC_2D_ROWS = same_names(
    "planner.",
    ("tolerance", float, "m", 0.125, "how far a blocked goal's substitute may be", non_negative),
    ("cost_travel_multiplier", float, "", 1.0, "how strongly paths avoid cost", non_negative),
    ("max_iterations", int, "", 1_000_000, "search budget (cells expanded)", positive),
    *_SHARED_PLANNER_ROWS,
)
_SIMPLE_SMOOTHER_ROWS = same_names(
    "smoother.",
    ("tolerance", float, "", 1e-10, "change below which an iteration stops", positive),
    ("max_its", int, "", 1000, "iterations per round", positive),
    ("w_data", float, "", 0.2, "weight toward the original path", non_negative),
    ("w_smooth", float, "", 0.3, "weight toward a smooth path", non_negative),
    ("do_refinement", bool, "", True, "smooth the result again", None),
    ("refinement_num", int, "", 2, "extra rounds", non_negative),
)
_INFLATION_ROWS = same_names(
    "{costmap}.",
    ("inflation_radius", float, "m", 0.55, "distance from obstacles that costs", non_negative),
    ("cost_scaling_factor", float, "1/m", 10.0, "how fast the cost falls off", positive),
)
OBSERVATION_ROWS = (
    row(
        "obstacle_max_range",
        "{costmap}.obstacle.obstacle_max_range",
        float,
        "m",
        2.5,
        "farthest hit that marks",
        positive,
        aliases=("obstacle_range",),
    ),
    row(
        "raytrace_max_range",
        "{costmap}.obstacle.raytrace_max_range",
        float,
        "m",
        3.0,
        "farthest a beam clears",
        positive,
        aliases=("raytrace_range",),
    ),
    *same_names(
        "{costmap}.obstacle.",
        ("obstacle_min_range", float, "m", 0.0, "nearest hit that marks", non_negative),
        ("raytrace_min_range", float, "m", 0.0, "nearest a beam clears from", non_negative),
    ),
)
"""Rows of one observation source of an obstacle or voxel layer (under ``<layer>.<source>.``)."""
_WAIT_AT_WAYPOINT_ROWS = (
    row(
        "waypoint_pause_duration",
        "waypoint_pause",
        int,
        "ms",
        0,
        "pause at each reached waypoint",
        non_negative,
        convert=milliseconds,
    ),
)

_KEEPOUT_ROWS = (
    row(
        "override_lethal_cost",
        "keepout.override_lethal_cost",
        bool,
        "",
        False,
        "lower the zone's cost while the robot stands in it",
    ),
    row(
        "lethal_override_cost",
        "keepout.lethal_override_cost",
        int,
        "",
        252,
        "the cost written instead",
        lambda value: None if 0 <= value <= 252 else f"must be 0..252, got {value}",
    ),
)

PLUGIN_ROWS: dict[str, tuple[Mapped, ...]] = {
    "nav2_costmap_2d::KeepoutFilter": _KEEPOUT_ROWS,
    "nav2_regulated_pure_pursuit_controller::RegulatedPurePursuitController": _RPP_ROWS,
    "nav2_controller::SimpleGoalChecker": _SIMPLE_GOAL_ROWS,
    "nav2_controller::SimpleProgressChecker": _SIMPLE_PROGRESS_ROWS,
    "nav2_navfn_planner::NavfnPlanner": _NAVFN_ROWS,
    "nav2_smac_planner::SmacPlanner2D": _SMAC_2D_ROWS,
    "nav2_smoother::SimpleSmoother": _SIMPLE_SMOOTHER_ROWS,
    "nav2_costmap_2d::InflationLayer": _INFLATION_ROWS,
    "nav2_waypoint_follower::WaitAtWaypoint": _WAIT_AT_WAYPOINT_ROWS,
}
"""Rows of each plugin class baobab runs (its instance's parameters)."""

ROS_ONLY = frozenset(
    {
        "use_sim_time",
        "plugin_lib_names",
        "transform_tolerance",
        "always_send_full_costmap",
        "map_subscribe_transient_local",
        "subscribe_to_updates",
        "bt_loop_duration",
        "default_server_timeout",
        "wait_for_service_timeout",
        "action_server_result_timeout",
        "service_introspection_mode",
        "introspection_mode",
        "enable_groot_monitoring",
        "enable_stamped_cmd_vel",
        "bond_heartbeat_period",
        "bond_timeout",
        "autostart",
        "attempt_respawn_reconnection",
        "costmap_update_timeout",
        "clock_topic",
        "publish_frequency",
        "publish_zero_velocity",
        "error_code_names",
        "error_code_name_prefixes",
        "filter_info_topic",
        "qos_overrides",
    }
)
"""Parameter names that only wire ROS together; baobab has nothing to set with them."""
_ROS_ONLY_SUFFIXES = ("_topic", "_frame", "_frame_id", "_topic_name")
_ROS_ONLY_PREFIXES = ("groot", "qos_overrides")


def is_ros_only(name: str) -> bool:
    """Whether a (dotted) parameter name only wires ROS: frames, topics, time, QoS, timeouts."""
    last = name.rsplit(".", 1)[-1]
    return (
        last in ROS_ONLY
        or last.endswith(_ROS_ONLY_SUFFIXES)
        or last.startswith(_ROS_ONLY_PREFIXES)
        or name.startswith(_ROS_ONLY_PREFIXES)
    )
