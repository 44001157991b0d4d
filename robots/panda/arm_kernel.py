"""The arm server's 1 kHz work as one compiled step: control, gripper servo and task checks.

:class:`~baobab.robots.panda.arm_server.ArmServer` keeps one :data:`ARM_LOOP` record, and
:func:`arm_loop_step` runs once per control period, inside MuJoCo's own step
(:mod:`baobab.robots.panda.native_loop`). It reads the arm's joint state from MjData, takes
the running motion's set-point for this step, runs the impedance controller
(:func:`~baobab.robots.panda.impedance_law.control_step`), writes the seven joint torques,
advances the gripper's set-point, and checks the running tasks as the server's rules say: a
motion that lost tracking (the arm then holds where it is), reached its goal or did not settle
in time; a gripper command whose fingers stopped, opened fully or ran out of time. It records
how a task ended; the server turns that into the task's outcome when someone next looks.
"""

from __future__ import annotations

import enum

import numba
import numpy as np

from baobab.robots.panda.chain_dynamics import CHAIN_JOINTS
from baobab.robots.panda.gripper import advance_servo
from baobab.robots.panda.impedance_law import POSE_SIZE, control_step, store_pose
from baobab.robots.panda.model import ARM_DOF
from baobab.robots.panda.quaternion import matrix_to_quaternion
from baobab.sim.records import Record


class MotionEnd(enum.IntEnum):
    """How the running motion ended (``ARM_LOOP.motion_end``)."""

    RUNNING = 0
    SUCCEEDED = 1
    TRACKING_LOST = 2
    GOAL_NOT_REACHED = 3


class GripperEnd(enum.IntEnum):
    """How the running gripper command ended (``ARM_LOOP.gripper_end``)."""

    RUNNING = 0
    CLOSED = 1  # the fingers stopped while closing: on an object, or shut
    OPENED = 2
    BLOCKED = 3  # the fingers stopped while opening
    TIMED_OUT = 4


ARM_LOOP = np.dtype(
    [
        # Where the arm lives in MjData: addresses of its arrays, for the native loop (valid
        # while the MjData lives), their sizes, and the arm's entries.
        ("qpos_address", np.int64),
        ("qvel_address", np.int64),
        ("ctrl_address", np.int64),
        ("sensordata_address", np.int64),
        ("nq", np.int64),
        ("nv", np.int64),
        ("nu", np.int64),
        ("nsensordata", np.int64),
        ("qpos_index", np.int64, CHAIN_JOINTS),
        ("dof_index", np.int64, CHAIN_JOINTS),
        ("arm_actuators", np.int64, ARM_DOF),
        ("gripper_actuator", np.int64),
        ("contact_sensor", np.int64),  # sensordata entry counting robot contacts, or -1
        # The controller's record and the running motion's set-points (addresses).
        ("controller_address", np.int64),
        ("setpoints_address", np.int64),
        ("setpoints_rows", np.int64),
        # Clock: the control period, physics steps per control step, the sim time of the last
        # physics step seen (a forward and a step at the same time are one step), counters.
        ("period", np.float64),
        ("period_steps", np.int64),
        ("physics_steps", np.int64),
        ("last_time", np.float64),
        ("steps", np.int64),  # control steps taken
        ("contact_steps", np.int64),  # control steps that saw a robot contact
        # The joint state read at the last control step (rad, m; rad/s, m/s).
        ("q", np.float64, CHAIN_JOINTS),
        ("v", np.float64, CHAIN_JOINTS),
        # The hand: set-point and goal of its width (m), set-point change per control step.
        ("gripper_servo", np.float64, 2),
        ("gripper_step", np.float64),
        # Task rules (ArmServerConfig), in m, rad and s.
        ("position_tolerance", np.float64),
        ("orientation_tolerance", np.float64),
        ("settle_timeout", np.float64),
        ("max_position_tracking_error", np.float64),
        ("max_orientation_tracking_error", np.float64),
        ("gripper_timeout", np.float64),
        ("stall_time", np.float64),
        ("stall_speed", np.float64),
        ("open_width", np.float64),  # an opening command has succeeded at this width
        # The running motion, and what its last control step saw.
        ("motion_active", np.int64),
        ("motion_start", np.int64),  # control steps taken when it started
        ("motion_duration", np.float64),
        ("motion_elapsed", np.float64),
        ("motion_errors", np.float64, 2),  # distance (m) and angle (rad) to the set-point
        ("motion_end", np.int64),  # a MotionEnd
        # The running gripper command, and what its last control step saw.
        ("gripper_active", np.int64),
        ("gripper_closing", np.int64),
        ("gripper_start", np.int64),
        ("gripper_stalled_steps", np.int64),
        ("gripper_width", np.float64),
        ("gripper_end", np.int64),  # a GripperEnd
    ]
)
"""The arm server's compiled state. All fields are 8 bytes wide: the record travels to the
kernels as a float64 buffer."""

_LEFT_FINGER, _RIGHT_FINGER = ARM_DOF, ARM_DOF + 1


@numba.njit(cache=True, nogil=True, error_model="numpy")
def arm_loop_step(
    qpos: np.ndarray,
    qvel: np.ndarray,
    ctrl: np.ndarray,
    sensordata: np.ndarray,
    setpoints: np.ndarray,
    controller: Record,
    loop: Record,
) -> None:  # pragma: no cover - compiled
    """One control step of the arm and the hand, and the checks of the running tasks.

    Args:
        qpos: ``MjData.qpos``.
        qvel: ``MjData.qvel``.
        ctrl: ``MjData.ctrl``; the arm's torques (N m) and the gripper's control are written.
        sensordata: ``MjData.sensordata`` (read only if ``loop.contact_sensor >= 0``).
        setpoints: the running motion's poses, one row per control step (N, 7): position (m)
            and quaternion x, y, z, w, in the base frame (ignored when no motion runs).
        controller: the controller's :data:`~baobab.robots.panda.impedance_law.CONTROLLER`
            record.
        loop: the :data:`ARM_LOOP` record.
    """
    q, v = loop.q, loop.v
    for j in range(CHAIN_JOINTS):
        q[j] = qpos[loop.qpos_index[j]]
        v[j] = qvel[loop.dof_index[j]]
    state = controller.state
    motion_step = loop.steps - loop.motion_start
    if loop.motion_active == 1:
        row = setpoints[min(motion_step, setpoints.shape[0] - 1)]
        store_pose(state.target, row[:3], row[3:POSE_SIZE])
    control_step(q, v, controller)
    for j in range(ARM_DOF):
        ctrl[loop.arm_actuators[j]] = state.torque[j]
    ctrl[loop.gripper_actuator] = advance_servo(loop.gripper_servo, loop.gripper_step)
    if loop.contact_sensor >= 0 and sensordata[loop.contact_sensor] > 0.0:
        loop.contact_steps += 1
    if loop.motion_active == 1:
        _check_motion(motion_step * loop.period, controller, loop)
    if loop.gripper_active == 1:
        _check_gripper(q[_LEFT_FINGER] + q[_RIGHT_FINGER], v[_LEFT_FINGER] + v[_RIGHT_FINGER], loop)
    loop.steps += 1


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _check_motion(elapsed: float, controller: Record, loop: Record) -> None:  # pragma: no cover
    """The motion's rules after a control step (the server's ``move_to`` contract)."""
    state = controller.state
    position_error, angle_error = state.tracking[0], state.tracking[1]
    loop.motion_elapsed = elapsed
    loop.motion_errors[0] = position_error
    loop.motion_errors[1] = angle_error
    if (
        position_error > loop.max_position_tracking_error
        or angle_error > loop.max_orientation_tracking_error
    ):
        hold_measured_pose(controller)
        loop.motion_end = MotionEnd.TRACKING_LOST
    elif elapsed >= loop.motion_duration:
        if position_error <= loop.position_tolerance and angle_error <= loop.orientation_tolerance:
            loop.motion_end = MotionEnd.SUCCEEDED
        elif elapsed >= loop.motion_duration + loop.settle_timeout:
            loop.motion_end = MotionEnd.GOAL_NOT_REACHED
    if loop.motion_end != MotionEnd.RUNNING:
        loop.motion_active = 0


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _check_gripper(width: float, width_rate: float, loop: Record) -> None:  # pragma: no cover
    """The gripper command's rules after a control step (the server's ``gripper`` contract)."""
    loop.gripper_width = width
    if abs(width_rate) < loop.stall_speed:
        loop.gripper_stalled_steps += 1
    else:
        loop.gripper_stalled_steps = 0
    settled = loop.gripper_servo[0] == loop.gripper_servo[1]
    stopped = settled and loop.gripper_stalled_steps * loop.period >= loop.stall_time
    elapsed = (loop.steps - loop.gripper_start) * loop.period
    closing = loop.gripper_closing == 1
    if closing and stopped:
        loop.gripper_end = GripperEnd.CLOSED
    elif not closing and width >= loop.open_width:
        loop.gripper_end = GripperEnd.OPENED
    elif not closing and stopped:
        loop.gripper_end = GripperEnd.BLOCKED
    elif elapsed >= loop.gripper_timeout:
        loop.gripper_end = GripperEnd.TIMED_OUT
    if loop.gripper_end != GripperEnd.RUNNING:
        loop.gripper_active = 0


@numba.njit(cache=True, nogil=True, error_model="numpy")
def hold_measured_pose(controller: Record) -> None:  # pragma: no cover - compiled
    """Make the TCP pose measured at the last step the set-point and the reference."""
    state = controller.state
    quaternion = np.empty(4)
    matrix_to_quaternion(state.rotation, quaternion)
    store_pose(state.target, state.position, quaternion)
    state.reference[:] = state.target
    state.tracking_stale = 1.0
