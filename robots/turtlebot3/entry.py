"""The TurtleBot3s in the robot registry: the Burger (its own body) and the Waffle."""

from __future__ import annotations

from baobab.robots.robot_info import DIFF_DRIVE_KERNEL, MOBILE_CAPABILITIES, RobotInfo
from baobab.robots.turtlebot3.facts import BURGER, WAFFLE

ENTRIES = (
    RobotInfo(
        name="turtlebot3",
        description="TurtleBot3 Burger: differential drive, 0.22 m/s, LDS-01 lidar",
        capabilities=MOBILE_CAPABILITIES,
        facts=BURGER,
        body="baobab.robots.turtlebot3.model:turtlebot3_spec",
        prefix="tb3/",
        kernel=DIFF_DRIVE_KERNEL,
        aliases=("turtlebot3_burger",),
    ),
    RobotInfo(
        name="turtlebot3_waffle",
        description="TurtleBot3 Waffle: 0.28 x 0.31 m footprint, 0.26 m/s, LDS lidar",
        capabilities=MOBILE_CAPABILITIES,
        facts=WAFFLE,
        prefix="tb3/",
        kernel=DIFF_DRIVE_KERNEL,
    ),
)
"""This folder's robots, as :mod:`baobab.robots.catalog` lists them."""
