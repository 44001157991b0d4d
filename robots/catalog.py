"""The robots a mission may name, with the facts validation needs before any physics.

Figures are the TurtleBot3 Burger's (:data:`baobab.robots.turtlebot3.model.BURGER`) and the bundled
Panda scene's (``sim/worlds/panda_table.xml``: a table and a 5 cm cube named ``cube``). Importing
this module loads nothing else: ``baobab validate`` reads it without MuJoCo.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

NAVIGATION = "navigation"
"""A Nav2-style navigation server (:mod:`baobab.nav`)."""
BASE_CONTROLLERS = "base_controllers"
"""The tutorial base controllers: go-to-goal and Bug2."""
ARM = "arm"
"""Cartesian tool moves and a gripper."""
TELEOP = "teleop"
"""Teleop input that events hold (assisted teleop reads it)."""
ROS_NODES = "ros_nodes"
"""rclpy node files run on the robot, which is on ROS topics (:mod:`baobab.nav.ros`)."""
COLLISION_MONITOR = "collision_monitor"
"""Nav2's collision monitor on the base's commands, when a ``collision_monitor:`` block
configures one (:mod:`baobab.nav.collision_monitor`)."""


@dataclass(frozen=True)
class RobotInfo:
    """What a mission can ask of one robot.

    Attributes:
        name: the ``robot:`` value.
        description: one line for ``baobab list``.
        capabilities: capability names, e.g. ``navigation``.
        mobile: True for a base that drives on a 2D world's floor (needs ``world``/``start``).
        footprint_radius: radius of the base's footprint (m); goals closer than this to an
            obstacle are refused. 0 for fixed robots.
        max_linear_speed: forward speed limit (m/s); 0 for fixed robots.
        max_angular_speed: turn rate limit (rad/s); 0 for fixed robots.
        scenes: for fixed robots, the scene names ``world:`` may give (first = default).
        scene_objects: free objects of those scenes, by name (``relative_to:`` targets).
        has_lidar: True when the robot carries a 2D lidar (``noise: lidar_std`` applies).
        collision_monitor: the robot's own ``collision_monitor:`` parameters (Nav2's names),
            which a world's and a mission's block override; None for none.
    """

    name: str
    description: str
    capabilities: frozenset[str]
    mobile: bool
    footprint_radius: float = 0.0
    max_linear_speed: float = 0.0
    max_angular_speed: float = 0.0
    scenes: tuple[str, ...] = ()
    scene_objects: tuple[str, ...] = ()
    has_lidar: bool = False
    collision_monitor: Mapping[str, Any] | None = None

    def describe_capabilities(self) -> str:
        """``arm`` or ``base_controllers, navigation, teleop``."""
        return ", ".join(sorted(self.capabilities))


ROBOTS: dict[str, RobotInfo] = {
    "turtlebot3": RobotInfo(
        name="turtlebot3",
        description="TurtleBot3 Burger: differential drive with a 360-beam 2D lidar",
        capabilities=frozenset(
            {NAVIGATION, BASE_CONTROLLERS, TELEOP, ROS_NODES, COLLISION_MONITOR}
        ),
        mobile=True,
        footprint_radius=0.105,
        max_linear_speed=0.22,
        max_angular_speed=2.84,
        has_lidar=True,
    ),
    "panda": RobotInfo(
        name="panda",
        description="Franka Panda arm with a parallel gripper, Cartesian impedance control",
        capabilities=frozenset({ARM, ROS_NODES}),
        mobile=False,
        scenes=("panda_table",),
        scene_objects=("cube",),
    ),
}
