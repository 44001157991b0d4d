"""The Panda as the mission runner drives it: the :class:`~baobab.robots.arm_runtime.ArmRuntime`
its registry entry names (scene and server, arm port, joints, video view)."""

from __future__ import annotations

from baobab.robots.panda.arm_port import PandaArmPort
from baobab.robots.panda.arm_server import ArmServer
from baobab.robots.panda.model import ARM_JOINTS, BASE_BODY, FINGER_JOINTS
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
