"""The Panda's capability server: goal-style ``move_to`` and ``gripper`` tasks over the sim.

At the control rate (1 kHz when the physics step is 1 ms) a compiled step
(:func:`~baobab.robots.panda.arm_kernel.arm_loop_step`) reads the joint state, advances the
active motion (a :class:`LinearTrajectory` sampled at the control period when the goal
arrives), runs the Cartesian impedance law, writes the seven joint torques, moves the gripper
set-point and checks the running tasks. It runs inside MuJoCo's own step
(:mod:`~baobab.robots.panda.native_loop`), so the simulation steps the controlled arm in
batches without waking Python; the server finishes the tasks the step saw end whenever a task
handle is read (and every :data:`TASK_PERIOD` of sim time). Poses at this interface are in
the world frame with quaternions x, y, z, w; the controller works in the base (link0) frame.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass
from typing import Literal

import mujoco
import numpy as np
from scipy.spatial.transform import Rotation

from baobab.robots.panda import native_loop
from baobab.robots.panda.arm_kernel import ARM_LOOP, GripperEnd, MotionEnd
from baobab.robots.panda.errors import ArmErrorCode, GripperCommandError, TrajectoryGoalError
from baobab.robots.panda.gripper import MIN_GRASP_WIDTH, OPENING_SPEED, STALL_SPEED, Gripper
from baobab.robots.panda.impedance import CartesianImpedanceController, ImpedanceGains
from baobab.robots.panda.model import (
    ARM_JOINTS,
    BASE_BODY,
    FINGER_JOINTS,
    MAX_OPENING,
    PandaModel,
)
from baobab.robots.panda.pose import Pose
from baobab.robots.panda.quaternion import matrix_to_quaternion, transform_pose
from baobab.robots.panda.synced_task import SyncedTaskHandle
from baobab.robots.panda.trajectory import (
    LinearTrajectory,
    TimeScaling,
    TrajectoryGoal,
    parse_goal,
)
from baobab.sim.simulation import Simulation
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus

CONTROL_PERIOD = 0.001
"""Target control period (s); rounded up to a whole number of physics steps."""

TASK_PERIOD = 0.1
"""How often (s of sim time) the server finishes the tasks the control loop saw end, besides
whenever a task handle is read (which is what makes a task's end visible at once)."""

SHOULDER_HEIGHT = 0.333
"""Height of joint 2's axis above the base (m)."""

REACH = 0.855 + 0.1034
"""Largest distance from the shoulder to the TCP (m): the Panda's reach plus the hand."""

MAX_MOTION_DURATION = 600.0
"""Longest motion accepted (s); the trajectory is sampled up front at the control period."""


@dataclass(frozen=True)
class ArmServerConfig:
    """Tolerances and timeouts of the arm tasks.

    Attributes:
        position_tolerance: a motion succeeds within this distance of its goal (m).
        orientation_tolerance: ... and within this angle (rad).
        settle_timeout: time allowed after the trajectory ends to get within tolerance (s).
        max_position_tracking_error: the motion fails when the TCP is farther than this from
            the trajectory's current set-point (m): something blocks the arm.
        max_orientation_tracking_error: the same for the orientation (rad).
        gripper_timeout: a gripper command fails after this long (s).
        stall_time: the fingers count as stopped after this long below the stall speed (s).
        time_scaling: default time scaling of ``move_to``.
    """

    position_tolerance: float = 0.005
    orientation_tolerance: float = 0.02
    settle_timeout: float = 1.0
    max_position_tracking_error: float = 0.04
    max_orientation_tracking_error: float = 0.25
    gripper_timeout: float = 3.0
    stall_time: float = 0.05
    time_scaling: TimeScaling = TimeScaling.RUCKIG


@dataclass
class _Motion:
    handle: SyncedTaskHandle
    setpoints: np.ndarray  # (N, 7): position and quaternion x, y, z, w per control step
    start_step: int
    duration: float


@dataclass
class _GripperMotion:
    handle: SyncedTaskHandle
    closing: bool
    require_object: bool
    start_step: int


class ArmServer:
    """Runs the Panda inside a :class:`Simulation` and serves goal-style tasks.

    Args:
        sim: the simulation holding a Panda attached with ``prefix``.
        prefix: name prefix of the robot's elements in the model.
        gains: impedance gains (default :class:`ImpedanceGains`).
        config: task tolerances and timeouts.
        contact_sensor: name of a sensor counting the robot's contacts with its surroundings;
            :attr:`contact_steps` counts the control steps in which it read above zero.

    Raises:
        PandaSceneError: if the model does not reserve the control loop's userdata slots
            (``MjSpec.nuserdata = native_loop.USERDATA_SLOTS``) or integrates with RK4.
    """

    def __init__(
        self,
        sim: Simulation,
        *,
        prefix: str = "panda/",
        gains: ImpedanceGains | None = None,
        config: ArmServerConfig | None = None,
        contact_sensor: str | None = None,
    ) -> None:
        self.sim = sim
        self.prefix = prefix
        self.config = config or ArmServerConfig()
        model, data = sim.model, sim.data
        self.period = sim.physics_dt * max(1, math.ceil(CONTROL_PERIOD / sim.physics_dt - 1e-9))

        sim.forward()
        base = data.body(prefix + BASE_BODY)
        self.base_position = base.xpos.copy()
        self.base_rotation = Rotation.from_matrix(base.xmat.reshape(3, 3))
        gravity_in_base = self.base_rotation.inv().apply(model.opt.gravity)
        self.pin_model = PandaModel(gravity=gravity_in_base)
        self.controller = CartesianImpedanceController(self.pin_model, gains, period=self.period)
        self._no_motion = np.zeros((1, 7))
        self._base_matrix = self.base_rotation.as_matrix()
        self._loop = self._loop_record(model, prefix, contact_sensor)
        self._record = self._loop[0]
        self._steps = self._loop["steps"]  # a view: the control steps taken
        self._synced_steps = -1
        self._world_pose = np.empty(7)
        self._tcp_pose_step = -1
        self._tcp_pose = Pose((0.0, 0.0, 0.0))
        self.hand = Gripper(model, data, prefix, servo=self._record["gripper_servo"])
        self._record["gripper_actuator"] = self.hand.actuator
        self._motion: _Motion | None = None
        self._gripper_motion: _GripperMotion | None = None
        self.controller.reset(self._configuration(data))
        self.hand.hold_current()
        native_loop.attach(data, model, self._loop)
        weakref.finalize(self, native_loop.detach, data)
        # The simulation holds the server through this callback: the control loop lives as
        # long as the simulation does.
        task_period = self.period * max(1, round(TASK_PERIOD / self.period))
        self.callback = sim.every(task_period, self._sync_tasks, name="panda_arm_tasks")

    def _loop_record(
        self, model: mujoco.MjModel, prefix: str, contact_sensor: str | None
    ) -> np.ndarray:
        """The compiled loop's record: addresses resolved by name once, and the task rules."""
        loop = np.zeros(1, dtype=ARM_LOOP)
        record, config = loop[0], self.config
        joints = [model.joint(prefix + name) for name in (*ARM_JOINTS, *FINGER_JOINTS)]
        record["qpos_index"] = [int(j.qposadr[0]) for j in joints]
        record["dof_index"] = [int(j.dofadr[0]) for j in joints]
        record["arm_actuators"] = [model.actuator(prefix + name).id for name in ARM_JOINTS]
        record["contact_sensor"] = (
            -1 if contact_sensor is None else int(model.sensor(contact_sensor).adr[0])
        )
        record["controller_address"] = self.controller.buffer.ctypes.data
        self._point_at(record, self._no_motion)
        record["period"] = self.period
        record["period_steps"] = round(self.period / self.sim.physics_dt)
        record["gripper_step"] = OPENING_SPEED * self.period
        for name in (
            "position_tolerance",
            "orientation_tolerance",
            "settle_timeout",
            "max_position_tracking_error",
            "max_orientation_tracking_error",
            "gripper_timeout",
            "stall_time",
        ):
            record[name] = getattr(config, name)
        record["stall_speed"] = STALL_SPEED
        record["open_width"] = MAX_OPENING - 0.001
        return loop

    # ----------------------------------------------------------------- queries

    def tcp_pose(self) -> Pose:
        """The TCP pose in the world frame, measured at the last control step."""
        steps = int(self._steps[0])
        if steps != self._tcp_pose_step:  # the probes ask several times per step
            position, rotation = self.controller.measured_pose
            world = self._world_pose
            transform_pose(self._base_matrix, self.base_position, position, rotation, world)
            x, y, z, qx, qy, qz, qw = world.tolist()
            self._tcp_pose = Pose((x, y, z), (qx, qy, qz, qw))
            self._tcp_pose_step = steps
        return self._tcp_pose

    def setpoint_position(self) -> tuple[float, float, float]:
        """The controller's set-point position in the world frame (m)."""
        target = self.controller.target_position
        x, y, z = (self.base_position + self._base_matrix @ target).tolist()
        return x, y, z

    @property
    def busy(self) -> bool:
        """True while a motion task runs."""
        self._sync_tasks()
        return self._motion is not None

    @property
    def contact_steps(self) -> int:
        """Control steps in which the contact sensor (if any) counted a robot contact."""
        return int(self._record["contact_steps"])

    # ------------------------------------------------------------------ tasks

    def move_to(
        self, pose: Pose, duration: float, *, time_scaling: TimeScaling | None = None
    ) -> TaskHandle:
        """Move the TCP to ``pose`` (world frame) along a straight line in ``duration`` s.

        The trajectory takes max(duration, the Panda's minimum) with ruckig time scaling. A
        running motion is preempted (CANCELED). Feedback, as of the last control step:
        ``remaining_time`` (s), ``position_error`` (m) and ``orientation_error`` (rad) between
        the TCP and the trajectory's current set-point. The task succeeds once the trajectory
        has ended and the TCP is within the configured tolerances of the goal.

        Raises:
            TrajectoryGoalError: if ``duration`` is not strictly positive.
        """
        return self.execute_goal([duration, *pose.position, *pose.quaternion], time_scaling)

    def execute_goal(
        self, goal: list[float] | np.ndarray, time_scaling: TimeScaling | None = None
    ) -> TaskHandle:
        """Run a seed-style goal ``[T, x, y, z, qx, qy, qz, qw]`` (world frame).

        Raises:
            TrajectoryGoalError: if the goal fails the seed's checks (size 8, T > 0,
                normalisable quaternion) or T exceeds :data:`MAX_MOTION_DURATION`.
        """
        parsed = parse_goal(goal)
        if parsed.duration > MAX_MOTION_DURATION:
            raise TrajectoryGoalError(
                f"goal duration {parsed.duration:g} s exceeds the {MAX_MOTION_DURATION:g} s limit"
            )
        self._sync_tasks()
        handle = SyncedTaskHandle("move_to", self._cancel_motion, self._sync_tasks)
        if self._motion is not None:
            self._end_motion(TaskOutcome(TaskStatus.CANCELED, 0, "preempted by a new goal"))
        shoulder = self.base_position + self.base_rotation.apply([0.0, 0.0, SHOULDER_HEIGHT])
        if np.linalg.norm(parsed.position - shoulder) > REACH:
            handle.finish(
                _failure(
                    ArmErrorCode.GOAL_UNREACHABLE,
                    f"goal {np.round(parsed.position, 3).tolist()} is out of the arm's reach",
                )
            )
            return handle
        position, quaternion = self._to_base(parsed.position, Rotation.from_quat(parsed.quaternion))
        start_position, start_rotation = self.controller.tcp
        start_quaternion = np.empty(4)
        matrix_to_quaternion(start_rotation, start_quaternion)
        trajectory = LinearTrajectory(
            start_position,
            start_quaternion,
            TrajectoryGoal(parsed.duration, position, quaternion),
            time_scaling=time_scaling or self.config.time_scaling,
        )
        steps = math.ceil(trajectory.duration / self.period - 1e-9)
        positions, quaternions = trajectory.sample(np.arange(steps + 1) * self.period)
        setpoints = np.ascontiguousarray(np.hstack([positions, quaternions]))
        record = self._record
        self._motion = _Motion(handle, setpoints, int(self._steps[0]), trajectory.duration)
        self._point_at(record, setpoints)
        record["motion_start"] = record["steps"]
        record["motion_duration"] = trajectory.duration
        record["motion_end"] = MotionEnd.RUNNING
        record["motion_active"] = 1
        handle.live_feedback.update(
            remaining_time=trajectory.duration, position_error=0.0, orientation_error=0.0
        )
        return handle

    def gripper(
        self, action: Literal["open", "close"], *, require_object: bool = False
    ) -> TaskHandle:
        """Open the hand fully or close it; a close ends when the fingers stop.

        Feedback: ``width`` (m) and, once a close ends, ``grasped_object`` (the name of the
        body held between the fingers, or None).

        Args:
            action: ``"open"`` or ``"close"``.
            require_object: with ``"close"``, fail (GRASP_FAILED) unless an object ends up
                between the fingers.

        Raises:
            GripperCommandError: for any other action.
        """
        if action not in ("open", "close"):
            raise GripperCommandError(f"gripper action must be 'open' or 'close', got {action!r}")
        self._sync_tasks()
        if self._gripper_motion is not None:
            self._end_gripper(TaskOutcome(TaskStatus.CANCELED, 0, "preempted by a new command"))
        handle = SyncedTaskHandle(f"gripper_{action}", self._cancel_gripper, self._sync_tasks)
        closing = action == "close"
        self.hand.command(0.0 if closing else MAX_OPENING)
        record = self._record
        self._gripper_motion = _GripperMotion(handle, closing, require_object, int(self._steps[0]))
        record["gripper_closing"] = int(closing)
        record["gripper_start"] = record["steps"]
        record["gripper_stalled_steps"] = 0
        record["gripper_end"] = GripperEnd.RUNNING
        record["gripper_active"] = 1
        handle.live_feedback.update(width=self.hand.width, grasped_object=None)
        return handle

    def hold(self) -> None:
        """Hold the TCP where it is now (also what cancelling a motion does)."""
        position, rotation = self.controller.tcp
        quaternion = np.empty(4)
        matrix_to_quaternion(rotation, quaternion)
        self.controller.hold(position, quaternion)

    # ------------------------------------------------------------ task bookkeeping

    def _sync_tasks(self, _time: float | None = None) -> None:
        """Bring the tasks up to date with the control loop: feedback, and the ones it ended."""
        steps = int(self._steps[0])
        if steps == self._synced_steps:  # the loop has not run since
            return
        self._synced_steps = steps
        record = self._record
        motion = self._motion
        if motion is not None and steps > motion.start_step:
            elapsed = float(record["motion_elapsed"])
            position_error, orientation_error = record["motion_errors"].tolist()
            motion.handle.live_feedback.update(
                remaining_time=max(0.0, motion.duration - elapsed),
                position_error=position_error,
                orientation_error=orientation_error,
            )
            end = MotionEnd(int(record["motion_end"]))
            if end is not MotionEnd.RUNNING:
                self._end_motion(
                    self._motion_outcome(end, elapsed, position_error, orientation_error)
                )
        task = self._gripper_motion
        if task is not None and steps > task.start_step:
            width = float(record["gripper_width"])
            task.handle.live_feedback.update(width=width)
            end_of_command = GripperEnd(int(record["gripper_end"]))
            if end_of_command is not GripperEnd.RUNNING:
                self._end_gripper(self._gripper_outcome(task, end_of_command, width))

    def _motion_outcome(
        self, end: MotionEnd, elapsed: float, position_error: float, orientation_error: float
    ) -> TaskOutcome:
        if end is MotionEnd.SUCCEEDED:
            return TaskOutcome(TaskStatus.SUCCEEDED)
        if end is MotionEnd.TRACKING_LOST:
            return _failure(
                ArmErrorCode.TRACKING_LOST,
                f"tracking lost at t={elapsed:.3f} s: the TCP is "
                f"{position_error * 1000:.1f} mm / {orientation_error:.3f} rad off its "
                "set-point (blocked?)",
            )
        return _failure(
            ArmErrorCode.GOAL_NOT_REACHED,
            f"goal not reached {self.config.settle_timeout:g} s after the trajectory "
            f"ended: {position_error * 1000:.1f} mm / {orientation_error:.3f} rad off",
        )

    def _gripper_outcome(self, task: _GripperMotion, end: GripperEnd, width: float) -> TaskOutcome:
        if end is GripperEnd.CLOSED:
            grasped = self.hand.grasped_body() if width > MIN_GRASP_WIDTH else None
            task.handle.live_feedback.update(grasped_object=grasped)
            if grasped is None and task.require_object:
                return _failure(
                    ArmErrorCode.GRASP_FAILED,
                    f"the hand closed on nothing (width {width * 1000:.1f} mm)",
                )
            return TaskOutcome(TaskStatus.SUCCEEDED)
        if end is GripperEnd.OPENED:
            return TaskOutcome(TaskStatus.SUCCEEDED)
        if end is GripperEnd.BLOCKED:
            return _failure(
                ArmErrorCode.GRIPPER_BLOCKED,
                f"the fingers stopped at {width * 1000:.1f} mm while opening",
            )
        return _failure(
            ArmErrorCode.GRIPPER_TIMEOUT,
            f"the gripper did not finish within {self.config.gripper_timeout:g} s",
        )

    # ------------------------------------------------------------ task endings

    def _end_motion(self, outcome: TaskOutcome) -> None:
        motion, self._motion = self._motion, None
        self._record["motion_active"] = 0
        self._point_at(self._record, self._no_motion)
        if motion is not None:
            motion.handle.finish(outcome)

    def _end_gripper(self, outcome: TaskOutcome) -> None:
        task, self._gripper_motion = self._gripper_motion, None
        self._record["gripper_active"] = 0
        if task is not None:
            task.handle.finish(outcome)

    def _cancel_motion(self, handle: TaskHandle) -> None:
        if self._motion is not None and self._motion.handle is handle:
            self.hold()
            self._end_motion(TaskOutcome(TaskStatus.CANCELED, 0, "canceled"))

    def _cancel_gripper(self, handle: TaskHandle) -> None:
        if self._gripper_motion is not None and self._gripper_motion.handle is handle:
            self.hand.hold_current()
            self._end_gripper(TaskOutcome(TaskStatus.CANCELED, 0, "canceled"))

    # ---------------------------------------------------------------- frames

    def _configuration(self, data: mujoco.MjData) -> np.ndarray:
        return data.qpos[self._record["qpos_index"]]

    @staticmethod
    def _point_at(record: np.void, setpoints: np.ndarray) -> None:
        """Make the loop read ``setpoints`` (N, 7), which the server keeps alive meanwhile."""
        record["setpoints_address"] = setpoints.ctypes.data
        record["setpoints_rows"] = setpoints.shape[0]

    def _to_base(self, position: np.ndarray, rotation: Rotation) -> tuple[np.ndarray, np.ndarray]:
        inverse = self.base_rotation.inv()
        return inverse.apply(position - self.base_position), (inverse * rotation).as_quat()


def _failure(code: ArmErrorCode, message: str) -> TaskOutcome:
    return TaskOutcome(TaskStatus.FAILED, int(code), message, code.name)
