"""A Cartesian pose: position (m) and unit quaternion x, y, z, w."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from baobab.robots.panda.errors import PoseError


@dataclass(frozen=True)
class Pose:
    """A rigid-body pose in some frame (the arm server uses the world frame).

    Attributes:
        position: x, y, z (m).
        quaternion: x, y, z, w; normalised on construction.

    Raises:
        PoseError: on a wrong number of values or a near-zero quaternion.
    """

    position: tuple[float, float, float]
    quaternion: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0)

    def __post_init__(self) -> None:
        # Plain floats and math: poses are built at sampling rates (tcp_pose), and numpy's
        # per-call overhead would dominate for seven numbers.
        try:
            position = tuple(map(float, self.position))
            quaternion = tuple(map(float, self.quaternion))
        except (TypeError, ValueError) as error:
            raise PoseError(f"pose values must be numbers: {error}") from error
        if len(position) != 3 or len(quaternion) != 4:
            raise PoseError("a pose needs 3 position values and 4 quaternion values (x, y, z, w)")
        norm = math.hypot(*quaternion)
        if not norm > 1e-9:
            raise PoseError(f"the pose quaternion has near-zero norm ({norm:.3g})")
        object.__setattr__(self, "position", position)
        object.__setattr__(self, "quaternion", tuple(v / norm for v in quaternion))

    @classmethod
    def from_rotation(cls, position: Sequence[float] | np.ndarray, rotation: Rotation) -> Pose:
        """Pose from a position (m) and a scipy ``Rotation``."""
        x, y, z = (float(v) for v in position)
        qx, qy, qz, qw = (float(v) for v in rotation.as_quat())
        return cls((x, y, z), (qx, qy, qz, qw))

    @classmethod
    def top_down(cls, position: Sequence[float] | np.ndarray, yaw: float = 0.0) -> Pose:
        """A grasp pose with the tool z axis pointing down and yaw ``yaw`` (rad) about world z.

        At yaw 0 the tool x axis is world +x and the fingers close along world y.
        """
        rotation = Rotation.from_euler("z", yaw) * Rotation.from_euler("x", np.pi)
        return cls.from_rotation(position, rotation)

    @property
    def rotation(self) -> Rotation:
        """The orientation as a scipy ``Rotation``."""
        return Rotation.from_quat(self.quaternion)

    @property
    def position_array(self) -> np.ndarray:
        """The position as a (3,) array (m)."""
        return np.array(self.position)

    def translated(self, dx: float = 0.0, dy: float = 0.0, dz: float = 0.0) -> Pose:
        """The same orientation, moved by (dx, dy, dz) m."""
        x, y, z = self.position
        return Pose((x + dx, y + dy, z + dz), self.quaternion)

    def distance_to(self, other: Pose) -> tuple[float, float]:
        """Position distance (m) and rotation angle (rad) between this pose and ``other``."""
        distance = float(np.linalg.norm(self.position_array - other.position_array))
        angle = float((self.rotation.inv() * other.rotation).magnitude())
        return distance, angle
