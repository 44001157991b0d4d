"""``BasicNavigator``: Nav2's Simple Commander API over baobab's simulated navigation stack.

A Nav2 script drives a robot through ``nav2_simple_commander.robot_navigator.BasicNavigator``:
send a goal, poll ``isTaskComplete()``, read ``getFeedback()``, then ``getResult()``. Here the
same calls drive the :class:`~baobab.nav.server.NavigationServer` of a mobile robot in a MuJoCo
world that the navigator builds for itself. Method names, parameters, defaults, feedback field
names and message types are those of Nav2's current release (reference/nav2.md §1-§2,
nav2_ros_facts.md §4-§5), with every older release's names kept (``isNavComplete``,
``cancelNav``, ``NavigationResult``, ``clearTaskError``, ``clearCostmapAroundPose``). The
calls for servers baobab does not run yet (docking, following, routes, GPS waypoints, the
collision monitor) exist with Nav2's signatures and fail cleanly
(:mod:`baobab.nav.navigator_external`).

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
  rejected at once: the send returns None (Rolling's value, falsy as Humble's ``False``;
  accepted sends return the ``RunningTask``), ``goal_handle.accepted`` is False,
  ``isTaskComplete()`` is True, ``getResult()`` is FAILED and ``getTaskError()`` gives the
  action's UNKNOWN code (or a more precise one) with the reason.
  A rejected send also cancels the task that was running, so the robot is never left driving a
  goal the script no longer tracks. Goals the server accepts but cannot do (a goal inside a
  table, a back-up speed of the wrong sign) end FAILED with Nav2's error code instead.
* **Preemption.** A new goal of the same kind replaces the running one in place (Nav2's
  behaviour); a goal of another kind cancels the running one first (Nav2 asks the caller to).
* **No hijacking.** ``getPath``, ``getPathThroughPoses`` and ``smoothPath`` answer at once and
  leave the running task alone (Nav2 routes them through the task's shared result future).
* **State.** ``getResult()`` is UNKNOWN while a task runs (Nav2 would return the previous
  task's status); feedback and the task error are reset by each send, as in Rolling.
* **Localisation is perfect.** ``setInitialPose()`` teleports the simulated robot;
  ``initial_pose_received`` is always True.
* **Waypoints.** ``followWaypoints`` runs with ``stop_on_failure`` false (nav2_bringup's
  setting): a missed waypoint is recorded and the robot goes on. The missed ones appear in the
  feedback (``missed_waypoints``) and in ``result_future.result().result.missed_waypoints``.

``BasicNavigator`` is an rclpy ``Node`` (the shim's), so ``get_logger()``, ``get_clock()`` and
``rclpy.shutdown()`` behave as in ROS; the logger writes ROS console lines to standard error.
"""

from __future__ import annotations

import copy
import enum
from pathlib import Path as FilePath

from baobab.nav import msgs
from baobab.nav.errors import (
    ComputePathThroughPosesError,
    ComputePathToPoseError,
    GoalRejectedError,
    NavigationError,
    SmoothPathError,
)
from baobab.nav.navigator_core import NavigationResult, TaskResult
from baobab.nav.navigator_external import NavigatorExternal
from baobab.nav.navigator_feedback import RunningTask
from baobab.nav.navigator_messages import (
    MAP_FRAME,
    costmap_message,
    goal_pose,
    goal_poses,
    known_plugin,
    path_from_message,
    path_message,
)
from baobab.nav.navigator_robot import (
    NavigatorSetupError,
    check_free,
    default_start,
    pose_is_free,
)
from baobab.nav.server import NavigationServer
from baobab.sim.errors import WorldError
from baobab.sim.viewer import RealTimePacer
from baobab.sim.world import Pose2D, World, bundled_world_names, load_world

__all__ = ["BasicNavigator", "NavigationResult", "RunningTask", "TaskResult"]


class LoadMapResult(enum.IntEnum):
    """``nav2_msgs/srv/LoadMap`` result codes, what :meth:`BasicNavigator.changeMap` reports."""

    RESULT_SUCCESS = 0
    RESULT_MAP_DOES_NOT_EXIST = 1
    RESULT_INVALID_MAP_DATA = 2
    RESULT_INVALID_MAP_METADATA = 3
    RESULT_UNDEFINED_FAILURE = 255


class BasicNavigator(NavigatorExternal):
    """Nav2's Simple Commander over a simulated robot (see the module docstring).

    The constructor is :class:`~baobab.nav.navigator_core.NavigatorCore`'s: ``node_name``,
    ``namespace``, and keyword-only ``world``, ``robot``, ``start``, ``seed``, ``realtime``.
    The task launchers (``goToPose``, ``spin``, ...) are in
    :class:`~baobab.nav.navigator_tasks.NavigatorTasks` and, for the servers baobab does not
    run yet, :class:`~baobab.nav.navigator_external.NavigatorExternal`; polling a task
    (``isTaskComplete``, ``getFeedback``, ``getResult``, ``cancelTask``) and the task error in
    :class:`~baobab.nav.navigator_tracking.NavigatorTracking`.
    """

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
        check_free(self._world, pose, self._rig.footprint, what="initial pose")
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
            known_plugin("planner_id", planner_id, ComputePathToPoseError.INVALID_PLANNER)
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
            known_plugin("planner_id", planner_id, ComputePathThroughPosesError.INVALID_PLANNER)
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
            known_plugin("smoother_id", smoother_id, SmoothPathError.INVALID_SMOOTHER)
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

    def clearCostmapExceptRegion(self, reset_distance: float) -> None:
        """Clear the local costmap's obstacles outside the square of side ``reset_distance``
        (m) centred on the robot (Jazzy+)."""
        pose = self._rig.base.pose()
        self._clear_region("local", pose.x, pose.y, reset_distance, inside=False)

    def clearCostmapAroundRobot(self, reset_distance: float) -> None:
        """Clear the local costmap's obstacles inside the square of side ``reset_distance``
        (m) centred on the robot (Jazzy+)."""
        pose = self._rig.base.pose()
        self._clear_region("local", pose.x, pose.y, reset_distance, inside=True)

    def clearLocalCostmapAroundPose(self, pose: msgs.PoseStamped, reset_distance: float) -> None:
        """Clear the local costmap's obstacles inside the square of side ``reset_distance``
        (m) centred on ``pose`` (Rolling)."""
        self._clear_around_pose("local", pose, reset_distance)

    def clearGlobalCostmapAroundPose(self, pose: msgs.PoseStamped, reset_distance: float) -> None:
        """Clear the global costmap's obstacles inside the square of side ``reset_distance``
        (m) centred on ``pose`` (Rolling)."""
        self._clear_around_pose("global", pose, reset_distance)

    def clearCostmapAroundPose(self, pose: msgs.PoseStamped, reset_distance: float) -> None:
        """Jazzy's name of :meth:`clearLocalCostmapAroundPose`."""
        self._clear_around_pose("local", pose, reset_distance)

    def _clear_around_pose(self, which: str, pose: msgs.PoseStamped, reset_distance: float) -> None:
        frame = pose.header.frame_id
        if frame not in (MAP_FRAME, ""):
            self.error(
                "Cannot clear map around pose because pose cannot be transformed to costmap "
                f"frame: frame '{frame}' is not '{MAP_FRAME}'"
            )
            return
        position = pose.pose.position
        self._clear_region(which, position.x, position.y, reset_distance, inside=True)

    def _clear_region(
        self, which: str, x: float, y: float, reset_distance: float, *, inside: bool
    ) -> None:
        self._live_server().clear_costmap_region(
            which, float(x), float(y), float(reset_distance), inside=inside
        )

    def getGlobalCostmap(self) -> msgs.Costmap:
        """The global costmap as a ``nav2_msgs/Costmap`` (map frame, 0.05 m cells)."""
        return costmap_message(self._live_server().global_costmap(), self._stamp(), "master")

    def getLocalCostmap(self) -> msgs.Costmap:
        """The rolling 3 m x 3 m local costmap as a ``nav2_msgs/Costmap`` (map frame)."""
        return costmap_message(self._live_server().local_costmap(), self._stamp(), "master")

    def changeMap(self, map_filepath: str | FilePath) -> bool:
        """Switch to another map: a map_server map YAML (as Nav2's ``load_map`` takes), a
        world YAML or a bundled world name.

        The simulation is rebuilt around the new world with the robot where it stands if
        that pose is free there, else at the new world's default spawn (a map without one:
        its origin, if free); a running task is canceled, and sim time goes on from where it
        was. Returns False (with the task error set to a ``LoadMap`` result code and the
        reason) when the map cannot be loaded or the robot has nowhere free to stand.
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
        try:
            footprint = self._rig.footprint
            start = (
                pose if pose_is_free(world, pose, footprint) else default_start(world, footprint)
            )
        except NavigatorSetupError as exc:
            self.error(f"Change map request failed: {exc}")
            self._set_task_error((int(LoadMapResult.RESULT_UNDEFINED_FAILURE), str(exc)))
            return False
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
