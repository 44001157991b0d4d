"""The robot registry: every robot a mission may name, with its facts and what it provides.

A robot is one :class:`RobotInfo`: its name, the capabilities it provides, and, for a mobile
robot, its facts (:class:`~baobab.robots.diff_drive.facts.DiffDriveFacts`: dimensions,
footprint, wheels, masses, limits, lidar) from which its MuJoCo model is built and its
navigation, teleop and fault-monitor defaults derived (:attr:`RobotInfo.tuning`). A fixed robot
names its scenes and the module that builds and serves it. Consumers ask this registry; only it
and the robots' own folders name a robot. A user's robot file
(:mod:`baobab.robots.robot_file`) gives a :class:`RobotInfo` of the same kind.

Importing this module loads no numpy and no MuJoCo: ``baobab validate`` reads it.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from baobab.robots.diff_drive.facts import DiffDriveFacts
from baobab.robots.footprint import Footprint
from baobab.robots.tuning import RobotTuning, tune
from baobab.robots.turtlebot3.facts import BURGER, WAFFLE
from baobab.robots.turtlebot4.facts import TURTLEBOT4

if TYPE_CHECKING:  # the physics loads only when a robot is built
    from baobab.robots.arm_runtime import ArmRuntime
    from baobab.robots.diff_drive.robot import MobileRobot
    from baobab.sim.simulation import Simulation
    from baobab.sim.world import Pose2D, World

BASE = "base"
"""A differential-drive base that takes ``cmd_vel``."""
LIDAR = "lidar"
"""A planar lidar (``noise: lidar_std`` and the lidar faults apply)."""
NAVIGATION = "navigation"
"""A Nav2-style navigation server (:mod:`baobab.nav`)."""
BASE_CONTROLLERS = "base_controllers"
"""The tutorial base controllers: go-to-goal and Bug2."""
TELEOP = "teleop"
"""Teleop input that events hold (assisted teleop reads it)."""
ROS_NODES = "ros_nodes"
"""rclpy node files run on the robot, which is on ROS topics (:mod:`baobab.nav.ros`)."""
ARM = "arm"
"""Cartesian tool moves."""
GRIPPER = "gripper"
"""A parallel gripper (driven through the ``arm`` port)."""

MOBILE_CAPABILITIES = frozenset({BASE, LIDAR, NAVIGATION, BASE_CONTROLLERS, TELEOP, ROS_NODES})
"""What every differential-drive robot with a lidar provides."""


@dataclass(frozen=True)
class RobotInfo:
    """One robot of the registry (or a user's robot file).

    Attributes:
        name: the ``robot:`` value.
        description: one line for ``baobab list``.
        capabilities: capability names, e.g. ``navigation``.
        facts: a mobile robot's facts; None for a fixed robot.
        body: ``module:function`` that builds a mobile robot's own MjSpec from its facts;
            empty for the generic differential-drive body.
        prefix: the name prefix of the robot's MuJoCo elements.
        scenes: for fixed robots, the scene names ``world:`` may give (first = default).
        scene_objects: free objects of those scenes, by name (``relative_to:`` targets).
        runtime: for fixed robots, the module that builds and serves the robot.
        kernel: ``(module, function)`` of the compiled kernel its runs need first.
        error_codes: ``module:name`` of the IntEnum its own tasks fail with (an arm's).
        aliases: other names a mission may give it.
        path: the robot file a user's robot was read from; empty for a bundled one.
    """

    name: str
    description: str
    capabilities: frozenset[str]
    facts: DiffDriveFacts | None = None
    body: str = ""
    prefix: str = "robot/"
    scenes: tuple[str, ...] = ()
    scene_objects: tuple[str, ...] = ()
    runtime: str = ""
    kernel: tuple[str, str] | None = None
    error_codes: str = ""
    aliases: tuple[str, ...] = ()
    path: str = ""

    @property
    def mobile(self) -> bool:
        """True for a base that drives on a 2D world's floor (needs ``world``/``start``)."""
        return self.facts is not None

    @property
    def mobile_facts(self) -> DiffDriveFacts:
        """The facts of a mobile robot.

        Raises:
            ValueError: for a fixed robot (a programming error).
        """
        if self.facts is None:
            raise ValueError(f"robot '{self.name}' is not mobile")
        return self.facts

    @property
    def footprint(self) -> Footprint | None:
        """A mobile robot's real outline (unpadded); None for a fixed robot."""
        return None if self.facts is None else self.facts.footprint

    @property
    def footprint_radius(self) -> float:
        """Radius (m) of the circle around ``base_link`` holding the footprint; 0 if fixed."""
        return 0.0 if self.facts is None else self.facts.footprint_radius

    @property
    def max_linear_speed(self) -> float:
        """Forward speed limit (m/s); 0 for fixed robots."""
        return 0.0 if self.facts is None else self.facts.max_linear_speed

    @property
    def max_angular_speed(self) -> float:
        """Turn rate limit (rad/s); 0 for fixed robots."""
        return 0.0 if self.facts is None else self.facts.max_angular_speed

    @property
    def has_lidar(self) -> bool:
        """True when the robot carries a 2D lidar."""
        return LIDAR in self.capabilities

    @property
    def tuning(self) -> RobotTuning:
        """A mobile robot's navigation, teleop and fault-monitor defaults (from its facts)."""
        return tune(self.mobile_facts)

    def build_sim(
        self,
        world: World | str,
        start: Pose2D | None = None,
        *,
        seed: int = 0,
        lidar_noise_std: float = 0.0,
    ) -> tuple[Simulation, MobileRobot]:
        """Build ``world`` with this mobile robot at ``start`` (default: the world's spawn),
        compile it and start the robot (base controller and lidar).

        Raises:
            WorldError: the world cannot be loaded.
        """
        from baobab.robots.diff_drive.model import diff_drive_spec  # MuJoCo: only to build
        from baobab.robots.diff_drive.robot import build_mobile_sim

        body = load_attribute(self.body) if self.body else diff_drive_spec
        return build_mobile_sim(
            world,
            self.mobile_facts,
            start,
            body=body,
            prefix=self.prefix,
            seed=seed,
            lidar_noise_std=lidar_noise_std,
        )

    def arm_runtime(self) -> ArmRuntime:
        """A fixed robot's runtime module (imported now: it loads the robot's physics).

        Raises:
            ValueError: for a robot without one (a programming error).
        """
        if not self.runtime:
            raise ValueError(f"robot '{self.name}' has no arm runtime")
        runtime: ArmRuntime = importlib.import_module(self.runtime)
        return runtime

    def describe_capabilities(self) -> str:
        """``arm, gripper`` or ``base, base_controllers, lidar, navigation, teleop``."""
        return ", ".join(sorted(self.capabilities))


DEFAULT_MOBILE_ROBOT = "turtlebot3"
"""The robot whose defaults a navigation stack built without a robot uses."""

DIFF_DRIVE_KERNEL = ("baobab.robots.diff_drive.base_kernel", "base_kernel")
"""The compiled kernel every differential-drive robot's runs need first."""

ROBOTS: dict[str, RobotInfo] = {
    robot.name: robot
    for robot in (
        RobotInfo(
            name="turtlebot3",
            description="TurtleBot3 Burger: differential drive, 0.22 m/s, LDS-01 lidar",
            capabilities=MOBILE_CAPABILITIES,
            facts=BURGER,
            body="baobab.robots.turtlebot3.model:turtlebot3_spec",
            prefix="tb3/",
            kernel=DIFF_DRIVE_KERNEL,
            aliases=("turtlebot3_burger",),
        ),
        RobotInfo(
            name="turtlebot3_waffle",
            description="TurtleBot3 Waffle: 0.28 x 0.31 m footprint, 0.26 m/s, LDS lidar",
            capabilities=MOBILE_CAPABILITIES,
            facts=WAFFLE,
            prefix="tb3/",
            kernel=DIFF_DRIVE_KERNEL,
        ),
        RobotInfo(
            name="turtlebot4",
            description="TurtleBot 4: Create 3 base (0.34 m round, 0.31 m/s), RPLIDAR A1M8",
            capabilities=MOBILE_CAPABILITIES,
            facts=TURTLEBOT4,
            prefix="tb4/",
            kernel=DIFF_DRIVE_KERNEL,
        ),
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
}
"""Every bundled robot by name."""

ALIASES: dict[str, str] = {
    alias: robot.name for robot in ROBOTS.values() for alias in robot.aliases
}
"""Other names of bundled robots -> their names."""

ROBOT_NAMES: tuple[str, ...] = (*ROBOTS, *ALIASES)
"""Every name a mission's ``robot:`` may give."""

MOBILE_ROBOTS: tuple[str, ...] = tuple(name for name, robot in ROBOTS.items() if robot.mobile)
"""The bundled mobile robots, by name."""


def load_attribute(reference: str) -> Any:
    """What a ``module:name`` reference names (the module is imported now)."""
    module, _, name = reference.partition(":")
    return getattr(importlib.import_module(module), name)


def robot_named(name: str) -> RobotInfo | None:
    """The bundled robot called ``name`` (or one of its aliases), or None."""
    return ROBOTS.get(ALIASES.get(name, name))


def default_mobile_robot() -> RobotInfo:
    """The robot :data:`DEFAULT_MOBILE_ROBOT` names."""
    return ROBOTS[DEFAULT_MOBILE_ROBOT]
