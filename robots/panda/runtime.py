"""The Panda as the mission runner drives it: the :class:`~baobab.robots.arm_runtime.ArmRuntime`
its registry entry names (scene and server, arm port, joints, video view, its ROS view)."""

from __future__ import annotations

from typing import Any

import numpy as np

from baobab.robots.arm_runtime import SimulatedArm
from baobab.robots.panda.arm_port import PandaArmPort
from baobab.robots.panda.arm_server import ArmServer
from baobab.robots.panda.model import ARM_JOINTS, BASE_BODY, FINGER_JOINTS
from baobab.robots.panda.quaternion import matrix_to_quaternion
from baobab.robots.panda.scene import PREFIX, build_panda_sim, place_target, video_view
from baobab.sim.simulation import Simulation

__all__ = [
    "BASE_FRAME",
    "JOINT_NAMES",
    "PREFIX",
    "ROOT_JOINT",
    "arm_port",
    "build",
    "place_target",
    "simulated_arm",
    "video_view",
]

ROOT_JOINT = PREFIX + ARM_JOINTS[0]
BASE_FRAME = PREFIX + BASE_BODY
JOINT_NAMES = tuple(PREFIX + name for name in (*ARM_JOINTS, *FINGER_JOINTS))


def build(seed: int) -> tuple[Simulation, ArmServer]:
    """The ``panda_table`` scene seeded with ``seed`` (the cube where the seed puts it)."""
    return build_panda_sim(seed=seed)


def arm_port(sim: Simulation, server: ArmServer) -> PandaArmPort:
    """The ``arm`` port over ``server``."""
    return PandaArmPort(sim, server)


def simulated_arm(sim: Simulation, server: ArmServer) -> SimulatedArm:
    """The ROS runtime's view of a running Panda: ``panda_link0`` and ``panda_*`` joints, as
    the Franka ROS description names them."""
    controller = server.controller

    def tcp_pose() -> tuple[Any, Any]:
        position, rotation = controller.tcp
        quaternion = np.empty(4)
        matrix_to_quaternion(rotation, quaternion)
        return position, quaternion

    base = server.base_position.tolist()
    qx, qy, qz, qw = server.base_rotation.as_quat().tolist()
    return SimulatedArm(
        sim=sim,
        base_frame="panda_link0",
        base_in_world=((base[0], base[1], base[2]), (qx, qy, qz, qw)),
        tcp_pose=tcp_pose,
        reference_pose=lambda: controller.reference,
        set_target=lambda position, quaternion: controller.set_target(
            np.asarray(position, dtype=float), np.asarray(quaternion, dtype=float)
        ),
        joints=tuple(
            (f"panda_{name}", f"{server.prefix}{name}") for name in (*ARM_JOINTS, *FINGER_JOINTS)
        ),
        contact_steps=lambda: server.contact_steps,
    )
