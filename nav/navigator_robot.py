"""The simulated robot a :class:`~baobab.nav.navigator.BasicNavigator` drives.

The navigation server takes any :class:`~baobab.nav.interfaces.MobileBase` and
:class:`~baobab.nav.interfaces.ScanSource`. The Nav2 facade is different, because a Nav2 script
constructs ``BasicNavigator()`` and expects a robot to be there: :func:`build_simulated_robot`
builds one from ``baobab.robots`` (the layer below ``nav``; robots never import nav). The ROS
runtime's robots (:mod:`baobab.nav.ros.sim_topics`) come from here too: the same Burger with
what its topics need (odometry, joints, fixed frames), and :func:`build_simulated_arm` for the
Panda.

Checking a pose (:func:`check_free`, :func:`pose_is_free`) loads no physics: ``baobab nav2``
and ``baobab teleop`` refuse a blocked start before MuJoCo and the robot's compiled loop load,
so the robot package is imported when a robot is built.

The ROS runtime's robots (:mod:`baobab.nav.ros.sim_topics`) come from here too: the same
Burger with what its topics need (odometry, joints, fixed frames), and the Panda
(:func:`build_simulated_arm`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from baobab.sim.errors import BaobabError
from baobab.sim.geometry import nearest_obstacle
from baobab.sim.world import Pose2D, World

if TYPE_CHECKING:  # checking a pose (baobab nav2, baobab teleop) loads no physics
    from baobab.nav.interfaces import MobileBase, ScanSource
    from baobab.sim.simulation import Simulation

ROBOT_MODELS = ("turtlebot3",)
"""The robot names a navigator accepts."""

ARM_MODELS = ("panda",)
"""The arm names the ROS runtime accepts besides :data:`ROBOT_MODELS`."""

BURGER_IMU_OFFSET = (-0.032, 0.0, 0.068)
"""``imu_link`` in ``base_link`` (m), as the Burger's URDF places it (``imu_joint``)."""
BASE_LINK_HEIGHT = 0.010
"""``base_link`` above ``base_footprint`` (m), as the Burger's URDF places it."""


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
        sim: the simulation (world + robot), its callbacks registered.
        base: the drive, ground-truth pose in the map frame (the sim localises perfectly).
        lidar: the 2D scanner feeding the costmaps.
        footprint_radius: radius (m) of the base's circular footprint.
        teleport: puts the robot at rest at a map-frame pose (``setInitialPose``).
    """

    sim: Simulation
    base: MobileBase
    lidar: ScanSource
    footprint_radius: float
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


def build_simulated_robot(robot: str, world: World, start: Pose2D, seed: int) -> SimulatedRobot:
    """Build ``world`` with ``robot`` at ``start`` in a new simulation seeded with ``seed``.

    Raises:
        NavigatorSetupError: ``robot`` is not one of :data:`ROBOT_MODELS`, or ``start`` is not
            free for its footprint.
    """
    if robot != "turtlebot3":
        raise NavigatorSetupError(
            f"unknown robot {robot!r}; a navigator drives one of: {', '.join(ROBOT_MODELS)}"
        )
    from baobab.robots.turtlebot3 import BURGER, build_turtlebot3_sim  # MuJoCo: only to build

    check_free(world, start, BURGER.footprint_radius, what="start pose")
    _, turtlebot = build_turtlebot3_sim(world, start, seed=seed)
    return simulated_turtlebot3(turtlebot)


def simulated_turtlebot3(turtlebot: Any) -> SimulatedRobot:
    """The :class:`SimulatedRobot` view of a running Burger (a ``robots.turtlebot3.TurtleBot3``,
    say the one a mission built)."""
    from baobab.robots.turtlebot3 import BURGER

    base, names = turtlebot.base, turtlebot.names

    def odometry() -> tuple[Pose2D, float, float]:
        reading = base.odometry
        return reading.pose, reading.linear, reading.angular

    left, right = names.wheel_joints
    return SimulatedRobot(
        sim=turtlebot.sim,
        base=base,
        lidar=turtlebot.lidar,
        footprint_radius=BURGER.footprint_radius,
        teleport=base.teleport,
        odometry=odometry,
        body=names.body,
        joints=(("wheel_left_joint", left), ("wheel_right_joint", right)),
        static_frames=(
            StaticFrame("base_footprint", "base_link", (0.0, 0.0, BASE_LINK_HEIGHT)),
            StaticFrame(
                "base_link",
                "base_scan",
                (BURGER.lidar_offset_x, 0.0, BURGER.lidar_height - BASE_LINK_HEIGHT),
            ),
            StaticFrame("base_link", "imu_link", BURGER_IMU_OFFSET),
        ),
        scan_rate=BURGER.lidar_rate,
    )


@dataclass
class SimulatedArm:
    """An arm under Cartesian impedance control in its own simulation (the ROS runtime's Panda).

    Poses are in the arm's base frame ``base_frame``: position (m) and quaternion x, y, z, w.

    Attributes:
        sim: the simulation (table scene + arm), its control loop running.
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


def build_simulated_arm(robot: str, seed: int) -> SimulatedArm:
    """The Panda on its table (``panda_table``), holding its start pose, seeded with ``seed``.

    Raises:
        NavigatorSetupError: ``robot`` is not one of :data:`ARM_MODELS`.
    """
    if robot not in ARM_MODELS:
        raise NavigatorSetupError(
            f"unknown arm {robot!r}; the ROS runtime runs one of: {', '.join(ARM_MODELS)}"
        )
    # Like build_simulated_robot, the arm's import happens here, when one is asked for.
    from baobab.robots.panda import build_panda_sim

    sim, server = build_panda_sim(seed=seed)
    return simulated_panda(sim, server)


def simulated_panda(sim: Simulation, server: Any) -> SimulatedArm:
    """The :class:`SimulatedArm` view of a running Panda (a ``robots.panda.ArmServer``)."""
    import numpy as np

    from baobab.robots.panda.model import ARM_JOINTS, FINGER_JOINTS
    from baobab.robots.panda.quaternion import matrix_to_quaternion

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


def footprint_radius(robot: str) -> float:
    """The footprint radius (m) of a navigator's robot (0 for a name it does not drive)."""
    from baobab.robots.catalog import ROBOTS  # facts only: no physics

    info = ROBOTS.get(robot)
    return info.footprint_radius if info is not None and robot in ROBOT_MODELS else 0.0


def default_start(world: World, radius: float) -> Pose2D:
    """Where a robot starts when nothing says: the world's default spawn, or on a map without
    one the map frame's origin (where Nav2's AMCL starts its estimate, ``initial_pose`` 0, 0, 0).

    Raises:
        NavigatorSetupError: a map without a spawn whose origin is not free.
    """
    spawn = world.spawns.get("default")
    if spawn is not None:
        return spawn
    origin = Pose2D(x=0.0, y=0.0)
    name, distance = nearest_obstacle(world, 0.0, 0.0)
    if distance < radius:
        raise NavigatorSetupError(
            f"world '{world.name}' has no spawn and the map origin (0, 0) is not free ('{name}' "
            f"is {distance:.3f} m from it); give a start pose (start=Pose2D(...), --start X,Y,YAW"
            ", a mission's start:)"
        )
    return origin


def pose_is_free(world: World, pose: Pose2D, radius: float) -> bool:
    """True when a footprint of ``radius`` (m) at ``pose`` is clear of obstacles, on the floor."""
    return nearest_obstacle(world, pose.x, pose.y)[1] >= radius


def check_free(world: World, pose: Pose2D, radius: float, *, what: str) -> None:
    """Raise unless a footprint of ``radius`` (m) at ``pose`` is free in ``world``.

    Raises:
        NavigatorSetupError: naming the obstacle (or the floor edge) in the way.
    """
    name, distance = nearest_obstacle(world, pose.x, pose.y)
    if distance < radius:
        raise NavigatorSetupError(
            f"{what} ({pose.x:.3f}, {pose.y:.3f}) is not free in world '{world.name}': "
            f"'{name}' is {distance:.3f} m from it, the robot's footprint needs {radius:.3f} m"
        )
