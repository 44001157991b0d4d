"""A robot's navigation settings: Nav2's defaults with what the robot's facts decide.

:func:`navigation_params` turns a robot's :class:`~baobab.robots.tuning.RobotTuning` (its
footprint, inflation, speed and acceleration limits, checker tolerances) into the stack's
:class:`~baobab.nav.server.NavigationParams`. The records' own defaults are the registry's
default mobile robot's, so ``navigation_params(default robot)`` equals ``NavigationParams()``.
"""

from __future__ import annotations

from baobab.nav.behaviors import BehaviorParams
from baobab.nav.controller_server import ControllerParams
from baobab.nav.layered_costmap import CostmapParams
from baobab.nav.pure_pursuit import RegulatedPurePursuitParams
from baobab.nav.server import NavigationParams
from baobab.robots.catalog import RobotInfo
from baobab.robots.tuning import RobotTuning


def navigation_params(robot: RobotInfo | RobotTuning) -> NavigationParams:
    """Nav2's settings for ``robot`` (a registry entry or its tuning).

    Raises:
        ValueError: for a robot that does not drive (no facts to tune).
    """
    tuning = robot.tuning if isinstance(robot, RobotInfo) else robot
    costmap = CostmapParams(
        footprint=tuning.footprint,
        inflation_radius=tuning.inflation_radius,
        cost_scaling_factor=tuning.cost_scaling_factor,
    )
    pursuit = RegulatedPurePursuitParams(
        desired_linear_vel=tuning.max_linear_speed,
        max_angular_vel=tuning.max_angular_speed,
        rotate_to_heading_angular_vel=tuning.rotate_to_heading_speed,
        max_angular_accel=tuning.max_angular_accel,
        regulated_linear_scaling_min_speed=tuning.min_regulated_speed,
        inflation_cost_scaling_factor=tuning.cost_scaling_factor,
    )
    xy_tolerance, yaw_tolerance = tuning.goal_tolerances
    movement_radius, movement_time = tuning.progress
    controller = ControllerParams(
        xy_goal_tolerance=xy_tolerance,
        yaw_goal_tolerance=yaw_tolerance,
        required_movement_radius=movement_radius,
        movement_time_allowance=movement_time,
        rpp=pursuit,
    )
    slowest, fastest = tuning.spin_speeds
    behaviors = BehaviorParams(
        max_rotational_vel=fastest,
        min_rotational_vel=slowest,
        rotational_acc_lim=tuning.max_angular_accel,
        acceleration_limit=tuning.max_linear_accel,
        deceleration_limit=-tuning.max_linear_accel,
        minimum_speed=tuning.backup_min_speed,
    )
    return NavigationParams(
        global_costmap=costmap,
        local_costmap=costmap,
        controller=controller,
        behaviors=behaviors,
    )
