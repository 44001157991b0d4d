"""Errors raised for mistakes in what users ask of the Panda, and the codes of failed arm tasks."""

from __future__ import annotations

import enum

from baobab.sim.errors import BaobabError


class TrajectoryGoalError(BaobabError, ValueError):
    """A trajectory goal ``[T, x, y, z, qx, qy, qz, qw]`` that cannot be executed."""


class PandaSceneError(BaobabError, ValueError):
    """A scene request that cannot be built, such as a cube off the table."""


class GripperCommandError(BaobabError, ValueError):
    """A gripper command other than ``open`` or ``close``."""


class PoseError(BaobabError, ValueError):
    """A pose with the wrong number of values or a quaternion that cannot be normalised."""


class GainsError(BaobabError, ValueError):
    """Impedance gains that are negative, non-finite or out of range."""


class PandaModelError(BaobabError, ValueError):
    """A robot model the Panda's controller cannot drive (e.g. a TCP moved by the fingers)."""


class ArmErrorCode(enum.IntEnum):
    """Why an arm task failed (``TaskOutcome.error_code``)."""

    NONE = 0
    GOAL_UNREACHABLE = 1
    TRACKING_LOST = 2
    GOAL_NOT_REACHED = 3
    GRASP_FAILED = 4
    GRIPPER_BLOCKED = 5
    GRIPPER_TIMEOUT = 6
