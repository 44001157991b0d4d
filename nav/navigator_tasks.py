"""The Simple Commander calls that start a task: navigation, path following, behaviours, teleop.

Each call hands a goal to the navigation server through :meth:`NavigatorTracking._send`,
which turns a goal the navigator refuses into a rejected send (None, as Nav2 Rolling returns)
and otherwise starts tracking the task (see :mod:`baobab.nav.navigator` for how baobab differs
from Nav2).
"""

from __future__ import annotations

import enum

from baobab.nav import msgs
from baobab.nav.errors import (
    FollowPathError,
    GoalRejectedError,
    NavigateThroughPosesError,
    NavigateToPoseError,
)
from baobab.nav.navigator_feedback import RunningTask
from baobab.nav.navigator_messages import (
    goal_pose,
    goal_poses,
    known_plugin,
    path_from_message,
)
from baobab.nav.navigator_tracking import NavigatorTracking
from baobab.nav.ros.std_msgs.msg import Empty
from baobab.sim.tasks import TaskHandle


class NavigatorTasks(NavigatorTracking):
    """The task launchers of :class:`~baobab.nav.navigator.BasicNavigator` (Nav2's names).

    As Nav2's assisted teleop does, the navigator listens on ``cmd_vel_teleop`` (``Twist`` or
    ``TwistStamped``) and ``preempt_teleop`` (``Empty``): a script's node that publishes there
    drives :meth:`assistedTeleop` (:meth:`publishTeleop` and :meth:`preemptTeleop` do the
    same without a publisher).
    """

    def _setup(self) -> None:
        super()._setup()
        for kind in (msgs.Twist, msgs.TwistStamped):
            self.create_subscription(kind, "cmd_vel_teleop", self.publishTeleop, 10, _internal=True)
        self.create_subscription(
            Empty, "preempt_teleop", lambda _: self.preemptTeleop(), 10, _internal=True
        )

    def goToPose(self, pose: msgs.PoseStamped, behavior_tree: str = "") -> RunningTask | None:
        """Navigate to ``pose`` (map frame), replanning at 1 Hz with Nav2's recoveries."""

        def submit() -> TaskHandle:
            target = goal_pose(pose)
            self.info(f"Navigating to goal: {pose.pose.position.x} {pose.pose.position.y}...")
            _default_tree_only(behavior_tree, NavigateToPoseError.FAILED_TO_LOAD_BEHAVIOR_TREE)
            return self._server.navigate_to_pose(target)

        return self._send(RunningTask.NAVIGATE_TO_POSE, submit)

    def goThroughPoses(
        self, poses: list[msgs.PoseStamped] | msgs.Goals, behavior_tree: str = ""
    ) -> RunningTask | None:
        """Navigate through ``poses`` in order without stopping (a list or ``nav_msgs/Goals``)."""
        self.info(f"Navigating with {_count(poses)} goals....")

        def submit() -> TaskHandle:
            _default_tree_only(
                behavior_tree, NavigateThroughPosesError.FAILED_TO_LOAD_BEHAVIOR_TREE
            )
            goals = goal_poses(poses)
            if not goals:
                raise GoalRejectedError("no poses given")
            return self._server.navigate_through_poses(goals)

        return self._send(RunningTask.NAVIGATE_THROUGH_POSES, submit)

    def followWaypoints(
        self, poses: list[msgs.PoseStamped], number_of_loops: int = 0, goal_index: int = 0
    ) -> RunningTask | None:
        """Navigate to each pose in turn; ``number_of_loops`` extra passes from ``goal_index``."""
        self.info(f"Following {_count(poses)} goals....")
        return self._send(
            RunningTask.FOLLOW_WAYPOINTS,
            lambda: self._server.follow_waypoints(
                goal_poses(poses),
                number_of_loops=int(number_of_loops),
                goal_index=int(goal_index),
            ),
        )

    def followPath(
        self,
        path: msgs.Path,
        controller_id: str = "",
        goal_checker_id: str = "",
        progress_checker_id: str = "",
        path_handler_id: str = "",
    ) -> RunningTask | None:
        """Track ``path`` (``nav_msgs/Path`` in map) with the controller alone."""
        self.info("Executing path...")

        def submit() -> TaskHandle:
            known_plugin("controller_id", controller_id, FollowPathError.INVALID_CONTROLLER)
            known_plugin("goal_checker_id", goal_checker_id, FollowPathError.INVALID_CONTROLLER)
            known_plugin(
                "progress_checker_id", progress_checker_id, FollowPathError.INVALID_CONTROLLER
            )
            known_plugin("path_handler_id", path_handler_id, FollowPathError.INVALID_CONTROLLER)
            return self._server.follow_path(path_from_message(path))

        return self._send(RunningTask.FOLLOW_PATH, submit)

    def spin(
        self,
        spin_dist: float = 1.57,
        time_allowance: float = 10,
        disable_collision_checks: bool = False,
    ) -> RunningTask | None:
        """Turn in place by ``spin_dist`` rad (the sign is the direction)."""
        self.info(f"Spinning to angle {spin_dist}....")
        return self._send(
            RunningTask.SPIN,
            lambda: self._server.spin(
                float(spin_dist),
                float(time_allowance),
                disable_collision_checks=bool(disable_collision_checks),
            ),
        )

    def backup(
        self,
        backup_dist: float = 0.15,
        backup_speed: float = 0.025,
        time_allowance: float = 10,
        disable_collision_checks: bool = False,
    ) -> RunningTask | None:
        """Reverse ``backup_dist`` m at ``backup_speed`` m/s (Nav2 floors the speed at 0.10)."""
        self.info(f"Backing up {backup_dist} m at {backup_speed} m/s....")
        return self._send(
            RunningTask.BACKUP,
            lambda: self._server.back_up(
                float(backup_dist),
                float(backup_speed),
                float(time_allowance),
                disable_collision_checks=bool(disable_collision_checks),
            ),
        )

    backUp = backup

    def driveOnHeading(
        self,
        dist: float = 0.15,
        speed: float = 0.025,
        time_allowance: float = 10,
        disable_collision_checks: bool = False,
    ) -> RunningTask | None:
        """Drive straight ``dist`` m at ``speed`` m/s (same signs; negative drives backwards)."""
        self.info(f"Drive {dist} m on heading at {speed} m/s....")
        return self._send(
            RunningTask.DRIVE_ON_HEADING,
            lambda: self._server.drive_on_heading(
                float(dist),
                float(speed),
                float(time_allowance),
                disable_collision_checks=bool(disable_collision_checks),
            ),
        )

    def assistedTeleop(self, time_allowance: float = 30) -> RunningTask | None:
        """Drive by :meth:`publishTeleop` twists, slowed or stopped before collisions.

        Ends SUCCEEDED on :meth:`preemptTeleop`, FAILED (TIMEOUT) after ``time_allowance`` s of
        sim time (0: no limit).
        """
        self.info("Running 'assisted_teleop'....")
        return self._send(
            RunningTask.ASSISTED_TELEOP,
            lambda: self._server.assisted_teleop(float(time_allowance)),
        )

    def publishTeleop(self, twist: msgs.Twist | msgs.TwistStamped) -> None:
        """Publish a teleop twist, as on Nav2's ``cmd_vel_teleop`` topic (held until the next).

        Assisted teleop passes ``linear.x`` (m/s) and ``angular.z`` (rad/s) on, scaled down
        before collisions; the other components mean nothing to a differential drive.

        Raises:
            ValueError: a non-finite component.
        """
        plain = twist.twist if isinstance(twist, msgs.TwistStamped) else twist
        self._live_server().teleop_command(float(plain.linear.x), float(plain.angular.z))

    def preemptTeleop(self) -> None:
        """End a running assisted teleop with success, as Nav2's ``preempt_teleop`` topic does."""
        self._live_server().preempt_teleop()


def _count(poses: object) -> int | str:
    items = poses.goals if isinstance(poses, msgs.Goals) else poses
    return len(items) if isinstance(items, list | tuple) else "?"


def _default_tree_only(behavior_tree: str, code: enum.IntEnum) -> None:
    if behavior_tree:
        raise GoalRejectedError(
            f"behavior tree '{behavior_tree}' cannot be loaded: baobab runs Nav2's default "
            "navigation tree only (pass '')",
            code,
        )
