"""The TurtleBot 4 in the robot registry (the generic differential-drive body)."""

from __future__ import annotations

from baobab.robots.robot_info import DIFF_DRIVE_KERNEL, MOBILE_CAPABILITIES, RobotInfo
from baobab.robots.turtlebot4.facts import TURTLEBOT4

ENTRIES = (
    RobotInfo(
        name="turtlebot4",
        description="TurtleBot 4: Create 3 base (0.34 m round, 0.31 m/s), RPLIDAR A1M8",
        capabilities=MOBILE_CAPABILITIES,
        facts=TURTLEBOT4,
        prefix="tb4/",
        kernel=DIFF_DRIVE_KERNEL,
    ),
)
"""This folder's robot, as :mod:`baobab.robots.catalog` lists it."""
