"""Mobile-base nodes: Nav2-style navigation tasks and the tutorial base controllers.

Defaults follow Nav2 (reference/nav2.md): spin 1.57 rad in 10 s; drive_on_heading 0.15 m at
0.025 m/s in 10 s (the BT node defaults); back_up 0.30 m at 0.15 m/s in 10 s (the recovery of
Nav2's default tree); assisted_teleop 30 s; follow_waypoints stops on a missed waypoint (the
waypoint follower's source default). Goals are checked against the world before any physics:
on the floor and clear of obstacles by the robot's footprint radius.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Annotated, Literal

from pydantic import Field, ValidationInfo, model_validator

from baobab.behaviours.ports import BASE_CONTROLLERS, NAVIGATION
from baobab.behaviours.poses import GoalPose, MissionScope, Pose, PoseRef
from baobab.behaviours.registry import (
    BehaviourType,
    BuildRequest,
    NodeKind,
    NodeParams,
)
from baobab.sim.yaml_source import FieldValueError

if TYPE_CHECKING:  # imported by the factories, when a tree is built (validation needs none)
    import py_trees


Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]
TimeAllowance = Annotated[
    float, Field(gt=0, allow_inf_nan=False, description="s of sim time before the task fails")
]


def _where(pose: Pose) -> str:
    return pose.location or f"({pose.x:.2f}, {pose.y:.2f})"


class NavigateToPoseParams(NodeParams):
    """Plan and drive to ``goal``."""

    goal: GoalPose = Field(description="location name or pose")

    def summary(self) -> str:
        """The goal."""
        return _where(self.goal)


class NavigateThroughPosesParams(NodeParams):
    """Drive through ``poses`` in order without stopping at the intermediate ones."""

    poses: list[GoalPose] = Field(min_length=1, description="location names or poses")

    def summary(self) -> str:
        """The poses."""
        return " -> ".join(_where(pose) for pose in self.poses)


class FollowWaypointsParams(NodeParams):
    """Navigate to each waypoint in turn and pause there."""

    waypoints: list[GoalPose] = Field(min_length=1, description="location names or poses")
    wait_at_waypoint: NonNegative | None = Field(
        default=None,
        description="pause at each waypoint, s; default: the Nav2 parameter file's, else 0",
    )
    stop_on_failure: bool | None = Field(
        default=None,
        description="abort at the first missed waypoint; default: the Nav2 parameter file's, "
        "else true",
    )

    def summary(self) -> str:
        """The waypoints."""
        return " -> ".join(_where(pose) for pose in self.waypoints)


class FollowPathParams(NodeParams):
    """Track a given path with the local controller, without global planning."""

    path: list[GoalPose] = Field(min_length=2, description="the path's poses, in order")

    def summary(self) -> str:
        """Number of poses."""
        return f"{len(self.path)} poses"


class SpinParams(NodeParams):
    """Turn in place by ``angle`` rad (or ``angle_deg``); positive is counter-clockwise."""

    angle: float | None = Field(default=None, allow_inf_nan=False, description="rad, default 1.57")
    angle_deg: float | None = Field(default=None, allow_inf_nan=False, description="deg")
    time_allowance: TimeAllowance = 10.0

    @model_validator(mode="after")
    def _one_angle(self) -> SpinParams:
        if self.angle is not None and self.angle_deg is not None:
            raise FieldValueError(("angle_deg",), "give either angle (rad) or angle_deg, not both")
        return self

    @property
    def radians(self) -> float:
        """The signed turn (rad)."""
        if self.angle_deg is not None:
            return math.radians(self.angle_deg)
        return 1.57 if self.angle is None else self.angle

    def summary(self) -> str:
        """``1.57 rad``."""
        return f"{self.radians:.2f} rad"


class _StraightParams(NodeParams):
    distance: Positive
    speed: Positive
    time_allowance: TimeAllowance = 10.0

    @model_validator(mode="after")
    def _feasible(self, info: ValidationInfo) -> _StraightParams:
        robot = MissionScope.of(info).robot
        if robot.max_linear_speed and self.speed > robot.max_linear_speed:
            raise FieldValueError(
                ("speed",),
                f"speed {self.speed:g} m/s exceeds {robot.name}'s limit "
                f"{robot.max_linear_speed:g} m/s",
            )
        needed = self.distance / self.speed
        if needed > self.time_allowance:
            raise FieldValueError(
                ("time_allowance",),
                f"{self.distance:g} m at {self.speed:g} m/s takes {needed:g} s, more than the "
                f"time_allowance {self.time_allowance:g} s",
            )
        return self

    def summary(self) -> str:
        """``0.30 m``."""
        return f"{self.distance:g} m"


class BackUpParams(_StraightParams):
    """Reverse ``distance`` m at ``speed`` m/s."""

    distance: Positive = Field(default=0.30, description="m, reversed")
    speed: Positive = Field(default=0.15, description="m/s")


class DriveOnHeadingParams(_StraightParams):
    """Drive straight ahead ``distance`` m at ``speed`` m/s."""

    distance: Positive = Field(default=0.15, description="m, ahead")
    speed: Positive = Field(default=0.025, description="m/s")


class ClearCostmapsParams(NodeParams):
    """Clear the local, global or all costmaps (instant)."""

    which: Literal["local", "global", "all"] = "all"

    def summary(self) -> str:
        """Which costmaps."""
        return self.which


class AssistedTeleopParams(NodeParams):
    """Pass teleop commands through the collision projection for ``time_allowance`` s."""

    time_allowance: TimeAllowance = 30.0

    def summary(self) -> str:
        """``30 s``."""
        return f"{self.time_allowance:g} s"


class IsAtParams(NodeParams):
    """Succeed when the robot is within ``tolerance`` m of ``location``, else fail."""

    location: PoseRef = Field(description="location name or pose")
    tolerance: Positive = Field(default=0.25, description="m")
    yaw_tolerance: Positive | None = Field(default=None, description="rad; default: any heading")

    def summary(self) -> str:
        """The location."""
        return _where(self.location)


def _navigate_to_pose(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    goal = request.params_as(NavigateToPoseParams).goal.pose2d()
    return request.goal_task(lambda caps: caps.navigation_port().navigate_to_pose(goal))


def _navigate_through_poses(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    goals = [pose.pose2d() for pose in request.params_as(NavigateThroughPosesParams).poses]
    return request.goal_task(lambda caps: caps.navigation_port().navigate_through_poses(goals))


def _follow_waypoints(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    params = request.params_as(FollowWaypointsParams)
    waypoints = [pose.pose2d() for pose in params.waypoints]
    wait, stop = params.wait_at_waypoint, params.stop_on_failure
    return request.goal_task(
        lambda caps: caps.navigation_port().follow_waypoints(waypoints, wait, stop)
    )


def _follow_path(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    path = [pose.pose2d() for pose in request.params_as(FollowPathParams).path]
    return request.goal_task(lambda caps: caps.navigation_port().follow_path(path))


def _spin(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    p = request.params_as(SpinParams)
    return request.goal_task(lambda caps: caps.navigation_port().spin(p.radians, p.time_allowance))


def _back_up(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    p = request.params_as(BackUpParams)
    return request.goal_task(
        lambda caps: caps.navigation_port().back_up(p.distance, p.speed, p.time_allowance)
    )


def _drive_on_heading(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    p = request.params_as(DriveOnHeadingParams)
    return request.goal_task(
        lambda caps: caps.navigation_port().drive_on_heading(p.distance, p.speed, p.time_allowance)
    )


def _clear_costmaps(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    from baobab.behaviours.actions import InstantCall

    which = request.params_as(ClearCostmapsParams).which
    caps = request.capabilities
    return InstantCall(request.name, lambda: caps.navigation_port().clear_costmaps(which))


def _assisted_teleop(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    allowance = request.params_as(AssistedTeleopParams).time_allowance
    return request.goal_task(lambda caps: caps.navigation_port().assisted_teleop(allowance))


def _is_at(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    from baobab.behaviours.conditions import IsAt

    params = request.params_as(IsAtParams)
    caps = request.capabilities
    return IsAt(
        request.name,
        params.location.pose2d(),
        params.tolerance,
        params.yaw_tolerance,
        lambda: caps.navigation_port().robot_pose(),
    )


def _go_to_goal(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    goal = request.params_as(NavigateToPoseParams).goal.pose2d()
    return request.goal_task(lambda caps: caps.base_controller_port().go_to_goal(goal))


def _bug2(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    goal = request.params_as(NavigateToPoseParams).goal.pose2d()
    return request.goal_task(lambda caps: caps.base_controller_port().bug2(goal))


class GoToGoalParams(NavigateToPoseParams):
    """Drive straight at ``goal`` with the proportional go-to-goal controller."""


class Bug2Params(NavigateToPoseParams):
    """Bug2 to ``goal``: follow the M-line, walls on the left when blocked."""


NODE_TYPES = (
    BehaviourType(
        "navigate_to_pose",
        NodeKind.ACTION,
        NavigateToPoseParams,
        "plan and drive to a goal pose",
        _navigate_to_pose,
        capability=NAVIGATION,
        shorthand="goal",
        pose_shorthand=True,
    ),
    BehaviourType(
        "navigate_through_poses",
        NodeKind.ACTION,
        NavigateThroughPosesParams,
        "drive through poses without stopping",
        _navigate_through_poses,
        capability=NAVIGATION,
        shorthand="poses",
    ),
    BehaviourType(
        "follow_waypoints",
        NodeKind.ACTION,
        FollowWaypointsParams,
        "visit waypoints in turn, pausing at each",
        _follow_waypoints,
        capability=NAVIGATION,
        shorthand="waypoints",
    ),
    BehaviourType(
        "follow_path",
        NodeKind.ACTION,
        FollowPathParams,
        "track a given path without planning",
        _follow_path,
        capability=NAVIGATION,
        shorthand="path",
    ),
    BehaviourType(
        "spin",
        NodeKind.ACTION,
        SpinParams,
        "turn in place by an angle",
        _spin,
        capability=NAVIGATION,
        shorthand="angle",
    ),
    BehaviourType(
        "back_up",
        NodeKind.ACTION,
        BackUpParams,
        "reverse a distance",
        _back_up,
        capability=NAVIGATION,
        shorthand="distance",
    ),
    BehaviourType(
        "drive_on_heading",
        NodeKind.ACTION,
        DriveOnHeadingParams,
        "drive straight ahead a distance",
        _drive_on_heading,
        capability=NAVIGATION,
        shorthand="distance",
    ),
    BehaviourType(
        "clear_costmaps",
        NodeKind.ACTION,
        ClearCostmapsParams,
        "clear local, global or all costmaps",
        _clear_costmaps,
        capability=NAVIGATION,
        shorthand="which",
    ),
    BehaviourType(
        "assisted_teleop",
        NodeKind.ACTION,
        AssistedTeleopParams,
        "teleop through the collision projection",
        _assisted_teleop,
        capability=NAVIGATION,
        shorthand="time_allowance",
    ),
    BehaviourType(
        "go_to_goal",
        NodeKind.ACTION,
        GoToGoalParams,
        "tutorial go-to-goal controller to a goal",
        _go_to_goal,
        capability=BASE_CONTROLLERS,
        shorthand="goal",
        pose_shorthand=True,
    ),
    BehaviourType(
        "bug2",
        NodeKind.ACTION,
        Bug2Params,
        "Bug2 wall-following controller to a goal",
        _bug2,
        capability=BASE_CONTROLLERS,
        shorthand="goal",
        pose_shorthand=True,
    ),
    BehaviourType(
        "is_at",
        NodeKind.CONDITION,
        IsAtParams,
        "succeed when the robot is within tolerance of a location",
        _is_at,
        capability=NAVIGATION,
        shorthand="location",
        pose_shorthand=True,
    ),
)
"""The navigation and base-controller node types."""
