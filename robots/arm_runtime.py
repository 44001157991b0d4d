"""What the mission runner asks of a fixed robot (an arm): the module its registry entry names.

A fixed robot's :attr:`~baobab.robots.catalog.RobotInfo.runtime` is a module that satisfies
:class:`ArmRuntime`: it builds the robot's scene and server, adapts the server to the ``arm``
port, and names what the faults, recordings, video and expectations need. The server is the
robot's own type; the runner only passes it back to the runtime or reads what the rig needs.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Protocol

if TYPE_CHECKING:
    import numpy as np

    from baobab.sim.camera import CameraPose
    from baobab.sim.simulation import Simulation


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
