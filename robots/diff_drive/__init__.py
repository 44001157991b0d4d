"""The differential-drive mobile robot every two-wheeled base of the registry is.

- :mod:`.facts`: :class:`DiffDriveFacts`, the one record of a robot's figures.
- :mod:`.model`: the generic body built from facts, the shared wheel, attaching to a world.
- :mod:`.robot`: :func:`build_mobile_sim` (world + robot + running base and lidar).
- :mod:`.base`: :class:`DiffDriveBase` (cmd_vel with limits, wheel odometry, ground truth).
- :mod:`.go_to_goal`, :mod:`.bug2`, :mod:`.teleop`: the seed's §6, §7 and §5 controllers.

The public names load on first use (PEP 562), so importing the facts does not load MuJoCo.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from baobab.sim.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from baobab.robots.diff_drive.base import BASE_CONTROL_PERIOD, DiffDriveBase, Odometry
    from baobab.robots.diff_drive.bug2 import (
        Bug2Controller,
        Bug2Params,
        dist_to_mline,
        follow_left_wall,
        min_range_in_sector,
    )
    from baobab.robots.diff_drive.facts import Body, Caster, DiffDriveFacts, LidarFacts
    from baobab.robots.diff_drive.go_to_goal import (
        GoToGoalController,
        GoToGoalParams,
        NavState,
        angle_wrap,
        go_to_goal_command,
        goal_distance,
    )
    from baobab.robots.diff_drive.model import attach_robot, diff_drive_spec
    from baobab.robots.diff_drive.names import DiffDriveNames
    from baobab.robots.diff_drive.robot import MobileRobot, build_mobile_sim, start_mobile_robot
    from baobab.robots.diff_drive.teleop import (
        LAYOUTS,
        KeyboardTeleop,
        KeyLayout,
        Twist2D,
        layout_named,
        twist_from_keys,
    )

_EXPORTS = {
    "BASE_CONTROL_PERIOD": "baobab.robots.diff_drive.base",
    "Body": "baobab.robots.diff_drive.facts",
    "Bug2Controller": "baobab.robots.diff_drive.bug2",
    "Bug2Params": "baobab.robots.diff_drive.bug2",
    "Caster": "baobab.robots.diff_drive.facts",
    "DiffDriveBase": "baobab.robots.diff_drive.base",
    "DiffDriveFacts": "baobab.robots.diff_drive.facts",
    "DiffDriveNames": "baobab.robots.diff_drive.names",
    "GoToGoalController": "baobab.robots.diff_drive.go_to_goal",
    "GoToGoalParams": "baobab.robots.diff_drive.go_to_goal",
    "KeyLayout": "baobab.robots.diff_drive.teleop",
    "KeyboardTeleop": "baobab.robots.diff_drive.teleop",
    "LAYOUTS": "baobab.robots.diff_drive.teleop",
    "LidarFacts": "baobab.robots.diff_drive.facts",
    "MobileRobot": "baobab.robots.diff_drive.robot",
    "NavState": "baobab.robots.diff_drive.go_to_goal",
    "Odometry": "baobab.robots.diff_drive.base",
    "Twist2D": "baobab.robots.diff_drive.teleop",
    "angle_wrap": "baobab.robots.diff_drive.go_to_goal",
    "attach_robot": "baobab.robots.diff_drive.model",
    "build_mobile_sim": "baobab.robots.diff_drive.robot",
    "diff_drive_spec": "baobab.robots.diff_drive.model",
    "dist_to_mline": "baobab.robots.diff_drive.bug2",
    "follow_left_wall": "baobab.robots.diff_drive.bug2",
    "go_to_goal_command": "baobab.robots.diff_drive.go_to_goal",
    "goal_distance": "baobab.robots.diff_drive.go_to_goal",
    "layout_named": "baobab.robots.diff_drive.teleop",
    "min_range_in_sector": "baobab.robots.diff_drive.bug2",
    "start_mobile_robot": "baobab.robots.diff_drive.robot",
    "twist_from_keys": "baobab.robots.diff_drive.teleop",
}
"""Public name -> the module defining it."""

__all__ = [
    "BASE_CONTROL_PERIOD",
    "LAYOUTS",
    "Body",
    "Bug2Controller",
    "Bug2Params",
    "Caster",
    "DiffDriveBase",
    "DiffDriveFacts",
    "DiffDriveNames",
    "GoToGoalController",
    "GoToGoalParams",
    "KeyLayout",
    "KeyboardTeleop",
    "LidarFacts",
    "MobileRobot",
    "NavState",
    "Odometry",
    "Twist2D",
    "angle_wrap",
    "attach_robot",
    "build_mobile_sim",
    "diff_drive_spec",
    "dist_to_mline",
    "follow_left_wall",
    "go_to_goal_command",
    "goal_distance",
    "layout_named",
    "min_range_in_sector",
    "start_mobile_robot",
    "twist_from_keys",
]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)
