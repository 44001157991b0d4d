"""Franka Emika Panda: MJCF model, Cartesian impedance control, trajectories, gripper, pick.

Quick start::

    from baobab.robots.panda import build_panda_sim, pick_and_place, place_target

    sim, arm = build_panda_sim(seed=3)
    report = pick_and_place(sim, arm, place_target(sim)[:2])

The public names load on first use (PEP 562), so importing one light submodule does not
load the others (MuJoCo models, controllers).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from baobab.sim.lazy_exports import lazy_exports

if TYPE_CHECKING:
    from baobab.robots.panda.arm_server import ArmServer, ArmServerConfig
    from baobab.robots.panda.errors import (
        ArmErrorCode,
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

_EXPORTS = {
    "ArmErrorCode": "baobab.robots.panda.errors",
    "ArmServer": "baobab.robots.panda.arm_server",
    "ArmServerConfig": "baobab.robots.panda.arm_server",
    "CartesianImpedanceController": "baobab.robots.panda.impedance",
    "CartesianLimits": "baobab.robots.panda.trajectory",
    "GainsError": "baobab.robots.panda.errors",
    "Gripper": "baobab.robots.panda.gripper",
    "GripperCommandError": "baobab.robots.panda.errors",
    "ImpedanceGains": "baobab.robots.panda.impedance",
    "LinearTrajectory": "baobab.robots.panda.trajectory",
    "PANDA_CARTESIAN_LIMITS": "baobab.robots.panda.trajectory",
    "PANDA_XML": "baobab.robots.panda.model",
    "PandaModel": "baobab.robots.panda.model",
    "PandaSceneError": "baobab.robots.panda.errors",
    "PickReport": "baobab.robots.panda.pick",
    "PickSettings": "baobab.robots.panda.pick",
    "Pose": "baobab.robots.panda.pose",
    "PoseError": "baobab.robots.panda.errors",
    "TimeScaling": "baobab.robots.panda.trajectory",
    "TrajectoryGoal": "baobab.robots.panda.trajectory",
    "TrajectoryGoalError": "baobab.robots.panda.errors",
    "build_panda_sim": "baobab.robots.panda.scene",
    "cube_pose": "baobab.robots.panda.scene",
    "panda_table_spec": "baobab.robots.panda.scene",
    "parse_goal": "baobab.robots.panda.trajectory",
    "pick_and_place": "baobab.robots.panda.pick",
    "place_target": "baobab.robots.panda.scene",
}
"""Public name -> the module defining it."""

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


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)
