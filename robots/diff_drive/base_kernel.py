"""A differential-drive base's 100 Hz step, compiled, inside MuJoCo's own step.

:class:`~baobab.robots.diff_drive.base.DiffDriveBase` keeps one :data:`BASE_LOOP` record per
robot; the records of one simulation form one array, run by :func:`base_kernel` inside every
``mj_step`` (:mod:`baobab.sim.native_control`). At each of its control ticks a record's step
ramps the commanded body velocity toward ``cmd_vel`` within the acceleration limits, writes
the two wheel velocity targets and integrates wheel odometry from the encoder angles. An
optional probe (the mission metrics) samples, at its own periods, whether the robot touches
an obstacle (from one MuJoCo contact sensor per obstacle geom, two for all of a map's walls)
and the ground-truth position.

Compiled so that the 100 Hz tick wakes no Python: the simulation steps the physics in one
``mj_step`` batch up to the next Python callback, and a Python tick would cut every batch
to 10 ms.

Timing is the firmware's: the work due at physics step k runs inside the step taken from k,
on the state at k, after the Python callbacks due at k. So a ``cmd_vel`` given at k is ramped
toward from the tick at k on, and a callback at k reads the odometry of the tick before. The
kernel acts only while the simulation's gate is open (during ``Simulation.step_to``), so a
``mj_forward`` after editing the state by hand runs nothing.
"""

from __future__ import annotations

import functools
import math
import weakref
from typing import TypeAlias

import numba
import numpy as np

from baobab.sim import native_control
from baobab.sim.errors import SimulationError
from baobab.sim.mujoco_native import mj_get_state, pointer, remainder
from baobab.sim.native_control import STATE_TIME
from baobab.sim.records import Record
from baobab.sim.simulation import Simulation

BASE_LOOP = np.dtype(
    [
        ("group_size", np.int64),  # records in this simulation's array (read from record 0)
        # Where the robot lives in MjData (addresses valid while the MjData lives).
        ("qpos_address", np.int64),
        ("ctrl_address", np.int64),
        ("sensordata_address", np.int64),
        ("gate_address", np.int64),
        ("nq", np.int64),
        ("nu", np.int64),
        ("nsensordata", np.int64),
        ("root_qpos", np.int64),  # qpos address of the free joint (x, y, z, w, x, y, z)
        ("left_qpos", np.int64),
        ("right_qpos", np.int64),
        ("left_actuator", np.int64),
        ("right_actuator", np.int64),
        ("physics_dt", np.float64),  # s
        # The controller: period, next due physics step, figures.
        ("period_steps", np.int64),
        ("next_step", np.int64),
        ("linear_step", np.float64),  # m/s per tick
        ("angular_step", np.float64),  # rad/s per tick
        ("half_separation", np.float64),  # m
        ("wheel_separation", np.float64),  # m
        ("wheel_radius", np.float64),  # m
        ("max_wheel_speed", np.float64),  # m/s at the rim
        ("encoder_tick", np.float64),  # rad
        ("target_linear", np.float64),  # cmd_vel after clipping, m/s
        ("target_angular", np.float64),  # rad/s
        ("commanded_linear", np.float64),  # the ramped twist sent to the wheels, m/s
        ("commanded_angular", np.float64),  # rad/s
        # Wheel odometry.
        ("encoder_left", np.float64),  # rad, quantised
        ("encoder_right", np.float64),
        ("odom_x", np.float64),  # m, odom frame
        ("odom_y", np.float64),
        ("odom_yaw", np.float64),  # rad
        ("odom_linear", np.float64),  # m/s over the last tick
        ("odom_angular", np.float64),  # rad/s
        ("odom_stamp", np.float64),  # s
        # The probe (mission metrics); periods of 0 switch its parts off.
        ("contact_period_steps", np.int64),
        ("contact_next_step", np.int64),
        ("contact_samples", np.int64),  # samples with a robot-obstacle contact
        ("contact_sensor", np.int64),  # sensordata address of the first obstacle's sensor
        ("contact_sensors", np.int64),  # one per obstacle geom but a map's walls
        ("contact_world_sensors", np.int64),  # the first ones, of the world body's geoms
        ("contact_map_sensor", np.int64),  # address of the floor's, then the world body's; or -1
        ("contact_address", np.int64),  # float64[contact_sensors (+ 1 with a map)]: 1 once touched
        ("pose_period_steps", np.int64),
        ("pose_next_step", np.int64),
        ("pose_count", np.int64),  # samples in the buffer, drained by Python
        ("pose_capacity", np.int64),
        ("pose_address", np.int64),  # float64[pose_capacity, 3]: t (s), x, y (m)
        ("pose_overflow", np.int64),
    ]
)
"""One robot's base loop: where it lives in MjData, its state and its probe (all 8-byte)."""

LOOP_WORDS = BASE_LOOP.itemsize // 8
"""A record's size in 8-byte words."""
WORD = {name: field[1] // 8 for name, field in (BASE_LOOP.fields or {}).items()}
"""Each field's index in a record viewed as 8-byte words (Python reads and writes them so)."""

Loop: TypeAlias = Record
"""One :data:`BASE_LOOP` record in compiled code (numba's record type; fields by name)."""


@numba.njit(cache=True, nogil=True)
def _control_tick(loop: Loop, qpos: np.ndarray, ctrl: np.ndarray, time: float) -> None:
    """Ramp toward cmd_vel, command the wheels, integrate odometry."""
    linear, angular = loop.commanded_linear, loop.commanded_angular
    step = loop.linear_step
    linear = min(max(loop.target_linear, linear - step), linear + step)
    step = loop.angular_step
    angular = min(max(loop.target_angular, angular - step), angular + step)
    loop.commanded_linear, loop.commanded_angular = linear, angular
    half = loop.half_separation
    left, right = linear - angular * half, linear + angular * half
    excess = max(abs(left), abs(right)) / loop.max_wheel_speed
    if excess > 1.0:
        left, right = left / excess, right / excess
    ctrl[loop.left_actuator] = left / loop.wheel_radius
    ctrl[loop.right_actuator] = right / loop.wheel_radius

    tick = loop.encoder_tick
    left_angle = np.rint(qpos[loop.left_qpos] / tick) * tick
    right_angle = np.rint(qpos[loop.right_qpos] / tick) * tick
    d_left = (left_angle - loop.encoder_left) * loop.wheel_radius
    d_right = (right_angle - loop.encoder_right) * loop.wheel_radius
    loop.encoder_left, loop.encoder_right = left_angle, right_angle
    distance = (d_left + d_right) / 2
    turn = (d_right - d_left) / loop.wheel_separation
    yaw = loop.odom_yaw
    heading = yaw + turn / 2  # second-order (midpoint) integration over the tick
    loop.odom_x = loop.odom_x + distance * math.cos(heading)
    loop.odom_y = loop.odom_y + distance * math.sin(heading)
    loop.odom_yaw = remainder(yaw + turn, 2 * math.pi)
    elapsed = time - loop.odom_stamp
    if elapsed > 0:
        loop.odom_linear = distance / elapsed
        loop.odom_angular = turn / elapsed
    loop.odom_stamp = time


@numba.njit(cache=True, nogil=True)
def _sample_contacts(loop: Loop) -> None:
    """Count a sample if any obstacle's contact sensor reads a contact; flag those touched.

    A map's walls are the last entry: the robot touches them when the world body's sensor
    counts more contacts than the floor's and the world file's obstacles' sensors together
    (each sensor reads the number of contacts it matches).
    """
    count = loop.contact_sensors
    sensordata = numba.carray(pointer(loop.sensordata_address), (loop.nsensordata,), np.float64)
    with_map = loop.contact_map_sensor >= 0
    touched = numba.carray(pointer(loop.contact_address), (count + with_map,), np.float64)
    first = loop.contact_sensor
    any_touched = False
    world_geoms = 0.0
    for index in range(count):
        found = sensordata[first + index]
        if index < loop.contact_world_sensors:
            world_geoms += found
        if found > 0.0:
            touched[index] = 1.0
            any_touched = True
    if with_map:
        floor = sensordata[loop.contact_map_sensor]
        if sensordata[loop.contact_map_sensor + 1] - floor - world_geoms > 0.0:
            touched[count] = 1.0
            any_touched = True
    if any_touched:
        loop.contact_samples += 1


@numba.njit(cache=True, nogil=True)
def _sample_pose(loop: Loop, qpos: np.ndarray, time: float) -> None:
    if loop.pose_count >= loop.pose_capacity:
        loop.pose_overflow = 1
        return
    poses = numba.carray(pointer(loop.pose_address), (loop.pose_capacity, 3), np.float64)
    row = loop.pose_count
    poses[row, 0] = time
    poses[row, 1] = qpos[loop.root_qpos]
    poses[row, 2] = qpos[loop.root_qpos + 1]
    loop.pose_count = row + 1


@numba.njit(cache=True, nogil=True)
def _next_after(next_step: int, period: int, step: int) -> int:
    next_step += period
    while next_step <= step:
        next_step += period
    return next_step


@numba.njit(cache=True, nogil=True)
def _run_due(loop: Loop, step: int) -> None:
    """Do the work due at physics ``step``."""
    qpos = numba.carray(pointer(loop.qpos_address), (loop.nq,), np.float64)
    time = step * loop.physics_dt
    if loop.period_steps > 0 and loop.next_step <= step:
        ctrl = numba.carray(pointer(loop.ctrl_address), (loop.nu,), np.float64)
        _control_tick(loop, qpos, ctrl, time)
        loop.next_step = _next_after(loop.next_step, loop.period_steps, step)
    if loop.contact_period_steps > 0 and loop.contact_next_step <= step:
        _sample_contacts(loop)
        loop.contact_next_step = _next_after(
            loop.contact_next_step, loop.contact_period_steps, step
        )
    if loop.pose_period_steps > 0 and loop.pose_next_step <= step:
        _sample_pose(loop, qpos, time)
        loop.pose_next_step = _next_after(loop.pose_next_step, loop.pose_period_steps, step)


def base_kernel(model: int, data: int, address: int) -> None:  # pragma: no cover - compiled
    """The kernel (``mjcb_control``) of every base of one simulation (module docstring)."""
    first = numba.carray(pointer(address), (LOOP_WORDS,), np.float64).view(BASE_LOOP)
    size = first[0].group_size
    loops = numba.carray(pointer(address), (size * LOOP_WORDS,), np.float64).view(BASE_LOOP)
    gate = numba.carray(pointer(loops[0].gate_address), (1,), np.int64)
    if gate[0] == 0:
        return
    time = np.empty(1)
    mj_get_state(pointer(model), pointer(data), pointer(time.ctypes.data), STATE_TIME)
    step = int(np.rint(time[0] / loops[0].physics_dt))
    for index in range(size):
        _run_due(loops[index], step)


@functools.cache
def kernel_address() -> int:
    """Compile (or load from numba's cache) :func:`base_kernel` once per process."""
    return native_control.compile_kernel(base_kernel)


MAX_ROBOTS = 8
"""Bases one simulation can hold (the records are preallocated so that none moves)."""


class BaseLoops:
    """The :data:`BASE_LOOP` records of one simulation, run by :func:`base_kernel`.

    It holds no reference to its simulation, which keys it weakly (:func:`base_loops`).
    """

    def __init__(self) -> None:
        self.loops = np.zeros(MAX_ROBOTS, dtype=BASE_LOOP)
        self.words = self.loops.view(np.float64)
        """The records as float64 words: record ``i``'s field ``f`` is
        ``words[i * LOOP_WORDS + WORD[f]]`` (float fields only)."""
        self.size = 0

    def add(self, sim: Simulation) -> np.void:
        """A new, zeroed record (a view into :attr:`loops`), attached to ``sim``.

        Raises:
            SimulationError: if the simulation holds :data:`MAX_ROBOTS` bases already, or its
                model does not reserve the userdata of compiled control.
        """
        if self.size == MAX_ROBOTS:
            raise SimulationError(f"a simulation holds at most {MAX_ROBOTS} mobile bases")
        loop = self.loops[self.size]
        self.size += 1
        self.loops["group_size"] = self.size
        loop["gate_address"] = sim.native_gate.ctypes.data
        native_control.attach(sim.data, sim.model, kernel_address(), self.loops)
        return loop


_loops: weakref.WeakKeyDictionary[Simulation, BaseLoops] = weakref.WeakKeyDictionary()


def base_loops(sim: Simulation) -> BaseLoops:
    """The base records of ``sim`` (created on first use; they live as long as ``sim``)."""
    loops = _loops.get(sim)
    if loops is None:
        loops = _loops[sim] = BaseLoops()
    return loops
