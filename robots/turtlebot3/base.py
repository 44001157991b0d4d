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
        self._rotation = np.empty(9)
        robot_body = model.body(self.names.body).id
        self._robot_geoms = np.flatnonzero(model.body_rootid[model.geom_bodyid] == robot_body)
        self._is_robot_geom = np.zeros(model.ngeom, dtype=bool)
        self._is_robot_geom[self._robot_geoms] = True
        self._is_floor_geom = model.geom_group == FLOOR_GROUP
        obstacle = (model.geom_group == STATIC_GROUP) | (model.geom_group == MOVABLE_GROUP)
        self._obstacle_geoms = np.flatnonzero(obstacle)
        self._footprint = model.geom(self.names.footprint_geom).id
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
        facts, dt = self.facts, self.period
        (v_target, w_target), (v, w) = self._target, self._commanded
        dv = facts.max_linear_accel * dt
        dw = facts.max_angular_accel * dt
        v = clamp(v_target, v - dv, v + dv)
        w = clamp(w_target, w - dw, w + dw)
        self._commanded = (v, w)
        for actuator, speed in zip(self._actuators, self.wheel_speeds(v, w), strict=True):
            actuator.ctrl[0] = speed
        self._integrate_odometry(time)

    # -- odometry -----------------------------------------------------------------------------

    def _encoder_angles(self) -> tuple[float, float]:
        tick = 2 * math.pi / self.facts.encoder_ticks_per_rev
        left, right = (float(wheel.qpos[0]) for wheel in self._wheels)
        return round(left / tick) * tick, round(right / tick) * tick

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

    def _rotation_matrix(self) -> np.ndarray:
        mujoco.mju_quat2Mat(self._rotation, self._root.qpos[3:7])
        return self._rotation.reshape(3, 3)

    def pose(self) -> Pose2D:
        """Ground-truth pose of ``base_link`` in the map frame (m, rad)."""
        rotation = self._rotation_matrix()
        position = self._root.qpos
        return Pose2D(
            x=float(position[0]),
            y=float(position[1]),
            yaw=math.atan2(rotation[1, 0], rotation[0, 0]),
        )

    def body_velocity(self) -> tuple[float, float]:
        """Ground-truth forward speed (m/s) and yaw rate (rad/s)."""
        rotation = self._rotation_matrix()
        velocity = self._root.qvel
        # Free joint: linear velocity in the world frame, angular velocity in the body frame.
        forward = float(rotation[:, 0] @ velocity[:3])
        yaw_rate = float(rotation[2] @ velocity[3:6])
        return forward, yaw_rate

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
        model, data = self._sim.model, self._sim.data
        candidates = self._obstacle_geoms
        if candidates.size == 0:
            return math.inf
        centre = data.geom_xpos[self._footprint, :2]
        gaps = np.linalg.norm(data.geom_xpos[candidates, :2] - centre, axis=1)
        reach = model.geom_rbound[candidates] + model.geom_rbound[self._footprint]
        nearest = math.inf
        for geom in candidates[gaps - reach < max_distance]:
            distance = mujoco.mj_geomDistance(
                model, data, self._footprint, int(geom), max_distance, None
            )
            nearest = min(nearest, distance)
        return nearest if nearest < max_distance else math.inf
