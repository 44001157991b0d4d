"""``tf2_ros``: the transform buffer, its listener, broadcasters and TF's exceptions."""

from __future__ import annotations

from baobab.nav.ros.tf2_ros.buffer import Buffer
from baobab.nav.ros.tf2_ros.static_transform_broadcaster import StaticTransformBroadcaster
from baobab.nav.ros.tf2_ros.transform_broadcaster import TransformBroadcaster
from baobab.nav.ros.tf2_ros.transform_listener import TransformListener
from baobab.nav.ros.tf_tree import (
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TimeoutException,
    TransformException,
)

__all__ = [
    "Buffer",
    "ConnectivityException",
    "ExtrapolationException",
    "InvalidArgumentException",
    "LookupException",
    "StaticTransformBroadcaster",
    "TimeoutException",
    "TransformBroadcaster",
    "TransformException",
    "TransformListener",
]
