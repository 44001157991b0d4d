"""Nav2's behaviour server actions: Spin, BackUp, DriveOnHeading, Wait, AssistedTeleop.

Fields, types and defaults of Nav2's current release (reference/nav2_ros_facts.md §5): every
result carries ``total_elapsed_time``, every goal with motion ``disable_collision_checks``.
"""

from __future__ import annotations

from baobab.nav.errors import (
    AssistedTeleopError,
    BackUpError,
    DriveOnHeadingError,
    SpinError,
    WaitError,
)
from baobab.nav.msgs import Point
from baobab.nav.rosaction import Action, result_codes
from baobab.nav.rosmsg import Message
from baobab.nav.rostime import DurationMsg

_RESULT = {
    "total_elapsed_time": "builtin_interfaces/Duration",
    "error_code": "uint16",
    "error_msg": "string",
}
_DRIVE_GOAL = {
    "target": "geometry_msgs/Point",
    "speed": "float",
    "time_allowance": "builtin_interfaces/Duration",
    "disable_collision_checks": "boolean",
}


class Spin_Goal(Message):
    """Turn by ``target_yaw`` (rad, signed) within ``time_allowance`` (0: no limit)."""

    _type_name = "nav2_msgs/action/Spin_Goal"
    _fields_and_field_types = {
        "target_yaw": "float",
        "time_allowance": "builtin_interfaces/Duration",
        "disable_collision_checks": "boolean",
    }
    target_yaw: float
    time_allowance: DurationMsg
    disable_collision_checks: bool


@result_codes(SpinError)
class Spin_Result(Message):
    """How long the spin took and how it ended."""

    _type_name = "nav2_msgs/action/Spin_Result"
    _fields_and_field_types = dict(_RESULT)
    total_elapsed_time: DurationMsg
    error_code: int
    error_msg: str


class Spin_Feedback(Message):
    """The signed turn so far (rad)."""

    _type_name = "nav2_msgs/action/Spin_Feedback"
    _fields_and_field_types = {"angular_distance_traveled": "float"}
    angular_distance_traveled: float


class Spin(Action):
    """``nav2_msgs/action/Spin``."""

    _type_name = "nav2_msgs/action/Spin"
    Goal = Spin_Goal
    Result = Spin_Result
    Feedback = Spin_Feedback


class BackUp_Goal(Message):
    """Reverse ``target.x`` m at ``speed`` m/s."""

    _type_name = "nav2_msgs/action/BackUp_Goal"
    _fields_and_field_types = dict(_DRIVE_GOAL)
    target: Point
    speed: float
    time_allowance: DurationMsg
    disable_collision_checks: bool


@result_codes(BackUpError)
class BackUp_Result(Message):
    """How long the back-up took and how it ended."""

    _type_name = "nav2_msgs/action/BackUp_Result"
    _fields_and_field_types = dict(_RESULT)
    total_elapsed_time: DurationMsg
    error_code: int
    error_msg: str


class BackUp_Feedback(Message):
    """The straight-line distance so far (m)."""

    _type_name = "nav2_msgs/action/BackUp_Feedback"
    _fields_and_field_types = {"distance_traveled": "float"}
    distance_traveled: float


class BackUp(Action):
    """``nav2_msgs/action/BackUp``."""

    _type_name = "nav2_msgs/action/BackUp"
    Goal = BackUp_Goal
    Result = BackUp_Result
    Feedback = BackUp_Feedback


class DriveOnHeading_Goal(Message):
    """Drive straight ``target.x`` m at ``speed`` m/s."""

    _type_name = "nav2_msgs/action/DriveOnHeading_Goal"
    _fields_and_field_types = dict(_DRIVE_GOAL)
    target: Point
    speed: float
    time_allowance: DurationMsg
    disable_collision_checks: bool


@result_codes(DriveOnHeadingError)
class DriveOnHeading_Result(Message):
    """How long the drive took and how it ended."""

    _type_name = "nav2_msgs/action/DriveOnHeading_Result"
    _fields_and_field_types = dict(_RESULT)
    total_elapsed_time: DurationMsg
    error_code: int
    error_msg: str


class DriveOnHeading_Feedback(Message):
    """The straight-line distance so far (m)."""

    _type_name = "nav2_msgs/action/DriveOnHeading_Feedback"
    _fields_and_field_types = {"distance_traveled": "float"}
    distance_traveled: float


class DriveOnHeading(Action):
    """``nav2_msgs/action/DriveOnHeading``."""

    _type_name = "nav2_msgs/action/DriveOnHeading"
    Goal = DriveOnHeading_Goal
    Result = DriveOnHeading_Result
    Feedback = DriveOnHeading_Feedback


class Wait_Goal(Message):
    """Wait for ``time``."""

    _type_name = "nav2_msgs/action/Wait_Goal"
    _fields_and_field_types = {"time": "builtin_interfaces/Duration"}
    time: DurationMsg


@result_codes(WaitError)
class Wait_Result(Message):
    """How long the wait took and how it ended."""

    _type_name = "nav2_msgs/action/Wait_Result"
    _fields_and_field_types = dict(_RESULT)
    total_elapsed_time: DurationMsg
    error_code: int
    error_msg: str


class Wait_Feedback(Message):
    """The time left."""

    _type_name = "nav2_msgs/action/Wait_Feedback"
    _fields_and_field_types = {"time_left": "builtin_interfaces/Duration"}
    time_left: DurationMsg


class Wait(Action):
    """``nav2_msgs/action/Wait``."""

    _type_name = "nav2_msgs/action/Wait"
    Goal = Wait_Goal
    Result = Wait_Result
    Feedback = Wait_Feedback


class AssistedTeleop_Goal(Message):
    """Assisted teleop for ``time_allowance`` (0: no limit)."""

    _type_name = "nav2_msgs/action/AssistedTeleop_Goal"
    _fields_and_field_types = {"time_allowance": "builtin_interfaces/Duration"}
    time_allowance: DurationMsg


@result_codes(AssistedTeleopError)
class AssistedTeleop_Result(Message):
    """How long the session lasted and how it ended."""

    _type_name = "nav2_msgs/action/AssistedTeleop_Result"
    _fields_and_field_types = dict(_RESULT)
    total_elapsed_time: DurationMsg
    error_code: int
    error_msg: str


class AssistedTeleop_Feedback(Message):
    """How long the session has run."""

    _type_name = "nav2_msgs/action/AssistedTeleop_Feedback"
    _fields_and_field_types = {"current_teleop_duration": "builtin_interfaces/Duration"}
    current_teleop_duration: DurationMsg


class AssistedTeleop(Action):
    """``nav2_msgs/action/AssistedTeleop``."""

    _type_name = "nav2_msgs/action/AssistedTeleop"
    Goal = AssistedTeleop_Goal
    Result = AssistedTeleop_Result
    Feedback = AssistedTeleop_Feedback
