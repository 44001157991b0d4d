"""The ``arm`` port over the Panda's :class:`~baobab.robots.panda.arm_server.ArmServer`.

Mission leaves speak :class:`~baobab.behaviours.ports.ArmPort` (plain sequences, quaternions
x, y, z, w, world frame); the server speaks its own ``Pose``. This adapter converts between
the two and reads free objects' positions from the simulation, standing in for perception.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco

from baobab.robots.panda.arm_server import ArmServer
from baobab.robots.panda.errors import GripperCommandError, PandaSceneError
from baobab.robots.panda.pose import Pose
from baobab.sim.simulation import Simulation
from baobab.sim.tasks import TaskHandle


class PandaArmPort:
    """:class:`~baobab.behaviours.ports.ArmPort` for a Panda served by ``server`` in ``sim``
    (structurally: robots do not import the behaviours above them)."""

    def __init__(self, sim: Simulation, server: ArmServer) -> None:
        self.sim = sim
        self.server = server

    def move_to(
        self, position: Sequence[float], orientation_xyzw: Sequence[float], duration: float
    ) -> TaskHandle:
        """Move the TCP to ``position`` (m) and ``orientation_xyzw`` in ``duration`` s."""
        x, y, z = (float(v) for v in position)
        qx, qy, qz, qw = (float(v) for v in orientation_xyzw)
        return self.server.move_to(Pose((x, y, z), (qx, qy, qz, qw)), duration)

    def gripper(self, command: str) -> TaskHandle:
        """``"open"`` or ``"close"`` the hand."""
        if command == "open":
            return self.server.gripper("open")
        if command == "close":
            return self.server.gripper("close")
        raise GripperCommandError(f"gripper command must be 'open' or 'close', got {command!r}")

    def object_position(self, name: str) -> tuple[float, float, float]:
        """World position (m) of the free body ``name`` (e.g. ``cube``)."""
        if mujoco.mj_name2id(self.sim.model, mujoco.mjtObj.mjOBJ_BODY, name) < 0:
            raise PandaSceneError(f"the scene has no object '{name}'")
        x, y, z = (float(v) for v in self.sim.data.body(name).xpos)
        return x, y, z

    def tcp_pose(self) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        """The TCP position (m) and orientation (x, y, z, w), world frame."""
        pose = self.server.tcp_pose()
        return pose.position, pose.quaternion
