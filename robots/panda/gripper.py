"""The Franka Hand in MuJoCo: opening command, width, and grasp detection.

The hand is a position servo on the mean finger travel (tendon ``split``; the fingers are
coupled by a joint equality). Commands move the servo's set-point at a bounded speed, as the
real hand does, so the fingers meet an object softly and then squeeze it with the servo's
force. A grasp is detected when the fingers have stopped with a width above zero and the pads
of both fingers touch the same body that is not part of the robot.
"""

from __future__ import annotations

import mujoco
import numba
import numpy as np

from baobab.robots.panda.model import (
    BASE_BODY,
    FINGER_JOINTS,
    GRIPPER_ACTUATOR,
    LEFT_PAD_GEOM,
    MAX_OPENING,
    RIGHT_PAD_GEOM,
)

OPENING_SPEED = 0.1
"""Speed of the commanded opening (m/s of width): 0.05 m/s per finger."""

STALL_SPEED = 0.002
"""Width rate (m/s) under which the fingers count as stopped."""

MIN_GRASP_WIDTH = 0.002
"""Widths (m) above this when closed mean something is between the fingers."""


@numba.njit(cache=True, nogil=True)
def advance_servo(servo: np.ndarray, step: float) -> float:  # pragma: no cover - compiled
    """Move the set-point ``servo[0]`` towards the goal ``servo[1]`` by at most ``step`` (m).

    Returns the actuator control: the servo acts on the mean finger travel, half the width.
    """
    setpoint = servo[0]
    setpoint += min(step, max(-step, servo[1] - setpoint))
    servo[0] = setpoint
    return 0.5 * setpoint


class Gripper:
    """MuJoCo side of the Panda hand, for one attached robot.

    Args:
        model: the compiled model holding the robot.
        data: its data.
        prefix: the name prefix the robot was attached with (e.g. ``"panda/"``).
        servo: storage (2,) for the set-point and goal width (m), e.g. a field of a compiled
            control loop's record that advances the set-point itself (see :func:`advance_servo`);
            a new array if None.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        data: mujoco.MjData,
        prefix: str = "",
        *,
        servo: np.ndarray | None = None,
    ) -> None:
        self._model = model
        self._data = data
        self.actuator = int(model.actuator(prefix + GRIPPER_ACTUATOR).id)
        """Index of the gripper's actuator in ``data.ctrl``."""
        left, right = (model.joint(prefix + name) for name in FINGER_JOINTS)
        # Plain indices into MjData's arrays (fixed storage, bound once).
        self._qpos, self._qvel, self._ctrl = data.qpos, data.qvel, data.ctrl
        self._left_qpos, self._right_qpos = int(left.qposadr[0]), int(right.qposadr[0])
        self._left_dof, self._right_dof = int(left.dofadr[0]), int(right.dofadr[0])
        self._left_pads = _pad_geoms(model, prefix + LEFT_PAD_GEOM)
        self._right_pads = _pad_geoms(model, prefix + RIGHT_PAD_GEOM)
        self._robot_body = _in_subtree(model, model.body(prefix + BASE_BODY).id)
        self.servo = np.zeros(2) if servo is None else servo
        """Set-point and goal of the width (m)."""
        self.servo[:] = self.width

    @property
    def width(self) -> float:
        """Distance between the fingers (m): 0 closed, 0.08 fully open."""
        return float(self._qpos[self._left_qpos] + self._qpos[self._right_qpos])

    @property
    def width_rate(self) -> float:
        """Rate of change of the width (m/s)."""
        return float(self._qvel[self._left_dof] + self._qvel[self._right_dof])

    @property
    def goal_width(self) -> float:
        """The width the hand is moving its set-point to (m)."""
        return float(self.servo[1])

    @property
    def setpoint_settled(self) -> bool:
        """True once the commanded set-point has reached the goal width."""
        return bool(self.servo[0] == self.servo[1])

    def command(self, width: float) -> None:
        """Move towards ``width`` (m, clipped to 0 .. 0.08) at :data:`OPENING_SPEED`.

        A set-point left squeezing on the far side of the fingers restarts from the current
        width, so opening on an object releases it at once.
        """
        goal = float(np.clip(width, 0.0, MAX_OPENING))
        self.servo[1] = goal
        width_now = self.width
        if (goal - width_now) * (self.servo[0] - width_now) < 0.0:
            self.servo[0] = width_now

    def hold_current(self) -> None:
        """Make the current width the goal and set-point (stops a motion where it is)."""
        self.servo[:] = self.width

    def update(self, dt: float) -> None:
        """Advance the set-point by one period ``dt`` (s) and write the actuator control."""
        self._ctrl[self.actuator] = advance_servo(self.servo, OPENING_SPEED * dt)

    def grasped_body(self) -> str | None:
        """Name of the body both fingers' pads touch, if it is not part of the robot."""
        ncon = self._data.ncon
        if ncon == 0:
            return None
        geoms = self._data.contact.geom[:ncon]
        touched_left = _bodies_touched(self._model, geoms, self._left_pads)
        touched_right = _bodies_touched(self._model, geoms, self._right_pads)
        common = [b for b in touched_left & touched_right if not self._robot_body[b]]
        return self._model.body(min(common)).name if common else None

    def is_grasping(self) -> bool:
        """Stopped above zero width with both fingers on the same object."""
        return (
            self.width > MIN_GRASP_WIDTH
            and abs(self.width_rate) < STALL_SPEED
            and self.grasped_body() is not None
        )


def _pad_geoms(model: mujoco.MjModel, pad_geom: str) -> np.ndarray:
    return np.array([model.geom(pad_geom).id])


def _bodies_touched(model: mujoco.MjModel, geoms: np.ndarray, pads: np.ndarray) -> set[int]:
    first_is_pad = np.isin(geoms[:, 0], pads)
    second_is_pad = np.isin(geoms[:, 1], pads)
    others = np.concatenate([geoms[first_is_pad, 1], geoms[second_is_pad, 0]])
    return {int(b) for b in model.geom_bodyid[others]}


def _in_subtree(model: mujoco.MjModel, root: int) -> np.ndarray:
    inside = np.zeros(model.nbody, dtype=bool)
    inside[root] = True
    for body in range(root + 1, model.nbody):
        inside[body] = inside[model.body_parentid[body]]
    return inside
