"""The Panda's capability server: goal-style ``move_to`` and ``gripper`` tasks over the sim.

One periodic callback at the control rate (1 kHz when the physics step is 1 ms) reads the
joint state, advances the active motion (a :class:`LinearTrajectory` sampled at the control
period when the goal arrives), runs the Cartesian impedance law, writes the seven joint
torques, moves the gripper set-point and ends the tasks that are done. Poses at this
interface are in the world frame with quaternions x, y, z, w; the controller works in the
base (link0) frame.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Literal

import numpy as np
from scipy.spatial.transform import Rotation

from baobab.robots.panda.errors import GripperCommandError, TrajectoryGoalError
from baobab.robots.panda.gripper import MIN_GRASP_WIDTH, STALL_SPEED, Gripper
from baobab.robots.panda.impedance import CartesianImpedanceController, ImpedanceGains
from baobab.robots.panda.model import (
    ARM_JOINTS,
    BASE_BODY,
    FINGER_JOINTS,
    MAX_OPENING,
    PandaModel,
)
from baobab.robots.panda.pose import Pose
from baobab.robots.panda.quaternion import matrix_to_quaternion
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

SHOULDER_HEIGHT = 0.333
"""Height of joint 2's axis above the base (m)."""

REACH = 0.855 + 0.1034
"""Largest distance from the shoulder to the TCP (m): the Panda's reach plus the hand."""

MAX_MOTION_DURATION = 600.0
"""Longest motion accepted (s); the trajectory is sampled up front at the control period."""


class ArmErrorCode(enum.IntEnum):
    """Why an arm task failed (``TaskOutcome.error_code``)."""

    NONE = 0
    GOAL_UNREACHABLE = 1
    TRACKING_LOST = 2
    GOAL_NOT_REACHED = 3
    GRASP_FAILED = 4
    GRIPPER_BLOCKED = 5
    GRIPPER_TIMEOUT = 6


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
    handle: TaskHandle
    positions: np.ndarray
    quaternions: np.ndarray
    start_step: int
    duration: float


@dataclass
class _GripperMotion:
    handle: TaskHandle
    closing: bool
    require_object: bool
    start_step: int
    stalled_steps: int = 0


class ArmServer:
    """Runs the Panda inside a :class:`Simulation` and serves goal-style tasks.

    Args:
        sim: the simulation holding a Panda attached with ``prefix``.
        prefix: name prefix of the robot's elements in the model.
        gains: impedance gains (default :class:`ImpedanceGains`).
        config: task tolerances and timeouts.
    """

    def __init__(
        self,
        sim: Simulation,
        *,
        prefix: str = "panda/",
        gains: ImpedanceGains | None = None,
        config: ArmServerConfig | None = None,
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
        self.hand = Gripper(model, data, prefix)

        # Addresses resolved by name once. An attached robot's joints are consecutive, so the
        # 1 kHz loop reads the state through views bound here, without copies.
        joints = [model.joint(prefix + name) for name in (*ARM_JOINTS, *FINGER_JOINTS)]
        self._qpos_index = np.array([int(j.qposadr[0]) for j in joints])
        self._dof_index = np.array([int(j.dofadr[0]) for j in joints])
        self._arm_actuators = np.array([model.actuator(prefix + name).id for name in ARM_JOINTS])
        self._q = _gather(data.qpos, self._qpos_index)
        self._v = _gather(data.qvel, self._dof_index)
        self._base_matrix = self.base_rotation.as_matrix()

        self._motion: _Motion | None = None
        self._gripper_motion: _GripperMotion | None = None
        self._steps = 0
        self.controller.reset(self._configuration())
        self.hand.hold_current()
        self.callback = sim.every(self.period, self._control, name="panda_arm_control")

    # ----------------------------------------------------------------- queries

    def tcp_pose(self) -> Pose:
        """The TCP pose in the world frame, measured at the last control step."""
        position, rotation = self.controller.tcp
        quaternion = np.empty(4)
        matrix_to_quaternion(self._base_matrix @ rotation, quaternion)
        x, y, z = (self.base_position + self._base_matrix @ position).tolist()
        qx, qy, qz, qw = quaternion.tolist()
        return Pose((x, y, z), (qx, qy, qz, qw))

    @property
    def busy(self) -> bool:
        """True while a motion task runs."""
        return self._motion is not None

    # ------------------------------------------------------------------ tasks

    def move_to(
        self, pose: Pose, duration: float, *, time_scaling: TimeScaling | None = None
    ) -> TaskHandle:
        """Move the TCP to ``pose`` (world frame) along a straight line in ``duration`` s.

        The trajectory takes max(duration, the Panda's minimum) with ruckig time scaling. A
        running motion is preempted (CANCELED). Feedback, updated every control step:
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
        handle = TaskHandle("move_to", self._cancel_motion)
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
        self._motion = _Motion(handle, positions, quaternions, self._steps, trajectory.duration)
        handle.feedback.update(
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
        if self._gripper_motion is not None:
            previous = self._gripper_motion.handle
            self._gripper_motion = None
            previous.finish(TaskOutcome(TaskStatus.CANCELED, 0, "preempted by a new command"))
        handle = TaskHandle(f"gripper_{action}", self._cancel_gripper)
        closing = action == "close"
        self.hand.command(0.0 if closing else MAX_OPENING)
        self._gripper_motion = _GripperMotion(handle, closing, require_object, self._steps)
        handle.feedback.update(width=self.hand.width, grasped_object=None)
        return handle

    def hold(self) -> None:
        """Hold the TCP where it is now (also what cancelling a motion does)."""
        position, rotation = self.controller.tcp
        quaternion = np.empty(4)
        matrix_to_quaternion(rotation, quaternion)
        self.controller.hold(position, quaternion)

    # ------------------------------------------------------------ control loop

    def _control(self, _time: float) -> None:
        motion = self._motion
        if motion is not None:
            index = min(self._steps - motion.start_step, len(motion.positions) - 1)
            self.controller.set_target(motion.positions[index], motion.quaternions[index])
        torque = self.controller.compute_torque(self._q(), self._v())
        self.sim.data.ctrl[self._arm_actuators] = torque
        self.hand.update(self.period)
        if motion is not None:
            self._update_motion(motion)
        if self._gripper_motion is not None:
            self._update_gripper(self._gripper_motion)
        self._steps += 1

    def _update_motion(self, motion: _Motion) -> None:
        config = self.config
        elapsed = (self._steps - motion.start_step) * self.period
        position_error, orientation_error = self.controller.target_error()
        motion.handle.feedback.update(
            remaining_time=max(0.0, motion.duration - elapsed),
            position_error=position_error,
            orientation_error=orientation_error,
        )
        if (
            position_error > config.max_position_tracking_error
            or orientation_error > config.max_orientation_tracking_error
        ):
            self.hold()
            self._end_motion(
                _failure(
                    ArmErrorCode.TRACKING_LOST,
                    f"tracking lost at t={elapsed:.3f} s: the TCP is "
                    f"{position_error * 1000:.1f} mm / {orientation_error:.3f} rad off its "
                    "set-point (blocked?)",
                )
            )
        elif elapsed >= motion.duration:
            if (
                position_error <= config.position_tolerance
                and orientation_error <= config.orientation_tolerance
            ):
                self._end_motion(TaskOutcome(TaskStatus.SUCCEEDED))
            elif elapsed >= motion.duration + config.settle_timeout:
                self._end_motion(
                    _failure(
                        ArmErrorCode.GOAL_NOT_REACHED,
                        f"goal not reached {config.settle_timeout:g} s after the trajectory "
                        f"ended: {position_error * 1000:.1f} mm / {orientation_error:.3f} rad off",
                    )
                )

    def _update_gripper(self, task: _GripperMotion) -> None:
        hand, config = self.hand, self.config
        width = hand.width
        task.handle.feedback.update(width=width)
        task.stalled_steps = task.stalled_steps + 1 if abs(hand.width_rate) < STALL_SPEED else 0
        stopped = hand.setpoint_settled and task.stalled_steps * self.period >= config.stall_time
        elapsed = (self._steps - task.start_step) * self.period
        if task.closing and stopped:
            grasped = hand.grasped_body() if width > MIN_GRASP_WIDTH else None
            task.handle.feedback.update(grasped_object=grasped)
            if grasped is None and task.require_object:
                self._end_gripper(
                    _failure(
                        ArmErrorCode.GRASP_FAILED,
                        f"the hand closed on nothing (width {width * 1000:.1f} mm)",
                    )
                )
            else:
                self._end_gripper(TaskOutcome(TaskStatus.SUCCEEDED))
        elif not task.closing and width >= MAX_OPENING - 0.001:
            self._end_gripper(TaskOutcome(TaskStatus.SUCCEEDED))
        elif not task.closing and stopped:
            self._end_gripper(
                _failure(
                    ArmErrorCode.GRIPPER_BLOCKED,
                    f"the fingers stopped at {width * 1000:.1f} mm while opening",
                )
            )
        elif elapsed >= config.gripper_timeout:
            self._end_gripper(
                _failure(
                    ArmErrorCode.GRIPPER_TIMEOUT,
                    f"the gripper did not finish within {config.gripper_timeout:g} s",
                )
            )

    # ------------------------------------------------------------ task endings

    def _end_motion(self, outcome: TaskOutcome) -> None:
        motion, self._motion = self._motion, None
        if motion is not None:
            motion.handle.finish(outcome)

    def _end_gripper(self, outcome: TaskOutcome) -> None:
        task, self._gripper_motion = self._gripper_motion, None
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

    def _configuration(self) -> np.ndarray:
        return self._q().copy()

    def _to_base(self, position: np.ndarray, rotation: Rotation) -> tuple[np.ndarray, np.ndarray]:
        inverse = self.base_rotation.inv()
        return inverse.apply(position - self.base_position), (inverse * rotation).as_quat()


def _gather(source: np.ndarray, index: np.ndarray) -> Callable[[], np.ndarray]:
    """A function returning ``source[index]``: a view bound once if ``index`` is consecutive."""
    start = int(index[0])
    if np.array_equal(index, np.arange(start, start + index.size)):
        view = source[start : start + index.size]
        return lambda: view
    return lambda: source[index]


def _failure(code: ArmErrorCode, message: str) -> TaskOutcome:
    return TaskOutcome(TaskStatus.FAILED, int(code), message, code.name)
