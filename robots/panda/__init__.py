"""Franka Emika Panda: MJCF model, Cartesian impedance control, trajectories, gripper, pick.

Quick start::

    from baobab.robots.panda import build_panda_sim, pick_and_place, place_target

    sim, arm = build_panda_sim(seed=3)
    report = pick_and_place(sim, arm, place_target(sim)[:2])
"""

from baobab.robots.panda.arm_server import ArmErrorCode, ArmServer, ArmServerConfig
from baobab.robots.panda.errors import (
    GainsError,
    GripperCommandError,
    PandaSceneError,
    PoseError,
    TrajectoryGoalError,
)
from baobab.robots.panda.gripper import Gripper
from baobab.robots.panda.impedance import CartesianImpedanceController, ImpedanceGains
from baobab.robots.panda.model import PANDA_XML, PandaModel
from baobab.robots.panda.pick import PickReport, PickSettings, pick_and_place
from baobab.robots.panda.pose import Pose
from baobab.robots.panda.scene import build_panda_sim, cube_pose, panda_table_spec, place_target
from baobab.robots.panda.trajectory import (
    PANDA_CARTESIAN_LIMITS,
    CartesianLimits,
    LinearTrajectory,
    TimeScaling,
    TrajectoryGoal,
    parse_goal,
)

__all__ = [
    "PANDA_CARTESIAN_LIMITS",
    "PANDA_XML",
    "ArmErrorCode",
    "ArmServer",
    "ArmServerConfig",
    "CartesianImpedanceController",
    "CartesianLimits",
    "GainsError",
    "Gripper",
    "GripperCommandError",
    "ImpedanceGains",
    "LinearTrajectory",
    "PandaModel",
    "PandaSceneError",
    "PickReport",
    "PickSettings",
    "Pose",
    "PoseError",
    "TimeScaling",
    "TrajectoryGoal",
    "TrajectoryGoalError",
    "build_panda_sim",
    "cube_pose",
    "panda_table_spec",
    "parse_goal",
    "pick_and_place",
    "place_target",
]
