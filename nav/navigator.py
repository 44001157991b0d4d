"""``BasicNavigator``: Nav2's Simple Commander API over baobab's simulated navigation stack.

A Nav2 script drives a robot through ``nav2_simple_commander.robot_navigator.BasicNavigator``:
send a goal, poll ``isTaskComplete()``, read ``getFeedback()``, then ``getResult()``. Here the
same calls drive the :class:`~baobab.nav.server.NavigationServer` of a TurtleBot3 in a MuJoCo
world that the navigator builds for itself. Method names, parameters, defaults, feedback field
names and message types are Nav2's (reference/nav2.md §1-§2; Kilted semantics where distros
differ), old names included (``isNavComplete``, ``cancelNav``, ``NavigationResult``).

Where baobab differs from Nav2, on purpose:

* **Time.** Nothing runs between calls: ``isTaskComplete()`` (and ``rclpy.spin_once``)
  advance the simulation by at most 0.1 s of sim time — the bound Nav2's own poll spins for —
  and return early when the task ends. With ``realtime=True`` each slice is paced to the wall
  clock. ``get_clock()`` and every ROS clock in the script read sim time, continuous across
  :meth:`BasicNavigator.changeMap`.
* **Every wait is bounded.** ``waitUntilNav2Active()`` and ``lifecycleStartup()`` return at
  once (the simulated stack is always active); ``isTaskComplete()`` returns True when there is
  no task, or when the last send was rejected — Kilted returns False after a rejection, so a
  ``while not isTaskComplete()`` loop would spin forever; here it ends.
* **Rejection.** A goal the navigator cannot pass to the server — a pose outside the ``map``
  frame, a zero quaternion, an empty pose list, a custom behaviour tree or plugin id — is
  rejected at once: the send returns ``False`` (Humble's value; accepted sends return Kilted's
  ``RunningTask``), ``isTaskComplete()`` is True, ``getResult()`` is FAILED and
  ``getTaskError()`` gives the action's UNKNOWN code (or a more precise one) with the reason.
  A rejected send also cancels the task that was running, so the robot is never left driving a
  goal the script no longer tracks. Goals the server accepts but cannot do (a goal inside a
  table, a back-up speed of the wrong sign) end FAILED with Nav2's error code instead.
* **Preemption.** A new goal of the same kind replaces the running one in place (Nav2's
  behaviour); a goal of another kind cancels the running one first (Nav2 asks the caller to).
* **No hijacking.** ``getPath``, ``getPathThroughPoses`` and ``smoothPath`` answer at once and
  leave the running task alone (Nav2 routes them through the task's shared result future).
* **State.** ``getResult()`` is UNKNOWN while a task runs (Nav2 would return the previous
  task's status); feedback and the task error are reset by each send, as in Rolling.
* **Localisation is perfect.** ``setInitialPose()`` teleports the simulated robot.
* **Waypoints.** ``followWaypoints`` runs with ``stop_on_failure`` false (nav2_bringup's
  setting): a missed waypoint is recorded and the robot goes on. The missed ones appear in the
  feedback (``missed_waypoints``) and in ``result_future.result().result.missed_waypoints``.

``BasicNavigator`` is an rclpy ``Node`` (the shim's), so ``get_logger()``, ``get_clock()`` and
``rclpy.shutdown()`` behave as in ROS; the logger writes ROS console lines to standard error.
"""

from __future__ import annotations

import copy
import enum
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path as FilePath
from typing import Literal

from baobab.nav import msgs
from baobab.nav.defaults import NavigatorDefaults, navigator_defaults
from baobab.nav.errors import (
    AssistedTeleopError,
    BackUpError,
    ComputePathThroughPosesError,
    ComputePathToPoseError,
    DriveOnHeadingError,
    FollowPathError,
    FollowWaypointsError,
    NavigateThroughPosesError,
    NavigateToPoseError,
    NavigationError,
    SmoothPathError,
    SpinError,
)
from baobab.nav.navigator_feedback import Feedback, ResultFuture, RunningTask, feedback_message
from baobab.nav.navigator_messages import (
    GoalRejectedError,
    costmap_message,
    goal_pose,
    goal_poses,
    path_from_message,
    path_message,
)
from baobab.nav.navigator_robot import (
    NavigatorSetupError,
    SimulatedRobot,
    build_simulated_robot,
    check_free,
    pose_is_free,
)
from baobab.nav.ros.rclpy.node import Node
from baobab.nav.rostime import Clock, ClockType, set_sim_time_source
from baobab.nav.server import NavigationServer, build_navigation
from baobab.sim.errors import BaobabError, WorldError
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus
from baobab.sim.viewer import RealTimePacer
from baobab.sim.world import Pose2D, World, bundled_world_names, load_world

__all__ = ["BasicNavigator", "NavigationResult", "RunningTask", "TaskResult"]

POLL_HORIZON = 0.1
"""Sim seconds one ``isTaskComplete()`` advances at most (Nav2 spins 0.1 s per poll)."""
POLL_SLICE = 0.01
"""Sim seconds between checks whether the task ended (and between real-time pacing waits)."""


class TaskResult(enum.Enum):
    """How the last task ended (Nav2's ``TaskResult``)."""

    UNKNOWN = 0
    SUCCEEDED = 1
    CANCELED = 2
    FAILED = 3


NavigationResult = TaskResult
"""The pre-Galactic name of :class:`TaskResult` (the same class, so comparisons mix freely)."""


class LoadMapResult(enum.IntEnum):
    """``nav2_msgs/srv/LoadMap`` result codes, what :meth:`BasicNavigator.changeMap` reports."""

    RESULT_SUCCESS = 0
    RESULT_MAP_DOES_NOT_EXIST = 1
    RESULT_INVALID_MAP_DATA = 2
    RESULT_INVALID_MAP_METADATA = 3
    RESULT_UNDEFINED_FAILURE = 255


_UNKNOWN_CODES: dict[RunningTask, enum.IntEnum] = {
    RunningTask.NAVIGATE_TO_POSE: NavigateToPoseError.UNKNOWN,
    RunningTask.NAVIGATE_THROUGH_POSES: NavigateThroughPosesError.UNKNOWN,
    RunningTask.FOLLOW_PATH: FollowPathError.UNKNOWN,
    RunningTask.FOLLOW_WAYPOINTS: FollowWaypointsError.UNKNOWN,
    RunningTask.SPIN: SpinError.UNKNOWN,
    RunningTask.BACKUP: BackUpError.UNKNOWN,
    RunningTask.DRIVE_ON_HEADING: DriveOnHeadingError.UNKNOWN,
    RunningTask.ASSISTED_TELEOP: AssistedTeleopError.UNKNOWN,
}
_RESULTS = {
    TaskStatus.SUCCEEDED: TaskResult.SUCCEEDED,
    TaskStatus.CANCELED: TaskResult.CANCELED,
    TaskStatus.FAILED: TaskResult.FAILED,
}
_PLUGIN_IDS = {
    "planner_id": ("GridBased",),
    "smoother_id": ("simple_smoother",),
    "controller_id": ("FollowPath",),
    "goal_checker_id": ("general_goal_checker", "goal_checker"),
    "progress_checker_id": ("progress_checker",),
    "path_handler_id": ("PathHandler",),
}
"""The plugin ids the one configured plugin of each server answers to ('' = the default)."""


@dataclass
class _Goal:
    """The task the navigator tracks: a server handle, or the outcome of a rejected send."""

    kind: RunningTask
    handle: TaskHandle | None
    rejection: TaskOutcome | None = None

    def outcome(self) -> TaskOutcome | None:
        return self.rejection if self.handle is None else self.handle.outcome


class BasicNavigator(Node):
    """Nav2's Simple Commander over a simulated robot (see the module docstring).

    Args:
        node_name: the node's name (and its logger's).
        namespace: the node's namespace.
        world: a bundled world name, a world YAML path or a loaded ``World``.
        robot: the robot model; ``"turtlebot3"`` (a Burger) is the one there is.
        start: the robot's map-frame start pose; the world's default spawn when None.
        seed: seed of the simulation's random generator.
        realtime: pace the simulation to the wall clock (for watching a run).

    ``world``, ``start``, ``seed`` and ``realtime`` left at None take the values of
    :func:`~baobab.nav.defaults.navigator_defaults` (what ``baobab nav2 --world ...`` sets);
    the default start applies only with the default world.

    Raises:
        WorldError: the world cannot be loaded (located message).
        NavigatorSetupError: an unknown robot, or a start pose that is not free.
        TypeError: an argument of the wrong type.
    """

    def __init__(
        self,
        node_name: str = "basic_navigator",
        namespace: str = "",
        *,
        world: str | FilePath | World | None = None,
        robot: str = "turtlebot3",
        start: Pose2D | None = None,
        seed: int | None = None,
        realtime: bool | None = None,
    ) -> None:
        defaults = navigator_defaults()
        settings = NavigatorDefaults(
            world=defaults.world if world is None or isinstance(world, World) else world,
            start=(defaults.start if world is None else None) if start is None else start,
            seed=defaults.seed if seed is None else seed,
            realtime=defaults.realtime if realtime is None else realtime,
        )
        loaded = world if isinstance(world, World) else load_world(settings.world)
        self._robot_model = robot
        self._seed = settings.seed
        self._time_offset = 0.0
        self._world = loaded
        self._rig, self._server = self._build(loaded, settings.start or loaded.spawn)
        super().__init__(node_name, namespace=namespace)
        self._sim_clock = Clock(clock_type=ClockType.ROS_TIME, source=self._sim_seconds)
        self._pacer = RealTimePacer() if settings.realtime else None
        self._goal: _Goal | None = None
        self._feedback_cleared = False
        self._task_error: tuple[int, str] | None = None
        self._task_error_until_outcome = False
        self._alive = True
        self.initial_pose = msgs.PoseStamped(header=msgs.Header(frame_id="map"))
        set_sim_time_source(self._sim_seconds)

    # -- the simulation -----------------------------------------------------------------------

    def _build(self, world: World, start: Pose2D) -> tuple[SimulatedRobot, NavigationServer]:
        rig = build_simulated_robot(self._robot_model, world, start, self._seed)
        return rig, build_navigation(rig.sim, rig.base, rig.lidar, world)

    def _sim_seconds(self) -> float:
        return self._time_offset + self._rig.sim.time

    def _live_server(self) -> NavigationServer:
        if not self._alive:
            raise BaobabError(f"navigator '{self.get_name()}' was destroyed")
        return self._server

    def _advance(self, horizon: float) -> None:
        """Step the simulation up to ``horizon`` sim seconds, stopping when the task ends."""
        self._live_server()
        sim = self._rig.sim
        end = sim.step_count + max(round(horizon / sim.physics_dt), 0)
        slice_steps = max(round(POLL_SLICE / sim.physics_dt), 1)
        goal = self._goal
        while sim.step_count < end:
            sim.step_to(min(sim.step_count + slice_steps, end))
            if self._pacer is not None:
                self._pacer.wait(self._sim_seconds())
            if goal is not None and goal.outcome() is not None:
                break

    def _spin_once(self, timeout_sec: float | None) -> None:
        """``rclpy.spin_once(navigator)``: advance the sim like one completion poll."""
        horizon = POLL_HORIZON if timeout_sec is None else min(max(timeout_sec, 0.0), POLL_HORIZON)
        self._advance(horizon)

    def _stamp(self) -> msgs.TimeMsg:
        return self._sim_clock.now().to_msg()

    def _stamped(self, pose: Pose2D) -> msgs.PoseStamped:
        return msgs.from_pose2d(pose, stamp=self._stamp())

    # -- node ---------------------------------------------------------------------------------

    def get_clock(self) -> Clock:
        """The navigator's ROS-time clock: simulation seconds."""
        return self._sim_clock

    def destroy_node(self) -> None:
        """Cancel the running task, stop the simulation's navigation, release the node."""
        if self._alive:
            self._alive = False
            self._server.close()
            set_sim_time_source(None)
        super().destroy_node()

    def destroyNode(self) -> None:
        """Nav2's spelling of :meth:`destroy_node`."""
        self.destroy_node()

    def info(self, msg: object) -> None:
        """Log at INFO."""
        self.get_logger().info(msg)

    def warn(self, msg: object) -> None:
        """Log at WARN."""
        self.get_logger().warn(msg)

    def error(self, msg: object) -> None:
        """Log at ERROR."""
        self.get_logger().error(msg)

    def debug(self, msg: object) -> None:
        """Log at DEBUG."""
        self.get_logger().debug(msg)

    # -- lifecycle ----------------------------------------------------------------------------

    def setInitialPose(self, initial_pose: msgs.PoseStamped) -> None:
        """Teleport the robot to ``initial_pose`` (map frame) at rest: the sim localises perfectly.

        Raises:
            NavigatorSetupError: the pose is invalid, outside ``map``, or not free.
        """
        try:
            pose = goal_pose(initial_pose, "initial pose")
        except GoalRejectedError as exc:
            raise NavigatorSetupError(str(exc)) from None
        self._live_server()
        check_free(self._world, pose, self._rig.footprint_radius, what="initial pose")
        self.info("Publishing Initial Pose")
        self._rig.teleport(pose)
        self.initial_pose = copy.deepcopy(initial_pose)

    def waitUntilNav2Active(self, navigator: str = "bt_navigator", localizer: str = "amcl") -> None:
        """Return at once: the simulated stack is always active."""
        self.info("Nav2 is ready for use!")

    def lifecycleStartup(self) -> None:
        """Return at once: the simulated stack is always active."""
        self.info("Starting up lifecycle nodes based on lifecycle_manager.")
        self.info("Nav2 is ready for use!")

    def lifecycleShutdown(self) -> None:
        """Cancel the running task, as Nav2's shutdown ends the servers' goals."""
        self.info("Shutting down lifecycle nodes based on lifecycle_manager.")
        self._live_server().cancel()

    # -- sending tasks ------------------------------------------------------------------------

    def _send(
        self, kind: RunningTask, submit: Callable[[], TaskHandle]
    ) -> RunningTask | Literal[False]:
        server = self._live_server()
        self._feedback_cleared = False
        self._set_task_error(None)
        try:
            handle = submit()
        except GoalRejectedError as exc:
            server.cancel()
            code = int(exc.code if exc.code is not None else _UNKNOWN_CODES[kind])
            message = f"{kind.name} goal was rejected: {exc}"
            self.error(message)
            self._goal = _Goal(kind, None, TaskOutcome(TaskStatus.FAILED, code, message))
            return False
        self._goal = _Goal(kind, handle)
        return kind

    def goToPose(
        self, pose: msgs.PoseStamped, behavior_tree: str = ""
    ) -> RunningTask | Literal[False]:
        """Navigate to ``pose`` (map frame), replanning at 1 Hz with Nav2's recoveries."""

        def submit() -> TaskHandle:
            target = goal_pose(pose)
            self.info(f"Navigating to goal: {pose.pose.position.x} {pose.pose.position.y}...")
            _default_tree_only(behavior_tree, NavigateToPoseError.FAILED_TO_LOAD_BEHAVIOR_TREE)
            return self._server.navigate_to_pose(target)

        return self._send(RunningTask.NAVIGATE_TO_POSE, submit)

    def goThroughPoses(
        self, poses: list[msgs.PoseStamped] | msgs.Goals, behavior_tree: str = ""
    ) -> RunningTask | Literal[False]:
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
    ) -> RunningTask | Literal[False]:
        """Navigate to each pose in turn; ``number_of_loops`` extra passes from ``goal_index``."""
        self.info(f"Following {_count(poses)} goals....")
        return self._send(
            RunningTask.FOLLOW_WAYPOINTS,
            lambda: self._server.follow_waypoints(
                goal_poses(poses),
                stop_on_failure=False,
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
    ) -> RunningTask | Literal[False]:
        """Track ``path`` (``nav_msgs/Path`` in map) with the controller alone."""
        self.info("Executing path...")

        def submit() -> TaskHandle:
            _known_plugin("controller_id", controller_id, FollowPathError.INVALID_CONTROLLER)
            _known_plugin("goal_checker_id", goal_checker_id, FollowPathError.INVALID_CONTROLLER)
            _known_plugin(
                "progress_checker_id", progress_checker_id, FollowPathError.INVALID_CONTROLLER
            )
            _known_plugin("path_handler_id", path_handler_id, FollowPathError.INVALID_CONTROLLER)
            return self._server.follow_path(path_from_message(path))

        return self._send(RunningTask.FOLLOW_PATH, submit)

    def spin(
        self,
        spin_dist: float = 1.57,
        time_allowance: float = 10,
        disable_collision_checks: bool = False,
    ) -> RunningTask | Literal[False]:
        """Turn in place by ``spin_dist`` rad (the sign is the direction)."""
        self.info(f"Spinning to angle {spin_dist}....")
        self._collision_checks_stay_on(disable_collision_checks)
        return self._send(
            RunningTask.SPIN,
            lambda: self._server.spin(float(spin_dist), float(time_allowance)),
        )

    def backup(
        self,
        backup_dist: float = 0.15,
        backup_speed: float = 0.025,
        time_allowance: float = 10,
        disable_collision_checks: bool = False,
    ) -> RunningTask | Literal[False]:
        """Reverse ``backup_dist`` m at ``backup_speed`` m/s (Nav2 floors the speed at 0.10)."""
        self.info(f"Backing up {backup_dist} m at {backup_speed} m/s....")
        self._collision_checks_stay_on(disable_collision_checks)
        return self._send(
            RunningTask.BACKUP,
            lambda: self._server.back_up(
                float(backup_dist), float(backup_speed), float(time_allowance)
            ),
        )

    backUp = backup

    def driveOnHeading(
        self,
        dist: float = 0.15,
        speed: float = 0.025,
        time_allowance: float = 10,
        disable_collision_checks: bool = False,
    ) -> RunningTask | Literal[False]:
        """Drive straight ``dist`` m at ``speed`` m/s (same signs; negative drives backwards)."""
        self.info(f"Drive {dist} m on heading at {speed} m/s....")
        self._collision_checks_stay_on(disable_collision_checks)
        return self._send(
            RunningTask.DRIVE_ON_HEADING,
            lambda: self._server.drive_on_heading(float(dist), float(speed), float(time_allowance)),
        )

    def assistedTeleop(self, time_allowance: float = 30) -> RunningTask | Literal[False]:
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

    def _collision_checks_stay_on(self, disable: bool) -> None:
        if disable:
            self.warn("disable_collision_checks is not supported: collision checks stay on")

    # -- following a task ---------------------------------------------------------------------

    def isTaskComplete(self, task: RunningTask | Literal[False] | None = RunningTask.NONE) -> bool:
        """Advance the sim up to 0.1 s; True once the task ended (or if there is none).

        ``task`` is accepted for Kilted's signature; there is one task at a time.
        """
        goal = self._goal
        if goal is None or goal.outcome() is not None:
            return True
        self._advance(POLL_HORIZON)
        outcome = goal.outcome()
        if outcome is None:
            return False
        if outcome.status is not TaskStatus.SUCCEEDED:
            self.debug(f"Task with failed with status code: {outcome.status.name}")
        return True

    isNavComplete = isTaskComplete

    def cancelTask(self) -> None:
        """Cancel the running task: it ends CANCELED and the robot stops at once."""
        self.info("Canceling current task.")
        self._live_server()
        goal = self._goal
        if goal is None or goal.handle is None:
            self._set_task_error((0, "Cancel task failed, goal handle is None"))
            return
        goal.handle.cancel()
        self._feedback_cleared = True
        self._set_task_error(None)

    cancelNav = cancelTask

    def getFeedback(self, task: RunningTask = RunningTask.NONE) -> Feedback | None:
        """The running task's latest feedback message, None before the first one."""
        goal = self._goal
        if goal is None or goal.handle is None or self._feedback_cleared:
            return None
        return feedback_message(goal.kind, goal.handle.feedback, self._stamped)

    def getResult(self) -> TaskResult:
        """How the last task ended; UNKNOWN while it runs or before any task."""
        goal = self._goal
        outcome = None if goal is None else goal.outcome()
        return TaskResult.UNKNOWN if outcome is None else _RESULTS[outcome.status]

    def getTaskError(self) -> tuple[int, str]:
        """``(error_code, error_msg)`` of the last task or request that did not succeed, else
        ``(0, '')``: a planning or smoothing request's sets it too, as in Nav2 Kilted."""
        goal = self._goal
        outcome = None if goal is None else goal.outcome()
        failed = outcome is not None and outcome.status is not TaskStatus.SUCCEEDED
        if self._task_error is not None and not (failed and self._task_error_until_outcome):
            return self._task_error
        if outcome is None or not failed:
            return (0, "")
        return (outcome.error_code, outcome.error_msg)

    def _set_task_error(self, error: tuple[int, str] | None) -> None:
        """What :meth:`getTaskError` returns (None: the last task's own error) until the next
        task starts or, when set while a task runs, until that task fails (as Nav2's
        ``setTaskError``, which the client calls again when it sees a task fail)."""
        goal = self._goal
        self._task_error = error
        self._task_error_until_outcome = goal is not None and goal.outcome() is None

    def _request_failed(
        self, what: str, exc: GoalRejectedError | NavigationError, unknown: enum.IntEnum
    ) -> None:
        """Log a planning or smoothing request's failure and make it the task error; a
        request refused before it reached the server has the action's UNKNOWN code."""
        self.warn(f"{what} failed: {exc}")
        if isinstance(exc, NavigationError):
            self._set_task_error((int(exc.code), exc.message))
        else:
            self._set_task_error((int(unknown if exc.code is None else exc.code), str(exc)))

    @property
    def result_future(self) -> ResultFuture | None:
        """The last task's result future (``.done()``, ``.result().result``), as in Nav2."""
        goal = self._goal
        if goal is None:
            return None
        handle = goal.handle
        return ResultFuture(
            goal.kind, goal.outcome, lambda: {} if handle is None else handle.feedback
        )

    # -- planning services --------------------------------------------------------------------

    def getPath(
        self,
        start: msgs.PoseStamped | None,
        goal: msgs.PoseStamped,
        planner_id: str = "",
        use_start: bool = False,
    ) -> msgs.Path | None:
        """A path to ``goal`` from the robot (from ``start`` with ``use_start``); None on failure.

        The running task is not disturbed. A failure is logged, and :meth:`getTaskError`
        returns its ``ComputePathToPose`` code and message (``(0, '')`` after a success).
        """
        self.info("Getting path...")
        server = self._live_server()
        self._set_task_error((0, ""))
        try:
            _known_plugin("planner_id", planner_id, ComputePathToPoseError.INVALID_PLANNER)
            origin = goal_pose(start, "start") if use_start and start is not None else None
            path = server.compute_path(origin, goal_pose(goal))
        except (GoalRejectedError, NavigationError) as exc:
            self._request_failed("Getting path", exc, ComputePathToPoseError.UNKNOWN)
            return None
        return path_message(path, self._stamp())

    def getPathThroughPoses(
        self,
        start: msgs.PoseStamped | None,
        goals: list[msgs.PoseStamped] | msgs.Goals,
        planner_id: str = "",
        use_start: bool = False,
    ) -> msgs.Path | None:
        """A path through ``goals`` in order from the robot (or ``start``); None on failure
        (its ``ComputePathThroughPoses`` code and message in :meth:`getTaskError`)."""
        self.info("Getting path through poses...")
        server = self._live_server()
        self._set_task_error((0, ""))
        try:
            _known_plugin("planner_id", planner_id, ComputePathThroughPosesError.INVALID_PLANNER)
            origin = goal_pose(start, "start") if use_start and start is not None else None
            path = server.compute_path_through_poses(origin, goal_poses(goals))
        except (GoalRejectedError, NavigationError) as exc:
            unknown = ComputePathThroughPosesError.UNKNOWN
            self._request_failed("Getting path through poses", exc, unknown)
            return None
        return path_message(path, self._stamp())

    def smoothPath(
        self,
        path: msgs.Path,
        smoother_id: str = "",
        max_duration: float = 2.0,
        check_for_collision: bool = False,
    ) -> msgs.Path | None:
        """Nav2's simple smoother on ``path``; None on failure (logged, and its ``SmoothPath``
        code and message in :meth:`getTaskError`)."""
        self.info("Smoothing path...")
        server = self._live_server()
        self._set_task_error((0, ""))
        try:
            _known_plugin("smoother_id", smoother_id, SmoothPathError.INVALID_SMOOTHER)
            smoothed = server.smooth_path(
                path_from_message(path), check_for_collisions=check_for_collision
            )
        except (GoalRejectedError, NavigationError) as exc:
            self._request_failed("Smoothing path", exc, SmoothPathError.UNKNOWN)
            return None
        return path_message(smoothed, self._stamp())

    # -- costmaps and maps --------------------------------------------------------------------

    def clearAllCostmaps(self) -> None:
        """Clear the obstacle layers of both costmaps; what the lidar still sees stays."""
        self._live_server().clear_costmaps("all")

    def clearLocalCostmap(self) -> None:
        """Clear the local costmap's obstacle layer."""
        self._live_server().clear_costmaps("local")

    def clearGlobalCostmap(self) -> None:
        """Clear the global costmap's obstacle layer."""
        self._live_server().clear_costmaps("global")

    def getGlobalCostmap(self) -> msgs.Costmap:
        """The global costmap as a ``nav2_msgs/Costmap`` (map frame, 0.05 m cells)."""
        return costmap_message(self._live_server().global_costmap(), self._stamp(), "master")

    def getLocalCostmap(self) -> msgs.Costmap:
        """The rolling 3 m x 3 m local costmap as a ``nav2_msgs/Costmap`` (map frame)."""
        return costmap_message(self._live_server().local_costmap(), self._stamp(), "master")

    def changeMap(self, map_filepath: str | FilePath) -> bool:
        """Switch to another world: a bundled world name or a world YAML path.

        The simulation is rebuilt around the new world with the robot where it stands if
        that pose is free there, else at the new world's default spawn; a running task is
        canceled, and sim time goes on from where it was. Returns False (with the task error
        set to a ``LoadMap`` result code and the reason) when the world cannot be loaded.
        """
        self.info("Changing map...")
        server = self._live_server()
        try:
            world = load_world(map_filepath)
        except WorldError as exc:
            code = (
                LoadMapResult.RESULT_INVALID_MAP_DATA
                if FilePath(map_filepath).is_file() or str(map_filepath) in bundled_world_names()
                else LoadMapResult.RESULT_MAP_DOES_NOT_EXIST
            )
            self.error(f"Change map request failed: {exc}")
            self._set_task_error((int(code), str(exc)))
            return False
        pose = self._rig.base.pose()
        start = pose if pose_is_free(world, pose, self._rig.footprint_radius) else world.spawn
        server.close()  # cancels the running task
        self._time_offset = self._sim_seconds()
        self._rig, self._server = self._build(world, start)
        self._world = world
        self._pacer = None if self._pacer is None else RealTimePacer()
        self.info("Change map request was successful!")
        return True

    @property
    def world(self) -> World:
        """The world the robot is in now."""
        return self._world

    @property
    def server(self) -> NavigationServer:
        """The navigation server behind the facade (for inspection in tests and tools)."""
        return self._server

    def robot_pose(self) -> Pose2D:
        """The robot's ground-truth map-frame pose (m, rad)."""
        return self._rig.base.pose()


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


def _known_plugin(parameter: str, value: str, code: enum.IntEnum | None) -> None:
    if value and value not in _PLUGIN_IDS[parameter]:
        known = " or ".join(f"'{name}'" for name in _PLUGIN_IDS[parameter])
        raise GoalRejectedError(f"unknown {parameter} '{value}': the server has {known}", code)
