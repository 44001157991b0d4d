"""Conversions between the navigator's ROS-shaped messages and the navigation server's types.

Goals arrive as ``PoseStamped`` in the ``map`` frame (an empty ``frame_id`` is taken as
``map``: the simulation localises perfectly, so map is the only frame a goal can be given in).
Paths go both ways between ``nav_msgs/Path`` and :class:`baobab.nav.path.Path`; costmaps leave
as ``nav2_msgs/Costmap`` (what Nav2's ``getGlobalCostmap`` returns). Plugin ids in a request
must be those of the one plugin each server has (:data:`PLUGIN_IDS`).
"""

from __future__ import annotations

from array import array
from collections.abc import Iterable
from enum import IntEnum

import numpy as np

from baobab.nav import msgs
from baobab.nav.costmap import Costmap2D
from baobab.nav.errors import GoalRejectedError
from baobab.nav.path import Path
from baobab.nav.rosmsg import defer_field, deferred_source
from baobab.sim.world import Pose2D

MAP_FRAME = "map"
"""The one frame goals may be given in."""
PLUGIN_IDS = {
    "planner_id": ("GridBased",),
    "smoother_id": ("simple_smoother",),
    "controller_id": ("FollowPath",),
    "goal_checker_id": ("general_goal_checker", "goal_checker"),
    "progress_checker_id": ("progress_checker",),
    "path_handler_id": ("PathHandler",),
}
"""The plugin ids the one configured plugin of each server answers to ('' = the default)."""


def goal_pose(pose: msgs.PoseStamped, what: str = "goal") -> Pose2D:
    """The map-frame planar pose of a goal message.

    Raises:
        TypeError: ``pose`` is not a ``PoseStamped`` (a programming error, as rosidl's
            type check raises for a wrong field type).
        GoalRejectedError: a frame other than ``map``, a non-finite position or a zero or
            non-finite quaternion.
    """
    _check_map_frame(pose, what)
    try:
        return msgs.to_pose2d(pose)
    except msgs.MessageValueError as exc:
        raise GoalRejectedError(f"{what} is invalid: {exc}") from None


def _check_map_frame(pose: msgs.PoseStamped, what: str) -> None:
    if not isinstance(pose, msgs.PoseStamped):
        raise TypeError(f"{what} must be a geometry_msgs PoseStamped, not {type(pose).__name__}")
    frame = pose.header.frame_id
    if frame not in (MAP_FRAME, ""):
        raise GoalRejectedError(
            f"{what} is in frame '{frame}', which cannot be transformed: goals must be in "
            f"'{MAP_FRAME}'"
        )


def known_plugin(parameter: str, value: str, code: IntEnum | None) -> None:
    """Refuse a plugin id (``planner_id``, ``controller_id``, ...) the server does not have.

    Raises:
        GoalRejectedError: ``value`` is neither empty (the default) nor the plugin's id.
    """
    if value and value not in PLUGIN_IDS[parameter]:
        known = " or ".join(f"'{name}'" for name in PLUGIN_IDS[parameter])
        raise GoalRejectedError(f"unknown {parameter} '{value}': the server has {known}", code)


def goal_poses(poses: Iterable[msgs.PoseStamped] | msgs.Goals) -> list[Pose2D]:
    """The planar poses of a goal list: a list of ``PoseStamped`` or a ``nav_msgs/Goals``.

    Raises:
        TypeError: a value that is neither.
        GoalRejectedError: as :func:`goal_pose`, for any of the poses.
    """
    items = poses.goals if isinstance(poses, msgs.Goals) else poses
    if isinstance(items, msgs.PoseStamped) or not isinstance(items, Iterable):
        raise TypeError(
            f"poses must be a list of PoseStamped or a nav_msgs Goals, not {type(poses).__name__}"
        )
    return [goal_pose(pose, f"pose {index}") for index, pose in enumerate(items)]


def path_message(path: Path, stamp: msgs.TimeMsg) -> msgs.Path:
    """The ``nav_msgs/Path`` of a planner path, every pose stamped ``stamp``.

    The pose messages are made on the first read of ``poses``: a path handed straight on to
    ``followPath`` or ``smoothPath`` is never converted (:func:`path_from_message` takes the
    planner path back).
    """
    message = msgs.Path(header=msgs.Header(stamp=_copy(stamp), frame_id=path.frame_id))
    stamp = _copy(stamp)
    defer_field(
        message, "poses", lambda: msgs.stamped_poses(path.poses, path.frame_id, stamp), path
    )
    return message


def path_from_message(path: msgs.Path | Path) -> Path:
    """A planner path from a ``nav_msgs/Path`` (a planner path passes through).

    Raises:
        TypeError: a value that is neither.
        GoalRejectedError: a pose outside the ``map`` frame or with an invalid orientation.
    """
    if isinstance(path, Path):
        return path
    if not isinstance(path, msgs.Path):
        raise TypeError(f"path must be a nav_msgs Path, not {type(path).__name__}")
    unread = deferred_source(path, "poses")
    if isinstance(unread, Path):
        return unread  # poses never read, so never changed: the planner path they stand for
    rows = []
    for index, pose in enumerate(path.poses):
        _check_map_frame(pose, f"path pose {index}")
        position, orientation = pose.pose.position, pose.pose.orientation
        rows.append(
            (position.x, position.y, orientation.x, orientation.y, orientation.z, orientation.w)
        )
    table = np.array(rows, dtype=float).reshape(-1, 6)
    quaternions = table[:, 2:]
    invalid = ~np.isfinite(table).all(axis=1) | (np.linalg.norm(quaternions, axis=1) < 1e-9)
    if invalid.any():
        first = int(np.argmax(invalid))
        goal_pose(path.poses[first], f"path pose {first}")  # raises, saying what is wrong
    return Path(np.column_stack([table[:, :2], msgs.yaws_from_quaternions(quaternions)]))


def costmap_message(costmap: Costmap2D, stamp: msgs.TimeMsg, layer: str) -> msgs.Costmap:
    """The ``nav2_msgs/Costmap`` of a costmap: row-major costs, ``data[i + size_x * j]``."""
    return msgs.Costmap(
        header=msgs.Header(stamp=_copy(stamp), frame_id=MAP_FRAME),
        metadata=msgs.CostmapMetaData(
            map_load_time=_copy(stamp),
            update_time=_copy(stamp),
            layer=layer,
            resolution=costmap.resolution,
            size_x=costmap.size_x,
            size_y=costmap.size_y,
            origin=msgs.Pose(position=msgs.Point(x=costmap.origin_x, y=costmap.origin_y)),
        ),
        data=array("B", np.ascontiguousarray(costmap.data, dtype=np.uint8).tobytes()),
    )


def _copy(stamp: msgs.TimeMsg) -> msgs.TimeMsg:
    return msgs.TimeMsg(sec=stamp.sec, nanosec=stamp.nanosec)
