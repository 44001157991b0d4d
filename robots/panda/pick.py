"""A scripted pick-and-place of the cube with the arm server's tasks.

The sequence is the one a mission will spell out with ``move_to`` and ``gripper`` leaves:
open, pregrasp above the cube, descend, close on the cube, lift, move above the target,
lower, release, retreat. Each step is one task, polled every ``poll_period`` of sim time;
the first step that does not succeed ends the pick. The cube pose comes from the simulation,
standing in for a perception system.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial.transform import Rotation

from baobab.robots.panda.arm_server import ArmServer
from baobab.robots.panda.pose import Pose
from baobab.robots.panda.scene import (
    CUBE_HALF_SIZE,
    CUBE_JOINT,
    TABLE_HEIGHT,
    cube_pose,
)
from baobab.sim.simulation import Simulation
from baobab.sim.tasks import TaskHandle, TaskStatus


@dataclass(frozen=True)
class PickSettings:
    """Geometry and pace of the pick.

    Attributes:
        pregrasp_height: TCP height above the grasp point before descending (m).
        lift_height: how far the cube is lifted (m).
        place_clearance: gap between cube and table when the hand releases it (m).
        retreat_height: how far the hand rises after releasing (m).
        speed: nominal TCP speed that sets each motion's duration (m/s).
        angular_speed: nominal rotation speed that sets each motion's duration (rad/s).
        min_duration: shortest motion duration (s).
        poll_period: how often the sequence checks its task (s of sim time).
        task_timeout: sim time after which a task that has not ended fails the pick (s).
    """

    pregrasp_height: float = 0.10
    lift_height: float = 0.15
    place_clearance: float = 0.005
    retreat_height: float = 0.10
    speed: float = 0.25
    angular_speed: float = 0.8
    min_duration: float = 0.6
    poll_period: float = 0.01
    task_timeout: float = 15.0


@dataclass(frozen=True)
class StepRecord:
    """How one step of the pick ended."""

    name: str
    status: TaskStatus
    error_code: int
    message: str
    end_time: float


@dataclass
class PickReport:
    """The outcome of :func:`pick_and_place`.

    Attributes:
        succeeded: every step SUCCEEDED.
        steps: the steps run, in order.
        cube_start: cube centre before the pick (m, world).
        cube_final: cube centre after the pick (m, world).
        max_lift: highest rise of the cube above its start, sampled every poll period (m).
        place_error: horizontal distance from the cube's final centre to the target (m).
        arm_table_contact_time: sim time during which a robot geom touched the table or the
            floor, counted at every control step (s).
        sim_time: sim time the pick took (s).
    """

    succeeded: bool = False
    steps: list[StepRecord] = field(default_factory=list)
    cube_start: np.ndarray = field(default_factory=lambda: np.zeros(3))
    cube_final: np.ndarray = field(default_factory=lambda: np.zeros(3))
    max_lift: float = 0.0
    place_error: float = math.inf
    arm_table_contact_time: float = 0.0
    sim_time: float = 0.0

    @property
    def failure(self) -> str:
        """The first failed step and its message, or '' if all succeeded."""
        for step in self.steps:
            if step.status is not TaskStatus.SUCCEEDED:
                return f"{step.name}: {step.status.value} {step.message}".strip()
        return ""


class _PickMonitor:
    """Records the cube's highest lift and the robot's table contacts during the pick.

    The lift is sampled every ``period`` (it changes slowly); the contacts are counted at
    every control step by the arm's compiled loop (:attr:`ArmServer.contact_steps`).
    """

    def __init__(self, sim: Simulation, arm: ArmServer, cube_start_z: float, period: float) -> None:
        self._arm = arm
        self._qpos = sim.data.qpos  # MjData's array (fixed storage), read at every sample
        self._cube_z = int(sim.model.joint(CUBE_JOINT).qposadr[0]) + 2
        self._cube_start_z = cube_start_z
        self._contact_steps_at_start = arm.contact_steps
        self.max_lift = 0.0
        self.handle = sim.every(period, self._record, name="pick_monitor")

    @property
    def contact_time(self) -> float:
        """Sim time (s) during which a robot geom touched the table or the floor."""
        return (self._arm.contact_steps - self._contact_steps_at_start) * self._arm.period

    def _record(self, _time: float) -> None:
        lift = float(self._qpos[self._cube_z]) - self._cube_start_z
        if lift > self.max_lift:
            self.max_lift = lift


def pick_and_place(
    sim: Simulation,
    arm: ArmServer,
    target: np.ndarray | tuple[float, float],
    settings: PickSettings | None = None,
) -> PickReport:
    """Pick the cube and place it centred on ``target`` (x, y in m, world frame).

    Runs the simulation until the sequence ends; returns what happened.
    """
    settings = settings or PickSettings()
    start_time = sim.time
    cube = cube_pose(sim)
    report = PickReport(cube_start=cube.position_array)
    monitor = _PickMonitor(sim, arm, cube.position[2], settings.poll_period)
    place_z = TABLE_HEIGHT + CUBE_HALF_SIZE + settings.place_clearance
    try:
        grasp = Pose.top_down(cube.position, _grasp_yaw(cube.rotation))
        sequence = [
            ("open", lambda: arm.gripper("open")),
            (
                "pregrasp",
                lambda: _move(arm, grasp.translated(dz=settings.pregrasp_height), settings),
            ),
            ("descend", lambda: _move(arm, grasp, settings)),
            ("close", lambda: arm.gripper("close", require_object=True)),
            ("lift", lambda: _move(arm, grasp.translated(dz=settings.lift_height), settings)),
            ("transfer", lambda: _move(arm, _over_target(sim, arm, target, grasp, None), settings)),
            ("lower", lambda: _move(arm, _over_target(sim, arm, target, grasp, place_z), settings)),
            ("release", lambda: arm.gripper("open")),
            (
                "retreat",
                lambda: _move(arm, arm.tcp_pose().translated(dz=settings.retreat_height), settings),
            ),
        ]
        for name, start in sequence:
            record = _run(sim, name, start(), settings)
            report.steps.append(record)
            if record.status is not TaskStatus.SUCCEEDED:
                break
    finally:
        monitor.handle.cancel()
    report.cube_final = cube_pose(sim).position_array
    report.max_lift = monitor.max_lift
    report.place_error = float(np.linalg.norm(report.cube_final[:2] - np.asarray(target)[:2]))
    report.arm_table_contact_time = monitor.contact_time
    report.sim_time = sim.time - start_time
    report.succeeded = len(report.steps) == len(sequence) and not report.failure
    return report


def _run(sim: Simulation, name: str, handle: TaskHandle, settings: PickSettings) -> StepRecord:
    deadline = sim.time + settings.task_timeout
    while not handle.status.done and sim.time < deadline:
        sim.step_for(settings.poll_period)
    if not handle.status.done:
        handle.cancel()
        return StepRecord(name, TaskStatus.FAILED, -1, "timed out", sim.time)
    outcome = handle.outcome
    assert outcome is not None  # done implies an outcome
    return StepRecord(name, outcome.status, outcome.error_code, outcome.error_msg, sim.time)


def _move(arm: ArmServer, pose: Pose, settings: PickSettings) -> TaskHandle:
    distance, angle = arm.tcp_pose().distance_to(pose)
    duration = max(settings.min_duration, distance / settings.speed, angle / settings.angular_speed)
    return arm.move_to(pose, duration)


def _over_target(
    sim: Simulation,
    arm: ArmServer,
    target: np.ndarray | tuple[float, float],
    grasp: Pose,
    cube_z: float | None,
) -> Pose:
    """TCP pose that puts the held cube's centre over ``target`` (at ``cube_z`` if given).

    The cube's offset in the hand, measured now, is compensated, as an in-hand pose estimate
    would be.
    """
    cube_position = cube_pose(sim).position_array
    tcp = arm.tcp_pose()
    offset = cube_position - tcp.position_array
    z = tcp.position[2] if cube_z is None else cube_z - offset[2]
    x, y = np.asarray(target, dtype=float)[:2] - offset[:2]
    return Pose((x, y, z), grasp.quaternion)


def _grasp_yaw(cube_rotation: Rotation) -> float:
    """Yaw (rad) of a top-down grasp across the cube's faces, folded into [-pi/4, pi/4]."""
    x_axis = cube_rotation.apply([1.0, 0.0, 0.0])
    yaw = math.atan2(x_axis[1], x_axis[0])
    return (yaw + math.pi / 4) % (math.pi / 2) - math.pi / 4
