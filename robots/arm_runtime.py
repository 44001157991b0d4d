"""What the mission runner asks of a fixed robot (an arm): the module its registry entry names.

A fixed robot's :attr:`~baobab.robots.catalog.RobotInfo.runtime` is a module that satisfies
:class:`ArmRuntime`: it builds the robot's scene and server, adapts the server to the ``arm``
port, and names what the faults, recordings, video and expectations need. The server is the
robot's own type; the runner only passes it back to the runtime or reads what the rig needs.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    import numpy as np

    from baobab.sim.camera import CameraPose
    from baobab.sim.simulation import Simulation


@dataclass
class SimulatedArm:
    """An arm under Cartesian impedance control in its own simulation, as the ROS runtime sees
    it. Poses are in the arm's base frame ``base_frame``: position (m) and quaternion x, y, z, w.

    Attributes:
        sim: the simulation (the arm's scene), its control loop running.
        base_frame: the ROS name of the arm's base frame.
        base_in_world: the base frame's pose in the world: position and quaternion.
        tcp_pose: the measured TCP pose.
        reference_pose: the filtered reference the impedance law tracks.
        set_target: the set-point the reference filters towards.
        joints: (ROS joint name, MuJoCo joint name) of the arm and finger joints.
        contact_steps: control steps in which the arm touched its surroundings so far.
    """

    sim: Simulation
    base_frame: str
    base_in_world: tuple[tuple[float, float, float], tuple[float, float, float, float]]
    tcp_pose: Callable[[], tuple[Any, Any]]
    reference_pose: Callable[[], tuple[Any, Any]]
    set_target: Callable[[Any, Any], None]
    joints: tuple[tuple[str, str], ...]
    contact_steps: Callable[[], int]


class ArmRuntime(Protocol):
    """A fixed robot's runtime module (see the module docstring)."""

    PREFIX: str
    """Name prefix of the robot's MuJoCo elements."""
    ROOT_JOINT: str
    """The joint whose generalised force a ``diverge`` fault makes NaN (prefixed)."""
    BASE_FRAME: str
    """The frame of the arm's base (prefixed), for recorded poses."""
    JOINT_NAMES: Sequence[str]
    """The joints ``/joint_states`` records (prefixed)."""

    def build(self, seed: int) -> tuple[Simulation, Any]:
        """The robot's scene, compiled and seeded, and its running server."""
        ...

    def arm_port(self, sim: Simulation, server: Any) -> Any:
        """The ``arm`` capability port over ``server``."""
        ...

    def place_target(self, sim: Simulation) -> np.ndarray:
        """World position (m) of the scene's place target."""
        ...

    def video_view(self, sim: Simulation, aspect: float) -> CameraPose:
        """The video's fixed view of the scene for frames ``aspect`` wide over high."""
        ...

    def simulated_arm(self, sim: Simulation, server: Any) -> SimulatedArm:
        """The ROS runtime's view of the running arm (its frames, joints and poses)."""
        ...
