"""The differential-drive base: cmd_vel in, wheel velocity targets out, wheel odometry.

:class:`DiffDriveBase` ticks at 100 Hz (by default), compiled, inside MuJoCo's step
(:mod:`.base_kernel`). Each tick it moves the commanded body velocity toward the latest
``cmd_vel`` no faster than the acceleration limits allow, turns it into wheel angular
velocities for the velocity actuators, and integrates odometry from the wheel encoder angles.
Ground truth (``pose``, ``body_velocity``) is read from the physics, in one compiled call per
physics state (:mod:`.ground_truth_kernel`), and kept apart from the odometry, which drifts
like the real thing would.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from baobab.robots.diff_drive.base_kernel import LOOP_WORDS, WORD, base_loops
from baobab.robots.diff_drive.clearance_bounds import ClearanceBounds
from baobab.robots.diff_drive.facts import DiffDriveFacts
from baobab.robots.diff_drive.ground_truth_kernel import (
    GroundTruth,
    ground_truth,
)
from baobab.robots.diff_drive.names import OBSTACLE_GROUPS, DiffDriveNames
from baobab.sim.builder import FLOOR_GROUP, MAP_WALL_MATERIAL
from baobab.sim.errors import SimulationError
from baobab.sim.simulation import Simulation
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
    """A differential-drive base: a ``cmd_vel`` interface over the two wheel velocity actuators.

    Args:
        sim: the simulation holding the robot attached with ``prefix``.
        prefix: name prefix of the robot's MuJoCo elements.
        facts: the robot's figures (speed and acceleration limits, wheel geometry).
        period: control period (s); a multiple of the physics step.
    """

    def __init__(
        self,
        sim: Simulation,
        *,
        prefix: str,
        facts: DiffDriveFacts,
        period: float = BASE_CONTROL_PERIOD,
    ) -> None:
        self._sim = sim
        self.facts = facts
        self.names = DiffDriveNames(prefix)
        self.period = period
        model, data = sim.model, sim.data
        self._root = data.joint(self.names.root_joint)
        self._root_z = float(model.joint(self.names.root_joint).qpos0[2])
        self._wheels = [data.joint(name) for name in self.names.wheel_joints]
        self._actuators = [data.actuator(name) for name in self.names.wheel_actuators]
        self._wheel_angles = tuple(wheel.qpos for wheel in self._wheels)
        # The free joint's place in MjData (valid while the MjData lives), for ground_truth.
        self._root_addresses = (self._root.qpos.ctypes.data, self._root.qvel.ctypes.data)
        self._truth_revision = -1
        self._truth: GroundTruth = (0.0, 0.0, 0.0, 0.0, 0.0)
        self._pose_revision = -1
        self._pose = Pose2D(x=0.0, y=0.0)
        robot_body = model.body(self.names.body).id
        self._robot_geoms = np.flatnonzero(model.body_rootid[model.geom_bodyid] == robot_body)
        self._is_robot_geom = np.zeros(model.ngeom, dtype=bool)
        self._is_robot_geom[self._robot_geoms] = True
        self._is_floor_geom = model.geom_group == FLOOR_GROUP
        self._footprint = model.geom(self.names.footprint_geom).id
        obstacles = np.flatnonzero(np.isin(model.geom_group, OBSTACLE_GROUPS))
        self._clearance_bounds = ClearanceBounds(model, data, self._footprint, obstacles)
        self._loop = self._start_loop(sim, model)
        self._reset_odometry()

    def _start_loop(self, sim: Simulation, model: mujoco.MjModel) -> np.void:
        """Fill this robot's compiled loop record (:mod:`.base_kernel`) and attach it."""
        group = base_loops(sim)
        loop = group.add(sim)
        facts, names = self.facts, self.names
        self._words, self._loop_index = group.words, group.size - 1
        first = self._loop_index * LOOP_WORDS
        self._target_word = first + WORD["target_linear"]  # then target_angular
        self._commanded_word = first + WORD["commanded_linear"]  # then commanded_angular
        self._odometry_word = first + WORD["odom_x"]  # x, y, yaw, linear, angular, stamp
        data = sim.data
        loop["qpos_address"] = data.qpos.ctypes.data
        loop["ctrl_address"] = data.ctrl.ctypes.data
        loop["sensordata_address"] = data.sensordata.ctypes.data
        loop["nq"], loop["nu"], loop["nsensordata"] = model.nq, model.nu, model.nsensordata
        loop["root_qpos"] = model.jnt_qposadr[model.joint(names.root_joint).id]
        left, right = (model.jnt_qposadr[model.joint(name).id] for name in names.wheel_joints)
        loop["left_qpos"], loop["right_qpos"] = left, right
        left, right = (model.actuator(name).id for name in names.wheel_actuators)
        loop["left_actuator"], loop["right_actuator"] = left, right
        loop["physics_dt"] = sim.physics_dt
        loop["period_steps"] = sim.steps_for(self.period, what="base control period")
        loop["next_step"] = sim.step_count
        loop["linear_step"] = facts.max_linear_accel * self.period
        loop["angular_step"] = facts.max_angular_accel * self.period
        loop["half_separation"] = facts.wheel_separation / 2
        loop["wheel_separation"] = facts.wheel_separation
        loop["wheel_radius"] = facts.wheel_radius
        loop["max_wheel_speed"] = facts.max_wheel_speed
        loop["encoder_tick"] = 2 * math.pi / facts.encoder_ticks_per_rev
        return loop

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
        self._set_target(
            clamp(linear, -facts.max_linear_speed, facts.max_linear_speed),
            clamp(angular, -facts.max_angular_speed, facts.max_angular_speed),
        )

    def stop(self) -> None:
        """Command zero velocity (the base decelerates within its limits)."""
        self._set_target(0.0, 0.0)

    def _set_target(self, linear: float, angular: float) -> None:
        words, at = self._words, self._target_word
        words[at] = linear
        words[at + 1] = angular

    @property
    def target(self) -> tuple[float, float]:
        """The latest ``cmd_vel`` after clipping: (m/s, rad/s)."""
        linear, angular = self._words[self._target_word : self._target_word + 2].tolist()
        return (linear, angular)

    @property
    def commanded(self) -> tuple[float, float]:
        """The acceleration-limited velocity sent to the wheels this tick: (m/s, rad/s)."""
        linear, angular = self._words[self._commanded_word : self._commanded_word + 2].tolist()
        return (linear, angular)

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

    # -- odometry -----------------------------------------------------------------------------

    def _reset_odometry(self) -> None:
        loop, tick = self._loop, 2 * math.pi / self.facts.encoder_ticks_per_rev
        for side, angle in zip(("left", "right"), self._wheel_angles, strict=True):
            loop[f"encoder_{side}"] = round(float(angle[0]) / tick) * tick
        for field in ("odom_x", "odom_y", "odom_yaw", "odom_linear", "odom_angular"):
            loop[field] = 0.0
        loop["odom_stamp"] = self._sim.time
        self._odom_origin = self.pose()

    @property
    def odometry(self) -> Odometry:
        """The latest wheel odometry (odom frame), integrated from the encoder angles."""
        at = self._odometry_word
        x, y, yaw, linear, angular, stamp = self._words[at : at + 6].tolist()
        return Odometry(stamp=stamp, pose=Pose2D(x=x, y=y, yaw=yaw), linear=linear, angular=angular)

    @property
    def odom_origin(self) -> Pose2D:
        """Where the ``odom`` frame lies in the map frame (m, rad)."""
        return self._odom_origin

    # -- ground truth -------------------------------------------------------------------------

    def _ground_truth(self, revision: int) -> GroundTruth:
        """x, y (m), yaw (rad), forward speed (m/s), yaw rate (rad/s) of the chassis, read
        from the physics once per state ``revision``."""
        if revision != self._truth_revision:
            self._truth = ground_truth(*self._root_addresses)
            self._truth_revision = revision
        return self._truth

    def ground_truth(self) -> GroundTruth:
        """Ground-truth ``(x, y, yaw, forward speed, yaw rate)`` of ``base_link`` in the map
        frame (m, m, rad, m/s, rad/s): :meth:`pose` and :meth:`body_velocity` in one tuple."""
        return self._ground_truth(self._sim.state_revision)

    def pose(self) -> Pose2D:
        """Ground-truth pose of ``base_link`` in the map frame (m, rad)."""
        revision = self._sim.state_revision
        if revision != self._pose_revision:  # several readers per control tick share one
            x, y, yaw, _, _ = self._ground_truth(revision)
            self._pose = Pose2D(x=x, y=y, yaw=yaw)
            self._pose_revision = revision
        return self._pose

    def body_velocity(self) -> tuple[float, float]:
        """Ground-truth forward speed (m/s) and yaw rate (rad/s)."""
        _, _, _, linear, angular = self._ground_truth(self._sim.state_revision)
        return linear, angular

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
        self._set_target(0.0, 0.0)
        self._loop["commanded_linear"] = self._loop["commanded_angular"] = 0.0
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

    def min_clearance(self, max_distance: float = 2.0, *, below: float = math.inf) -> float:
        """Distance (m) from the footprint to the nearest obstacle geom.

        Obstacles are the static and movable geoms; the footprint is the upright cylinder of
        the footprint's radius around ``base_link``, or the prism of its polygon. Negative when
        an obstacle reaches inside the footprint; ``inf`` when nothing is within
        ``max_distance``, or nothing nearer than ``below`` (m; obstacles that cannot be are
        not measured).
        """
        return self._clearance_bounds.min_clearance(max_distance, below=below)

    # -- the metrics probe --------------------------------------------------------------------

    def start_probe(
        self, *, pose_period: float, contact_period: float, drain_period: float
    ) -> BaseProbe:
        """Sample, compiled inside the physics step, the ground-truth position every
        ``pose_period`` and the robot's obstacle contacts every ``contact_period`` (s).

        Positions collect in a buffer that holds ``drain_period`` (s) of samples: call
        :meth:`BaseProbe.drain` at least that often. Sampling starts now.

        Raises:
            SimulationError: if a period is not a positive multiple of the physics step, or
                the model lacks the robot's contact sensors (:func:`.model.attach_robot`).
        """
        sim, model, loop = self._sim, self._sim.model, self._loop
        first, obstacles, on_world_body, map_sensor = self._contact_sensors(model)
        touched = np.zeros(len(obstacles) + (map_sensor >= 0))
        pose_steps = sim.steps_for(pose_period, what="pose sampling period")
        contact_steps = sim.steps_for(contact_period, what="contact sampling period")
        if pose_steps <= 0 or contact_steps <= 0:
            raise SimulationError("sampling periods must be positive")
        capacity = 2 * (sim.steps_for(drain_period, what="drain period") // pose_steps + 2)
        poses = np.zeros((capacity, 3))
        loop["contact_sensor"], loop["contact_sensors"] = first, len(obstacles)
        loop["contact_world_sensors"], loop["contact_map_sensor"] = on_world_body, map_sensor
        loop["contact_address"] = touched.ctypes.data
        loop["contact_samples"] = 0
        loop["pose_capacity"], loop["pose_address"] = capacity, poses.ctypes.data
        loop["pose_count"] = loop["pose_overflow"] = 0
        loop["pose_next_step"] = loop["contact_next_step"] = sim.step_count
        loop["pose_period_steps"], loop["contact_period_steps"] = pose_steps, contact_steps
        names = obstacles + [MAP_WALL_MATERIAL] if map_sensor >= 0 else obstacles
        self._probe = BaseProbe(loop, names, touched, poses)
        return self._probe

    def _contact_sensors(self, model: mujoco.MjModel) -> tuple[int, list[str], int, int]:
        """The sensordata address of the first contact sensor, the obstacle geoms with a
        sensor each (in model order: the world body's first), how many of them are the world
        body's, and the address of the map's two sensors (-1 without a map); see
        :func:`.model.attach_robot`.

        Raises:
            SimulationError: a sensor is missing or the sensors are not consecutive.
        """
        walls = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_MATERIAL, MAP_WALL_MATERIAL)
        wanted = np.isin(model.geom_group, OBSTACLE_GROUPS)
        if walls >= 0:
            wanted &= model.geom_matid != walls
        geoms = np.flatnonzero(wanted)
        obstacles = [model.geom(int(index)).name for index in geoms]
        sensors = [self.names.touch_sensor(name) for name in obstacles]
        if walls >= 0:
            sensors += list(self.names.map_contact_sensors)
        try:
            addresses = [int(model.sensor(name).adr[0]) for name in sensors]
        except KeyError as exc:
            raise SimulationError(f"the model has no contact sensor {exc}") from None
        first = addresses[0] if addresses else 0
        if addresses != list(range(first, first + len(addresses))):
            raise SimulationError("the robot's contact sensors are not consecutive")
        on_world_body = int((model.geom_bodyid[geoms] == 0).sum())
        if not (model.geom_bodyid[geoms[:on_world_body]] == 0).all():
            raise SimulationError("the world body's obstacles do not come first")
        map_sensor = addresses[-2] if walls >= 0 else -1
        return first, obstacles, on_world_body, map_sensor


class BaseProbe:
    """What a base's compiled loop samples for the metrics (:meth:`DiffDriveBase.start_probe`)."""

    def __init__(
        self, loop: np.void, obstacles: list[str], touched: np.ndarray, poses: np.ndarray
    ) -> None:
        self._loop = loop
        self._obstacles = obstacles
        self._touched = touched  # 1 for each obstacle touched so far
        self._poses = poses

    @property
    def contact_samples(self) -> int:
        """Samples in which the robot touched an obstacle."""
        return int(self._loop["contact_samples"])

    def touched(self) -> list[str]:
        """Names of the obstacle geoms the robot touched so far, in model order."""
        return [name for name, hit in zip(self._obstacles, self._touched, strict=True) if hit]

    def drain(self) -> list[tuple[float, float, float]]:
        """The position samples taken since the last drain: (t s, x m, y m), oldest first.

        Raises:
            SimulationError: if samples were lost because the buffer was not drained in time.
        """
        return list(zip(*self.drain_columns(), strict=True))

    def drain_columns(self) -> tuple[list[float], list[float], list[float]]:
        """:meth:`drain` as three columns: sim times (s), x (m), y (m)."""
        loop = self._loop
        if loop["pose_overflow"]:
            raise SimulationError("the base's position samples overflowed: drain them in time")
        count = int(loop["pose_count"])
        times, xs, ys = self._poses[:count].T.tolist()
        loop["pose_count"] = 0
        return times, xs, ys
