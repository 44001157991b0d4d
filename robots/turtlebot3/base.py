"""The differential-drive base: cmd_vel in, wheel velocity targets out, wheel odometry.

:class:`DiffDriveBase` runs as a periodic sim callback (100 Hz by default). Each tick it moves
the commanded body velocity toward the latest ``cmd_vel`` no faster than the acceleration
limits allow, turns it into wheel angular velocities for the velocity actuators, and integrates
odometry from the wheel encoder angles. Ground truth (``pose``, ``body_velocity``) is read from
the physics and kept apart from the odometry, which drifts like the real thing would.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from baobab.robots.turtlebot3.clearance_bounds import ClearanceBounds
from baobab.robots.turtlebot3.model import BURGER, DEFAULT_PREFIX, BurgerFacts, TurtleBot3Names
from baobab.sim.builder import FLOOR_GROUP, MOVABLE_GROUP, STATIC_GROUP
from baobab.sim.simulation import PeriodicHandle, Simulation
from baobab.sim.world import Pose2D

BASE_CONTROL_PERIOD = 0.01
"""Period of the base controller (s): 100 Hz."""


@dataclass(frozen=True)
class Odometry:
    """Wheel odometry: the pose of ``base_link`` in the ``odom`` frame and its body twist.

    The ``odom`` frame is where the robot stood when odometry was last reset (start or
    teleport). ``linear`` (m/s) and ``angular`` (rad/s) are averaged over the last tick.
    """

    stamp: float
    pose: Pose2D
    linear: float
    angular: float


def clamp(value: float, low: float, high: float) -> float:
    """``value`` limited to ``[low, high]``."""
    return min(max(value, low), high)


class DiffDriveBase:
    """The TurtleBot3 base: a ``cmd_vel`` interface over the two wheel velocity actuators.

    Args:
        sim: the simulation holding a Burger attached with ``prefix``.
        prefix: name prefix of the robot's MuJoCo elements.
        facts: the robot's figures (speed and acceleration limits, wheel geometry).
        period: control period (s); a multiple of the physics step.
    """

    def __init__(
        self,
        sim: Simulation,
        *,
        prefix: str = DEFAULT_PREFIX,
        facts: BurgerFacts = BURGER,
        period: float = BASE_CONTROL_PERIOD,
    ) -> None:
        self._sim = sim
        self.facts = facts
        self.names = TurtleBot3Names(prefix)
        self.period = period
        model, data = sim.model, sim.data
        self._root = data.joint(self.names.root_joint)
        self._root_z = float(model.joint(self.names.root_joint).qpos0[2])
        self._wheels = [data.joint(name) for name in self.names.wheel_joints]
        self._actuators = [data.actuator(name) for name in self.names.wheel_actuators]
        self._left_ctrl, self._right_ctrl = (actuator.ctrl for actuator in self._actuators)
        self._left_angle, self._right_angle = (wheel.qpos for wheel in self._wheels)
        self._linear_step = facts.max_linear_accel * period  # m/s per tick
        self._angular_step = facts.max_angular_accel * period  # rad/s per tick
        self._encoder_tick = 2 * math.pi / facts.encoder_ticks_per_rev  # rad
        self._rotation_buffer = np.empty(9)
        self._root_quaternion = self._root.qpos[3:7]  # a view: w, x, y, z
        self._pose_revision = -1
        self._velocity_revision = -1
        self._velocity = (0.0, 0.0)
        self._pose = Pose2D(x=0.0, y=0.0)
        robot_body = model.body(self.names.body).id
        self._robot_geoms = np.flatnonzero(model.body_rootid[model.geom_bodyid] == robot_body)
        self._is_robot_geom = np.zeros(model.ngeom, dtype=bool)
        self._is_robot_geom[self._robot_geoms] = True
        self._is_floor_geom = model.geom_group == FLOOR_GROUP
        obstacle = (model.geom_group == STATIC_GROUP) | (model.geom_group == MOVABLE_GROUP)
        self._obstacle_geoms = np.flatnonzero(obstacle)
        self._footprint = model.geom(self.names.footprint_geom).id
        self._clearance_bounds = ClearanceBounds(
            model,
            data,
            self._footprint,
            np.flatnonzero(model.geom_group == STATIC_GROUP),
            np.flatnonzero(model.geom_group == MOVABLE_GROUP),
        )
        self._target = (0.0, 0.0)
        self._commanded = (0.0, 0.0)
        self._reset_odometry()
        self.handle: PeriodicHandle = sim.every(period, self._on_tick, name=f"{prefix}base")

    # -- cmd_vel ------------------------------------------------------------------------------

    def command(self, linear: float, angular: float) -> None:
        """Set ``cmd_vel``: forward speed ``linear`` (m/s) and yaw rate ``angular`` (rad/s).

        Values beyond the speed limits are clipped; the base then ramps toward them within
        the acceleration limits and holds them until the next command.

        Raises:
            ValueError: if either value is not finite.
        """
        if not (math.isfinite(linear) and math.isfinite(angular)):
            raise ValueError(f"cmd_vel must be finite, got ({linear}, {angular})")
        facts = self.facts
        self._target = (
            clamp(linear, -facts.max_linear_speed, facts.max_linear_speed),
            clamp(angular, -facts.max_angular_speed, facts.max_angular_speed),
        )

    def stop(self) -> None:
        """Command zero velocity (the base decelerates within its limits)."""
        self._target = (0.0, 0.0)

    @property
    def target(self) -> tuple[float, float]:
        """The latest ``cmd_vel`` after clipping: (m/s, rad/s)."""
        return self._target

    @property
    def commanded(self) -> tuple[float, float]:
        """The acceleration-limited velocity sent to the wheels this tick: (m/s, rad/s)."""
        return self._commanded

    def wheel_speeds(self, linear: float, angular: float) -> tuple[float, float]:
        """Left and right wheel angular velocities (rad/s) for a body twist (m/s, rad/s).

        If a wheel would exceed its rim speed limit, both are scaled down together so the
        path keeps its curvature.
        """
        facts = self.facts
        half = facts.wheel_separation / 2
        left, right = linear - angular * half, linear + angular * half
        excess = max(abs(left), abs(right)) / facts.max_wheel_speed
        if excess > 1.0:
            left, right = left / excess, right / excess
        return left / facts.wheel_radius, right / facts.wheel_radius

    def _on_tick(self, time: float) -> None:
        v_target, w_target = self._target
        v, w = self._commanded
        v = min(max(v_target, v - self._linear_step), v + self._linear_step)
        w = min(max(w_target, w - self._angular_step), w + self._angular_step)
        self._commanded = (v, w)
        left, right = self.wheel_speeds(v, w)
        self._left_ctrl[0] = left
        self._right_ctrl[0] = right
        self._integrate_odometry(time)

    # -- odometry -----------------------------------------------------------------------------

    def _encoder_angles(self) -> tuple[float, float]:
        tick = self._encoder_tick
        return (
            round(float(self._left_angle[0]) / tick) * tick,
            round(float(self._right_angle[0]) / tick) * tick,
        )

    def _reset_odometry(self) -> None:
        self._encoders = self._encoder_angles()
        self._odom_xy_yaw = (0.0, 0.0, 0.0)
        self._odom_twist = (0.0, 0.0)
        self._odom_stamp = self._sim.time
        self._odom_origin = self.pose()

    def _integrate_odometry(self, time: float) -> None:
        facts = self.facts
        left, right = self._encoder_angles()
        d_left = (left - self._encoders[0]) * facts.wheel_radius
        d_right = (right - self._encoders[1]) * facts.wheel_radius
        self._encoders = (left, right)
        distance = (d_left + d_right) / 2
        turn = (d_right - d_left) / facts.wheel_separation
        x, y, yaw = self._odom_xy_yaw
        heading = yaw + turn / 2  # second-order (midpoint) integration over the tick
        self._odom_xy_yaw = (
            x + distance * math.cos(heading),
            y + distance * math.sin(heading),
            math.remainder(yaw + turn, 2 * math.pi),
        )
        elapsed = time - self._odom_stamp
        if elapsed > 0:
            self._odom_twist = (distance / elapsed, turn / elapsed)
        self._odom_stamp = time

    @property
    def odometry(self) -> Odometry:
        """The latest wheel odometry (odom frame), integrated from the encoder angles."""
        x, y, yaw = self._odom_xy_yaw
        return Odometry(
            stamp=self._odom_stamp,
            pose=Pose2D(x=x, y=y, yaw=yaw),
            linear=self._odom_twist[0],
            angular=self._odom_twist[1],
        )

    @property
    def odom_origin(self) -> Pose2D:
        """Where the ``odom`` frame lies in the map frame (m, rad)."""
        return self._odom_origin

    # -- ground truth -------------------------------------------------------------------------

    def _rotation(self) -> list[float]:
        """The chassis rotation matrix, row-major, as nine floats."""
        mujoco.mju_quat2Mat(self._rotation_buffer, self._root_quaternion)
        rotation: list[float] = self._rotation_buffer.tolist()
        return rotation

    def pose(self) -> Pose2D:
        """Ground-truth pose of ``base_link`` in the map frame (m, rad)."""
        revision = self._sim.state_revision
        if revision != self._pose_revision:  # several readers per control tick share one
            r = self._rotation()
            position = self._root.qpos
            self._pose = Pose2D(
                x=float(position[0]), y=float(position[1]), yaw=math.atan2(r[3], r[0])
            )
            self._pose_revision = revision
        return self._pose

    def body_velocity(self) -> tuple[float, float]:
        """Ground-truth forward speed (m/s) and yaw rate (rad/s)."""
        revision = self._sim.state_revision
        if revision != self._velocity_revision:
            r = self._rotation()
            vx, vy, vz, wx, wy, wz = self._root.qvel.tolist()
            # Free joint: linear velocity in the world frame, angular velocity in the body
            # frame.
            self._velocity = (r[0] * vx + r[3] * vy + r[6] * vz, r[6] * wx + r[7] * wy + r[8] * wz)
            self._velocity_revision = revision
        return self._velocity

    def teleport(self, pose: Pose2D) -> None:
        """Put the robot at ``pose`` (map frame) at rest, and restart odometry there."""
        quaternion = np.empty(4)
        mujoco.mju_axisAngle2Quat(quaternion, np.array([0.0, 0.0, 1.0]), pose.yaw)
        self._root.qpos[:] = [pose.x, pose.y, self._root_z, *quaternion]
        self._root.qvel[:] = 0.0
        for wheel in self._wheels:
            wheel.qvel[:] = 0.0
        for actuator in self._actuators:
            actuator.ctrl[0] = 0.0
        self._target = (0.0, 0.0)
        self._commanded = (0.0, 0.0)
        self._sim.forward()
        self._reset_odometry()

    # -- contacts and clearance ---------------------------------------------------------------

    def robot_contacts(self) -> list[str]:
        """Names of the non-floor geoms touching any robot geom now (sorted, no repeats)."""
        data, model = self._sim.data, self._sim.model
        if data.ncon == 0:
            return []
        pairs = data.contact.geom[: data.ncon]
        first, second = pairs[:, 0], pairs[:, 1]
        is_robot = self._is_robot_geom
        other = np.concatenate((second[is_robot[first]], first[is_robot[second]]))
        other = other[~self._is_floor_geom[other] & ~is_robot[other]]
        return sorted({model.geom(int(geom)).name for geom in other})

    def min_clearance(self, max_distance: float = 2.0) -> float:
        """Distance (m) from the footprint circle to the nearest obstacle geom.

        Obstacles are the static and movable geoms; the footprint is the upright cylinder of
        radius ``facts.footprint_radius`` around ``base_link``. Negative when an obstacle
        reaches inside the footprint; ``inf`` when nothing is within ``max_distance``.
        """
        return self._clearance_bounds.min_clearance(max_distance)
