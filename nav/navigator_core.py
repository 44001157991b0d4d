"""The core of :class:`~baobab.nav.navigator.BasicNavigator`: its node, its simulation, its task.

:class:`NavigatorCore` owns what every Simple Commander call shares: the simulated robot and
its :class:`~baobab.nav.server.NavigationServer`, the sim clock, advancing the simulation in
bounded slices, and the one task the navigator tracks (sent, polled, canceled, its feedback,
result and error). The task launchers are in :mod:`baobab.nav.navigator_tasks`; the planning
services, costmaps and maps in :mod:`baobab.nav.navigator`.
"""

from __future__ import annotations

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
    DriveOnHeadingError,
    FollowPathError,
    FollowWaypointsError,
    NavigateThroughPosesError,
    NavigateToPoseError,
    NavigationError,
    SpinError,
)
from baobab.nav.navigator_feedback import Feedback, ResultFuture, RunningTask, feedback_message
from baobab.nav.navigator_messages import GoalRejectedError
from baobab.nav.navigator_robot import (
    SimulatedRobot,
    build_simulated_robot,
    default_start,
    footprint_radius,
)
from baobab.nav.ros.rclpy.node import Node
from baobab.nav.rostime import Clock, ClockType, set_sim_time_source
from baobab.nav.server import NavigationServer, build_navigation
from baobab.sim.errors import BaobabError
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus
from baobab.sim.viewer import RealTimePacer
from baobab.sim.world import Pose2D, World, load_world

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


@dataclass
class _Goal:
    """The task the navigator tracks: a server handle, or the outcome of a rejected send."""

    kind: RunningTask
    handle: TaskHandle | None
    rejection: TaskOutcome | None = None

    def outcome(self) -> TaskOutcome | None:
        return self.rejection if self.handle is None else self.handle.outcome


class NavigatorCore(Node):
    """The node, the simulation and the task of a :class:`~baobab.nav.navigator.BasicNavigator`.

    Args:
        node_name: the node's name (and its logger's).
        namespace: the node's namespace.
        world: a bundled world name, a world YAML path or a loaded ``World``.
        robot: the robot model; ``"turtlebot3"`` (a Burger) is the one there is.
        start: the robot's map-frame start pose; the world's default spawn when None (on a
            map without one, the map origin: :func:`~baobab.nav.navigator_robot.default_start`).
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
        start = settings.start or default_start(loaded, footprint_radius(robot))
        self._rig, self._server = self._build(loaded, start)
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
