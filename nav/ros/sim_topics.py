"""The simulation on ROS topics, with the names, types, QoS and rates a ROS simulation uses.

A mobile base (as a differential-drive robot's Gazebo simulation runs it; the fixed frames
are its facts', the scan rate its lidar's):

=================  ==========================  ======  =====================================
topic              type                        rate    what
=================  ==========================  ======  =====================================
``/cmd_vel``       geometry_msgs/Twist         in      ``linear.x`` (m/s), ``angular.z``
``/odom``          nav_msgs/Odometry           30 Hz   wheel odometry, ``odom`` ->
                                                       ``base_footprint``
``/tf``            tf2_msgs/TFMessage          30 Hz   ``map`` -> ``odom`` -> ``base_footprint``
``/tf_static``     tf2_msgs/TFMessage          latched ``base_footprint`` -> ``base_link`` ->
                                                       ``base_scan``, ``imu_link``
``/joint_states``  sensor_msgs/JointState      30 Hz   wheel angles (rad) and speeds
``/imu``           sensor_msgs/Imu             200 Hz  orientation, rates, specific force
``/scan``          sensor_msgs/LaserScan       lidar   best effort, as Gazebo's ray sensor
``/clock``         rosgraph_msgs/Clock         10 Hz   as ``gazebo_ros_init`` publishes it
=================  ==========================  ======  =====================================

``map`` -> ``odom`` is the correction that makes ``map`` -> ``base_footprint`` the true pose
(the simulation localises perfectly), as AMCL would publish it. A scan taken at a physics
step is published after that step (stamped with the time it was taken).

An arm (the seed's Cartesian impedance controller): ``/cartesian_impedance/desired_pose``
(geometry_msgs/PoseStamped, in: the set-point the reference filter moves towards),
``/cartesian_impedance/current_pose`` and ``/cartesian_impedance/filt_ref_pose`` (out,
100 Hz), ``/joint_states`` (100 Hz), ``/tf_static`` (``world`` -> the arm's base frame) and
``/clock``; poses are in the arm's base frame (its runtime names it).

Every message is built only while its topic has a subscriber (or an ``--echo``/record tap).
"""

from __future__ import annotations

import math
from typing import Any

import mujoco
import numpy as np

from baobab.nav.msgs import (
    Header,
    Point,
    Pose,
    PoseStamped,
    PoseWithCovariance,
    Quaternion,
    Twist,
    Vector3,
)
from baobab.nav.navigator_robot import SimulatedArm, SimulatedRobot, StaticFrame
from baobab.nav.ros.geometry_msgs.msg import (
    Transform,
    TransformStamped,
    TwistWithCovariance,
)
from baobab.nav.ros.nav_msgs.msg import Odometry
from baobab.nav.ros.qos import (
    DurabilityPolicy,
    QoSProfile,
    qos_profile_sensor_data,
)
from baobab.nav.ros.rosgraph_msgs.msg import Clock
from baobab.nav.ros.runtime import RosRuntime
from baobab.nav.ros.sensor_msgs.msg import Imu, JointState, LaserScan
from baobab.nav.ros.tf2_msgs.msg import TFMessage
from baobab.nav.rostime import S_TO_NS, TimeMsg
from baobab.sim.lidar import LaserScan as SimScan
from baobab.sim.world import Pose2D

ODOM_RATE = 30.0
JOINT_STATE_RATE = 30.0
IMU_RATE = 200.0
CLOCK_RATE = 10.0
ARM_RATE = 100.0
"""Rates (Hz) of the topics in the module docstring's tables."""

RELIABLE = QoSProfile(depth=10)
LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
TF_QOS = QoSProfile(depth=100)


def stamp(time_ns: int) -> TimeMsg:
    """A ``builtin_interfaces/Time`` for ``time_ns``."""
    sec, nanosec = divmod(time_ns, S_TO_NS)
    return TimeMsg(sec=sec, nanosec=nanosec)


def yaw_quaternion(yaw: float) -> Quaternion:
    """The rotation by ``yaw`` (rad) about +z."""
    return Quaternion(z=math.sin(yaw / 2), w=math.cos(yaw / 2))


def transform(
    time_ns: int,
    parent: str,
    child: str,
    xyz: tuple[float, float, float],
    rotation: Quaternion,
) -> TransformStamped:
    """``child`` at ``xyz`` in ``parent``, rotated by ``rotation``."""
    x, y, z = (float(value) for value in xyz)
    return TransformStamped(
        header=Header(stamp=stamp(time_ns), frame_id=parent),
        child_frame_id=child,
        transform=Transform(translation=Vector3(x=x, y=y, z=z), rotation=rotation),
    )


def _static_tf(frames: tuple[StaticFrame, ...], time_ns: int) -> TFMessage:
    transforms = []
    for frame in frames:
        x, y, z, w = (float(value) for value in frame.xyzw)
        quaternion = Quaternion(x=x, y=y, z=z, w=w)
        transforms.append(transform(time_ns, frame.parent, frame.child, frame.xyz, quaternion))
    return TFMessage(transforms=transforms)


def publish_clock(runtime: RosRuntime) -> None:
    """``/clock`` at :data:`CLOCK_RATE`."""
    runtime.add_source(
        "/clock",
        Clock,
        RELIABLE,
        CLOCK_RATE,
        lambda now: Clock(clock=stamp(now)),
    )


def _joint_states(sim: Any, joints: tuple[tuple[str, str], ...]) -> Any:
    handles = [(name, sim.data.joint(mujoco_name)) for name, mujoco_name in joints]

    def build(now: int) -> JointState:
        return JointState(
            header=Header(stamp=stamp(now)),
            name=[name for name, _ in handles],
            position=[float(handle.qpos[0]) for _, handle in handles],
            velocity=[float(handle.qvel[0]) for _, handle in handles],
            effort=[0.0] * len(handles),
        )

    return build


class MobileRobotTopics:
    """Puts a mobile base and its lidar on the topics of the module docstring."""

    def __init__(self, runtime: RosRuntime, robot: SimulatedRobot) -> None:
        self._runtime = runtime
        self._robot = robot
        self._latest_scan: SimScan | None = None
        robot.lidar.subscribe(self._keep_scan)
        runtime.subscribe("/cmd_vel", Twist, RELIABLE, self._on_cmd_vel)
        step_ns = round(robot.sim.physics_dt * S_TO_NS)
        runtime.add_source("/odom", Odometry, RELIABLE, ODOM_RATE, self._odometry)
        runtime.add_source("/tf", TFMessage, TF_QOS, ODOM_RATE, self._tf)
        runtime.add_source(
            "/joint_states",
            JointState,
            RELIABLE,
            JOINT_STATE_RATE,
            _joint_states(robot.sim, robot.joints),
        )
        self._imu = _ImuReader(robot.sim, robot.body)
        runtime.add_source("/imu", Imu, qos_profile_sensor_data, IMU_RATE, self._imu.read)
        runtime.add_source(
            "/scan",
            LaserScan,
            qos_profile_sensor_data,
            robot.scan_rate,
            self._scan,
            phase_ns=step_ns,
        )
        publish_clock(runtime)
        latch = runtime.advertise("/tf_static", TFMessage, LATCHED)
        runtime.publish(latch, _static_tf(robot.static_frames, runtime.now_ns()))

    def _on_cmd_vel(self, message: Twist) -> None:
        self._robot.base.command(message.linear.x, message.angular.z)

    def _keep_scan(self, scan: SimScan) -> None:
        self._latest_scan = scan

    def _odom_pose(self) -> tuple[Pose2D, float, float]:
        if self._robot.odometry is not None:
            return self._robot.odometry()
        linear, angular = self._robot.base.body_velocity()
        return self._robot.base.pose(), linear, angular

    def _odometry(self, now: int) -> Odometry:
        pose, linear, angular = self._odom_pose()
        return Odometry(
            header=Header(stamp=stamp(now), frame_id="odom"),
            child_frame_id="base_footprint",
            pose=PoseWithCovariance(
                pose=Pose(
                    position=Point(x=float(pose.x), y=float(pose.y)),
                    orientation=yaw_quaternion(pose.yaw),
                )
            ),
            twist=TwistWithCovariance(
                twist=Twist(linear=Vector3(x=float(linear)), angular=Vector3(z=float(angular)))
            ),
        )

    def _tf(self, now: int) -> TFMessage:
        odom, _, _ = self._odom_pose()
        truth = self._robot.base.pose()
        yaw = truth.yaw - odom.yaw
        cos, sin = math.cos(yaw), math.sin(yaw)
        origin = (truth.x - (cos * odom.x - sin * odom.y), truth.y - (sin * odom.x + cos * odom.y))
        return TFMessage(
            transforms=[
                transform(now, "map", "odom", (*origin, 0.0), yaw_quaternion(yaw)),
                transform(
                    now, "odom", "base_footprint", (odom.x, odom.y, 0.0), yaw_quaternion(odom.yaw)
                ),
            ]
        )

    def _scan(self, now: int) -> LaserScan | None:
        scan = self._latest_scan
        if scan is None:
            return None
        return LaserScan(
            header=Header(stamp=stamp(round(scan.stamp * S_TO_NS)), frame_id="base_scan"),
            angle_min=float(scan.angle_min),
            angle_max=float(scan.angle_max),
            angle_increment=float(scan.angle_increment),
            scan_time=1.0 / self._robot.scan_rate,
            range_min=float(scan.range_min),
            range_max=float(scan.range_max),
            ranges=np.asarray(scan.ranges, dtype=np.float32),
        )


class _ImuReader:
    """IMU readings of a body: orientation, body rates and specific force (m/s^2).

    The acceleration is the change of the body's velocity since the previous reading; at
    rest the IMU reads +9.81 m/s^2 along its up axis, as a real one does.
    """

    def __init__(self, sim: Any, body: str) -> None:
        self._sim = sim
        self._body = sim.data.body(body)
        self._body_id = sim.model.body(body).id
        self._velocity = np.zeros(6)
        self._previous: tuple[int, np.ndarray] | None = None

    def read(self, now: int) -> Imu:
        model, data = self._sim.model, self._sim.data
        w, x, y, z = self._body.xquat.tolist()
        rotation = self._body.xmat.reshape(3, 3)
        mujoco.mj_objectVelocity(
            model, data, mujoco.mjtObj.mjOBJ_BODY, self._body_id, self._velocity, 1
        )
        angular = self._velocity[:3].tolist()
        mujoco.mj_objectVelocity(
            model, data, mujoco.mjtObj.mjOBJ_BODY, self._body_id, self._velocity, 0
        )
        linear_world = self._velocity[3:].copy()
        acceleration = np.zeros(3)
        if self._previous is not None and now > self._previous[0]:
            acceleration = (linear_world - self._previous[1]) / (
                (now - self._previous[0]) / S_TO_NS
            )
        self._previous = (now, linear_world)
        force = rotation.T @ (acceleration - model.opt.gravity)
        return Imu(
            header=Header(stamp=stamp(now), frame_id="imu_link"),
            orientation=Quaternion(x=x, y=y, z=z, w=w),
            angular_velocity=Vector3(x=angular[0], y=angular[1], z=angular[2]),
            linear_acceleration=Vector3(x=float(force[0]), y=float(force[1]), z=float(force[2])),
        )


class ArmTopics:
    """Puts an arm's impedance controller on the seed's topics (module docstring)."""

    def __init__(self, runtime: RosRuntime, arm: SimulatedArm) -> None:
        self._arm = arm
        runtime.subscribe(
            "/cartesian_impedance/desired_pose", PoseStamped, RELIABLE, self._on_desired_pose
        )
        runtime.add_source(
            "/cartesian_impedance/current_pose",
            PoseStamped,
            RELIABLE,
            ARM_RATE,
            lambda now: self._pose_message(now, arm.tcp_pose()),
        )
        runtime.add_source(
            "/cartesian_impedance/filt_ref_pose",
            PoseStamped,
            RELIABLE,
            ARM_RATE,
            lambda now: self._pose_message(now, arm.reference_pose()),
        )
        runtime.add_source(
            "/joint_states", JointState, RELIABLE, ARM_RATE, _joint_states(arm.sim, arm.joints)
        )
        publish_clock(runtime)
        (x, y, z), rotation = arm.base_in_world
        latch = runtime.advertise("/tf_static", TFMessage, LATCHED)
        runtime.publish(
            latch,
            _static_tf((StaticFrame("world", arm.base_frame, (x, y, z), rotation),), 0),
        )

    def _pose_message(self, now: int, pose: tuple[Any, Any]) -> PoseStamped:
        (x, y, z), (qx, qy, qz, qw) = (np.asarray(part, dtype=float).tolist() for part in pose)
        return PoseStamped(
            header=Header(stamp=stamp(now), frame_id=self._arm.base_frame),
            pose=Pose(
                position=Point(x=x, y=y, z=z), orientation=Quaternion(x=qx, y=qy, z=qz, w=qw)
            ),
        )

    def _on_desired_pose(self, message: PoseStamped) -> None:
        position, orientation = message.pose.position, message.pose.orientation
        quaternion = (orientation.x, orientation.y, orientation.z, orientation.w)
        norm = math.sqrt(sum(value * value for value in quaternion))
        if not math.isfinite(norm) or norm < 1e-9:
            raise ValueError(
                "/cartesian_impedance/desired_pose: the orientation quaternion "
                f"{quaternion} cannot be normalised"
            )
        values = (position.x, position.y, position.z)
        if not all(math.isfinite(value) for value in values):
            raise ValueError(f"/cartesian_impedance/desired_pose: position {values} is not finite")
        self._arm.set_target(values, tuple(value / norm for value in quaternion))
