"""The Panda's description and facts, and its Pinocchio model built from the same MJCF.

``panda.xml`` is the one description: MuJoCo compiles it (alone or attached to a scene) and
Pinocchio parses it with ``pin.buildModelFromMJCF``. The Pinocchio model keeps the two finger
joints (nq = nv = 9, arm first), so its dynamics match MuJoCo's with the fingers wherever they
are; the arm-only quantities are the first seven rows and columns.

Figures are the Franka "Robot and interface specifications" values collected in
reference/manip_mujoco.md §1.2.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pinocchio as pin

PANDA_XML = Path(__file__).with_name("panda.xml")
"""The robot-only MJCF (arm + hand), link0 at the origin."""

ARM_JOINTS = tuple(f"joint{i}" for i in range(1, 8))
"""The seven arm joints, base to wrist; the torque actuators carry the same names."""

FINGER_JOINTS = ("finger_joint1", "finger_joint2")
"""The two finger slide joints (m), each 0 (closed) .. 0.04 (open)."""

BASE_BODY = "link0"
HAND_BODY = "hand"
TCP_SITE = "tcp"
"""The tool centre point between the finger pads, 0.1034 m along the hand's z axis."""

GRIPPER_ACTUATOR = "gripper"
LEFT_FINGER_BODY = "left_finger"
RIGHT_FINGER_BODY = "right_finger"
LEFT_PAD_GEOM = "left_pad"
RIGHT_PAD_GEOM = "right_pad"
"""The grasp pads, one per fingertip; a grasp is both pads touching the same body."""

ARM_DOF = 7
MAX_OPENING = 0.08
"""Largest distance between the fingers (m)."""

TORQUE_LIMITS = np.array([87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0])
"""Joint torque limits (N m)."""

TORQUE_RATE_LIMIT = 1000.0
"""Joint torque rate limit (N m/s), the same for every joint."""

HOME_CONFIGURATION = np.array(
    [0.0, -math.pi / 4, 0.0, -3 * math.pi / 4, 0.0, math.pi / 2, math.pi / 4]
)
"""Franka's "ready" pose (rad): TCP 0.307 m ahead of and 0.487 m above the base, pointing down."""


class PandaModel:
    """Pinocchio kinematics and dynamics of the Panda, expressed in the base (link0) frame.

    Args:
        mjcf: path of the robot-only MJCF (default: the bundled ``panda.xml``).
        gravity: gravity in the base frame (m/s^2); pass ``R_world_base.T @ g_world`` when the
            base is tilted. Default: -9.81 along z.
    """

    def __init__(self, mjcf: Path = PANDA_XML, *, gravity: np.ndarray | None = None) -> None:
        self.model = pin.buildModelFromMJCF(str(mjcf))
        if gravity is not None:
            self.model.gravity.linear = np.asarray(gravity, dtype=float)
        self.data = self.model.createData()
        self.tcp_frame = self.model.getFrameId(TCP_SITE)
        self.joint_names: tuple[str, ...] = tuple(self.model.names[1:])

    @property
    def nq(self) -> int:
        """Configuration size: 7 arm joints then 2 fingers."""
        return int(self.model.nq)

    def tcp_pose(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """TCP position (m) and rotation matrix in the base frame at configuration ``q``."""
        pin.forwardKinematics(self.model, self.data, q)
        placement = pin.updateFramePlacement(self.model, self.data, self.tcp_frame)
        return placement.translation.copy(), placement.rotation.copy()

    def tcp_jacobian(self, q: np.ndarray) -> np.ndarray:
        """6 x nv TCP Jacobian (linear rows first) in the base-aligned frame at the TCP.

        This is MuJoCo's ``mj_jacSite`` (jacp; jacr) when the base is the world.
        """
        return pin.computeFrameJacobian(
            self.model, self.data, q, self.tcp_frame, pin.LOCAL_WORLD_ALIGNED
        )

    def mass_matrix(self, q: np.ndarray) -> np.ndarray:
        """Joint-space inertia matrix (nv x nv, armature included, kg m^2 / kg)."""
        return pin.crba(self.model, self.data, q).copy()

    def nonlinear_effects(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Coriolis, centrifugal and gravity torques C(q, v) v + g(q) (N m / N)."""
        return pin.nonLinearEffects(self.model, self.data, q, v).copy()

    def gravity_torques(self, q: np.ndarray) -> np.ndarray:
        """Gravity torques g(q) (N m / N)."""
        return pin.computeGeneralizedGravity(self.model, self.data, q).copy()
