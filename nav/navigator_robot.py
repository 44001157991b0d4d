"""The simulated robot a :class:`~baobab.nav.navigator.BasicNavigator` drives.

The navigation server takes any :class:`~baobab.nav.interfaces.MobileBase` and
:class:`~baobab.nav.interfaces.ScanSource`. The Nav2 facade is different, because a Nav2 script
constructs ``BasicNavigator()`` and expects a robot to be there: :func:`build_simulated_robot`
builds the one the robot registry (or a user's robot file) describes, and the navigation
settings its facts decide (``baobab.robots`` is the layer below ``nav``; robots never import
nav). The ROS runtime's robots (:mod:`baobab.nav.ros.sim_topics`) come from here too: a mobile
robot with what its topics need (odometry, joints, fixed frames, all from its facts), and an
arm from its runtime (:func:`build_simulated_arm`).

Checking a pose (:func:`check_free`, :func:`pose_is_free`) loads no physics: ``baobab nav2``
and ``baobab teleop`` refuse a blocked start before MuJoCo and the robot's compiled loop load,
so the robot's physics is built only when a robot is.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from baobab.robots.arm_runtime import SimulatedArm
from baobab.robots.catalog import MOBILE_ROBOTS, ROBOTS, RobotInfo, default_mobile_robot
from baobab.robots.footprint import Footprint
from baobab.robots.robot_file import UnknownRobotError, load_robot
from baobab.sim.errors import BaobabError
from baobab.sim.world import Pose2D, World

if TYPE_CHECKING:  # checking a pose (baobab nav2, baobab teleop) loads no physics
    from baobab.nav.interfaces import MobileBase, ScanSource
    from baobab.robots.diff_drive.robot import MobileRobot
    from baobab.sim.simulation import Simulation

__all__ = [
    "ARM_MODELS",
    "ROBOT_MODELS",
    "NavigatorSetupError",
    "SimulatedArm",
    "SimulatedRobot",
    "StaticFrame",
    "build_simulated_arm",
    "build_simulated_robot",
    "check_free",
    "navigator_robot",
    "pose_is_free",
    "simulated_robot",
]

ROBOT_MODELS = MOBILE_ROBOTS
"""The bundled robots a navigator drives (a robot file drives too)."""

ARM_MODELS = tuple(name for name, robot in ROBOTS.items() if robot.runtime)
"""The bundled arms the ROS runtime runs besides :data:`ROBOT_MODELS`."""


@dataclass(frozen=True)
class StaticFrame:
    """A fixed transform of the robot's frame tree: ``child`` at ``xyz`` (m) in ``parent``,
    rotated by the quaternion ``xyzw``."""

    parent: str
    child: str
    xyz: tuple[float, float, float]
    xyzw: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 1.0)


class NavigatorSetupError(BaobabError, ValueError):
    """A navigator asked for something that cannot be built: an unknown robot, a blocked pose."""


@dataclass
class SimulatedRobot:
    """A robot running in its own simulation, as the navigator needs it.

    Attributes:
        info: the robot's registry entry (or its robot file's).
        sim: the simulation (world + robot), its callbacks registered.
        base: the drive, ground-truth pose in the map frame (the sim localises perfectly).
        lidar: the 2D scanner feeding the costmaps.
        teleport: puts the robot at rest at a map-frame pose (``setInitialPose``).
    """

    info: RobotInfo
    sim: Simulation
    base: MobileBase
    lidar: ScanSource
    teleport: Callable[[Pose2D], None]
    odometry: Callable[[], tuple[Pose2D, float, float]] | None = None
    """Wheel odometry: the pose of ``base_footprint`` in ``odom`` and the body twist (m/s,
    rad/s); None when the base has none (ground truth then stands in)."""
    body: str = ""
    """The MuJoCo body of ``base_link`` (where the IMU reads)."""
    joints: tuple[tuple[str, str], ...] = ()
    """(ROS joint name, MuJoCo joint name) of the joints ``/joint_states`` reports."""
    static_frames: tuple[StaticFrame, ...] = ()
    """The robot's fixed frames below ``base_footprint``."""
    scan_rate: float = 5.0
    """Scans per second (Hz)."""

    @property
    def footprint(self) -> Footprint:
        """The robot's real outline (m, ``base_link``)."""
        return self.info.mobile_facts.footprint


def navigator_robot(robot: str | Path | RobotInfo | None) -> RobotInfo:
    """The mobile robot ``robot`` names: a registry entry, a bundled name or alias, a robot
    file's path; None is the registry's default mobile robot.

    Raises:
        NavigatorSetupError: an unknown name, or a robot that does not drive.
        RobotFileError: a robot file that cannot be used (located).
    """
    if robot is None:
        return default_mobile_robot()
    try:
        info = robot if isinstance(robot, RobotInfo) else load_robot(robot)
    except UnknownRobotError:
        raise NavigatorSetupError(
            f"unknown robot {str(robot)!r}; a navigator drives one of: "
            f"{', '.join(MOBILE_ROBOTS)}, or a robot file"
        ) from None
    if not info.mobile:
        raise NavigatorSetupError(
            f"robot '{info.name}' does not drive; a navigator drives one of: "
            f"{', '.join(MOBILE_ROBOTS)}, or a robot file"
        )
    return info


def build_simulated_robot(
    info: RobotInfo, world: World, start: Pose2D, seed: int
) -> SimulatedRobot:
    """Build ``world`` with the mobile robot ``info`` at ``start`` in a new simulation seeded
    with ``seed``.

    Raises:
        NavigatorSetupError: ``start`` is not free for the robot's footprint.
    """
    check_free(world, start, info.mobile_facts.footprint, what="start pose")
    _, robot = info.build_sim(world, start, seed=seed)
    return simulated_robot(info, robot)


def simulated_robot(info: RobotInfo, robot: MobileRobot) -> SimulatedRobot:
    """The :class:`SimulatedRobot` view of a running mobile robot (say the one a mission built):
    its odometry, wheel joints and the fixed frames its facts place (``base_link`` above
    ``base_footprint``, ``base_scan`` at the lidar's mount, ``imu_link``)."""
    from baobab.robots.diff_drive.robot import scan_rate  # MuJoCo: a robot is running

    base, names, facts = robot.base, robot.names, robot.facts

    def odometry() -> tuple[Pose2D, float, float]:
        reading = base.odometry
        return reading.pose, reading.linear, reading.angular

    left, right = names.wheel_joints
    lidar, height = facts.lidar, facts.base_link_height
    return SimulatedRobot(
        info=info,
        sim=robot.sim,
        base=base,
        lidar=robot.lidar,
        teleport=base.teleport,
        odometry=odometry,
        body=names.body,
        joints=(("wheel_left_joint", left), ("wheel_right_joint", right)),
        static_frames=(
            StaticFrame("base_footprint", "base_link", (0.0, 0.0, height)),
            StaticFrame("base_link", "base_scan", (lidar.x, lidar.y, lidar.z - height)),
            StaticFrame("base_link", "imu_link", facts.imu),
        ),
        scan_rate=scan_rate(robot.sim, lidar.rate),
    )


def build_simulated_arm(robot: str, seed: int) -> SimulatedArm:
    """The arm ``robot`` in its own scene, holding its start pose, seeded with ``seed`` (built
    by the runtime its registry entry names).

    Raises:
        NavigatorSetupError: ``robot`` is not one of :data:`ARM_MODELS`.
    """
    if robot not in ARM_MODELS:
        raise NavigatorSetupError(
            f"unknown arm {robot!r}; the ROS runtime runs one of: {', '.join(ARM_MODELS)}"
        )
    runtime = ROBOTS[robot].arm_runtime()  # the arm's physics loads only now
    sim, server = runtime.build(seed)
    return runtime.simulated_arm(sim, server)


def pose_is_free(world: World, pose: Pose2D, footprint: Footprint) -> bool:
    """True when ``footprint`` at ``pose`` is clear of obstacles and on the floor."""
    return footprint.clearance_in(world, pose)[1] >= 0.0


def default_start(world: World, footprint: Footprint) -> Pose2D:
    """Where a robot starts when nothing says: the world's default spawn, or on a map without
    one the map frame's origin (where Nav2's AMCL starts its estimate, ``initial_pose`` 0, 0, 0).

    Raises:
        NavigatorSetupError: a map without a spawn whose origin is not free.
    """
    spawn = world.spawns.get("default")
    if spawn is not None:
        return spawn
    origin = Pose2D(x=0.0, y=0.0)
    name, clearance = footprint.clearance_in(world, origin)
    if clearance < 0.0:
        raise NavigatorSetupError(
            f"world '{world.name}' has no spawn and the map origin (0, 0) is not free for the "
            f"robot's footprint ('{name}' is in the way); give a start pose (start=Pose2D(...), "
            "--start X,Y,YAW, a mission's start:)"
        )
    return origin


def check_free(world: World, pose: Pose2D, footprint: Footprint, *, what: str) -> None:
    """Raise unless ``footprint`` at ``pose`` is free in ``world``.

    Raises:
        NavigatorSetupError: naming the obstacle (or the floor edge) in the way.
    """
    name, clearance = footprint.clearance_in(world, pose)
    if clearance >= 0.0:
        return
    if footprint.radius is not None:
        needs = f"'{name}' is {clearance + footprint.radius:.3f} m from it, the robot's "
        needs += f"footprint needs {footprint.radius:.3f} m"
    else:
        needs = f"the robot's footprint at yaw {pose.yaw:.2f} rad reaches {-clearance:.3f} m "
        needs += f"into '{name}'"
    raise NavigatorSetupError(
        f"{what} ({pose.x:.3f}, {pose.y:.3f}) is not free in world '{world.name}': {needs}"
    )
