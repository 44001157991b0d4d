"""``geometry_msgs.msg``: points, quaternions, poses and twists."""

from __future__ import annotations

from baobab.nav.msgs import (
    Point,
    Pose,
    PoseStamped,
    PoseWithCovariance,
    PoseWithCovarianceStamped,
    Quaternion,
    Twist,
    TwistStamped,
    Vector3,
)

__all__ = [
    "Point",
    "Pose",
    "PoseStamped",
    "PoseWithCovariance",
    "PoseWithCovarianceStamped",
    "Quaternion",
    "Twist",
    "TwistStamped",
    "Vector3",
]
