"""The TurtleBot3 Burger: MuJoCo model, differential-drive base, and the tutorial controllers.

- :mod:`.model`: the Burger's figures and body (MjSpec), :func:`attach_turtlebot3`.
- :mod:`.robot`: :func:`build_turtlebot3_sim` (world + robot + running base and lidar).
- :mod:`.base`: :class:`DiffDriveBase` (cmd_vel with limits, wheel odometry, ground truth).
- :mod:`.go_to_goal`, :mod:`.bug2`, :mod:`.teleop`: the seed's §6, §7 and §5 controllers.

The public names load on first use (PEP 562), so importing one light submodule does not
load the others (MuJoCo models, controllers).
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
    from baobab.robots.diff_drive.go_to_goal import (
        GoToGoalController,
        GoToGoalParams,
        NavState,
        angle_wrap,
        go_to_goal_command,
        goal_distance,
    )
    from baobab.robots.diff_drive.robot import TurtleBot3, build_turtlebot3_sim, start_turtlebot3
    from baobab.robots.diff_drive.teleop import (
        LAYOUTS,
        KeyboardTeleop,
        KeyLayout,
        Twist2D,
        layout_named,
        twist_from_keys,
    )
    from baobab.robots.turtlebot3.model import (
        BURGER,
        DEFAULT_PREFIX,
        BurgerFacts,
        TurtleBot3Names,
        attach_turtlebot3,
        turtlebot3_spec,
    )

_EXPORTS = {
    "BASE_CONTROL_PERIOD": "baobab.robots.diff_drive.base",
    "BURGER": "baobab.robots.turtlebot3.model",
    "Bug2Controller": "baobab.robots.diff_drive.bug2",
    "Bug2Params": "baobab.robots.diff_drive.bug2",
    "BurgerFacts": "baobab.robots.turtlebot3.model",
    "DEFAULT_PREFIX": "baobab.robots.turtlebot3.model",
    "DiffDriveBase": "baobab.robots.diff_drive.base",
    "GoToGoalController": "baobab.robots.diff_drive.go_to_goal",
    "GoToGoalParams": "baobab.robots.diff_drive.go_to_goal",
    "KeyLayout": "baobab.robots.diff_drive.teleop",
    "KeyboardTeleop": "baobab.robots.diff_drive.teleop",
    "LAYOUTS": "baobab.robots.diff_drive.teleop",
    "NavState": "baobab.robots.diff_drive.go_to_goal",
    "Odometry": "baobab.robots.diff_drive.base",
    "TurtleBot3": "baobab.robots.diff_drive.robot",
    "TurtleBot3Names": "baobab.robots.turtlebot3.model",
    "Twist2D": "baobab.robots.diff_drive.teleop",
    "angle_wrap": "baobab.robots.diff_drive.go_to_goal",
    "attach_turtlebot3": "baobab.robots.turtlebot3.model",
    "build_turtlebot3_sim": "baobab.robots.diff_drive.robot",
    "dist_to_mline": "baobab.robots.diff_drive.bug2",
    "follow_left_wall": "baobab.robots.diff_drive.bug2",
    "go_to_goal_command": "baobab.robots.diff_drive.go_to_goal",
    "goal_distance": "baobab.robots.diff_drive.go_to_goal",
    "layout_named": "baobab.robots.diff_drive.teleop",
    "min_range_in_sector": "baobab.robots.diff_drive.bug2",
    "start_turtlebot3": "baobab.robots.diff_drive.robot",
    "turtlebot3_spec": "baobab.robots.turtlebot3.model",
    "twist_from_keys": "baobab.robots.diff_drive.teleop",
}
"""Public name -> the module defining it."""

__all__ = [
    "BASE_CONTROL_PERIOD",
    "BURGER",
    "DEFAULT_PREFIX",
    "LAYOUTS",
    "Bug2Controller",
    "Bug2Params",
    "BurgerFacts",
    "DiffDriveBase",
    "GoToGoalController",
    "GoToGoalParams",
    "KeyLayout",
    "KeyboardTeleop",
    "NavState",
    "Odometry",
    "TurtleBot3",
    "TurtleBot3Names",
    "Twist2D",
    "angle_wrap",
    "attach_turtlebot3",
    "build_turtlebot3_sim",
    "dist_to_mline",
    "follow_left_wall",
    "go_to_goal_command",
    "goal_distance",
    "layout_named",
    "min_range_in_sector",
    "start_turtlebot3",
    "turtlebot3_spec",
    "twist_from_keys",
]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)
