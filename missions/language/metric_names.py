"""The metrics a robot's runs measure, by name: what ``expect: metrics:`` may bound.

Known before any physics (``baobab validate`` checks the names); a run's rig registers exactly
these (``tests/test_validate_first.py`` holds the two together).
"""

from __future__ import annotations

from baobab.robots.catalog import RobotInfo

MOBILE_METRICS = (
    "sim_time",
    "path_length",
    "straight_line_distance",
    "min_clearance",
    "contacts",
    "min_keepout_clearance",
    "speed_limit_excess",
    "number_of_recoveries",
    "planned_path_length",
    "costmap_clears",
    "replans",
    "teleop_min_scaling",
    "teleop_slowed_cycles",
    "teleop_max_speed",
    "teleop_costmap_clears",
)
"""The numeric metrics of a mobile robot's run (``baobab.missions.run.rig.MobileRig``)."""
FILTER_METRICS = {"min_keepout_clearance": "keepout", "speed_limit_excess": "speed"}
"""Metrics measured against a costmap filter mask, by the mask they need (null without it)."""
MOBILE_STRUCTURED_METRICS = ("contact_objects", "start_pose", "final_pose", "visited")
ARM_METRICS = ("sim_time", "tcp_path_length", "object_max_lift", "contacts")
"""The numeric metrics of every arm run; each scene object adds ``<object>_max_lift``, and
``placement_error`` and ``max_tracking_error`` follow (``ArmRig``)."""


def metric_names(robot: RobotInfo) -> tuple[str, ...]:
    """The numeric metrics of ``robot``'s runs (what ``expect: metrics:`` may bound)."""
    if robot.mobile:
        return MOBILE_METRICS
    objects = robot.scene_objects
    per_object = tuple(f"{name}_max_lift" for name in objects)
    placement = ("placement_error",) if objects else ()
    return ARM_METRICS + per_object + placement + ("max_tracking_error",)


def structured_metric_names(robot: RobotInfo) -> tuple[str, ...]:
    """The metrics of ``robot``'s runs whose values are not numbers (poses, names)."""
    if robot.mobile:
        return MOBILE_STRUCTURED_METRICS
    return ("contact_objects", *(f"{name}_final_position" for name in robot.scene_objects))
