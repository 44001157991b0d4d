"""The Franka Panda in the robot registry: a fixed arm in its own scene, served by
:mod:`.runtime` (imported only when a run builds it)."""

from __future__ import annotations

from baobab.robots.robot_info import ARM, GRIPPER, ROS_NODES, RobotInfo

ENTRIES = (
    RobotInfo(
        name="panda",
        description="Franka Panda arm with a parallel gripper, Cartesian impedance control",
        capabilities=frozenset({ARM, GRIPPER, ROS_NODES}),
        scenes=("panda_table",),
        scene_objects=("cube",),
        runtime="baobab.robots.panda.runtime",
        error_codes="baobab.robots.panda.errors:ArmErrorCode",
        kernel=("baobab.robots.panda.native_loop", "_arm_kernel"),
    ),
)
"""This folder's robot, as :mod:`baobab.robots.catalog` lists it."""
