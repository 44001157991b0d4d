"""The TurtleBot3 Burger: MuJoCo model, differential-drive base, and the tutorial controllers.

- :mod:`.model`: the Burger's figures and body (MjSpec), :func:`attach_turtlebot3`.
- :mod:`.robot`: :func:`build_turtlebot3_sim` (world + robot + running base and lidar).
- :mod:`.base`: :class:`DiffDriveBase` (cmd_vel with limits, wheel odometry, ground truth).
- :mod:`.go_to_goal`, :mod:`.bug2`, :mod:`.teleop`: the seed's §6, §7 and §5 controllers.
"""

from baobab.robots.turtlebot3.base import BASE_CONTROL_PERIOD, DiffDriveBase, Odometry
from baobab.robots.turtlebot3.bug2 import (
    Bug2Controller,
    Bug2Params,
    dist_to_mline,
    follow_left_wall,
    min_range_in_sector,
)
from baobab.robots.turtlebot3.go_to_goal import (
    GoToGoalController,
    GoToGoalParams,
    NavState,
    angle_wrap,
    go_to_goal_command,
    goal_distance,
)
from baobab.robots.turtlebot3.model import (
    BURGER,
    DEFAULT_PREFIX,
    BurgerFacts,
    TurtleBot3Names,
    attach_turtlebot3,
    turtlebot3_spec,
)
from baobab.robots.turtlebot3.robot import TurtleBot3, build_turtlebot3_sim, start_turtlebot3
from baobab.robots.turtlebot3.teleop import (
    LAYOUTS,
    KeyboardTeleop,
    KeyLayout,
    Twist2D,
    layout_named,
    twist_from_keys,
)

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
