"""``nav2_msgs.action``: every Nav2 action type, as rclpy's generated classes are shaped.

``NavigateToPose.Goal()``, ``NavigateToPose.Feedback``, ``NavigateToPose.Result.UNKNOWN``:
each action is a class holding its Goal, Result and Feedback message classes (named
``NavigateToPose_Goal`` and so on), with the fields, defaults and codes of Nav2's current
release.
"""

from __future__ import annotations

from baobab.nav.ros.nav2_msgs.action._behaviors import (
    AssistedTeleop,
    BackUp,
    DriveOnHeading,
    Spin,
    Wait,
)
from baobab.nav.ros.nav2_msgs.action._navigation import (
    ComputePathThroughPoses,
    ComputePathToPose,
    FollowGPSWaypoints,
    FollowPath,
    FollowWaypoints,
    NavigateThroughPoses,
    NavigateToPose,
    SmoothPath,
)
from baobab.nav.ros.nav2_msgs.action._servers import (
    ComputeAndTrackRoute,
    ComputeRoute,
    DockRobot,
    FollowObject,
    UndockRobot,
)

__all__ = [
    "AssistedTeleop",
    "BackUp",
    "ComputeAndTrackRoute",
    "ComputePathThroughPoses",
    "ComputePathToPose",
    "ComputeRoute",
    "DockRobot",
    "DriveOnHeading",
    "FollowGPSWaypoints",
    "FollowObject",
    "FollowPath",
    "FollowWaypoints",
    "NavigateThroughPoses",
    "NavigateToPose",
    "SmoothPath",
    "Spin",
    "UndockRobot",
    "Wait",
]
