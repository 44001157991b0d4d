"""The Simple Commander calls served by Nav2's newer servers: docking, following, routes, GPS.

Each call builds the action's Goal message exactly as Nav2's ``BasicNavigator`` does and sends
it to the server registered under the action's name in
``NavigationServer.action_servers`` (:class:`~baobab.nav.interfaces.ActionServer`);
``toggleCollisionMonitor`` calls ``NavigationServer.services['collision_monitor/toggle']``,
which a navigator built with a collision monitor serves (:mod:`baobab.nav.collision_monitor`).
Where Nav2 would wait for ever for a server that is not there, the call fails at once and
cleanly: the send is rejected (None, the action's UNKNOWN code and the reason in
``getTaskError()``), ``getRoute`` returns None, and ``toggleCollisionMonitor`` logs the error.
A server plugged in later needs no change here.
"""

from __future__ import annotations

from collections.abc import Sequence

from baobab.nav import msgs
from baobab.nav.collision_monitor import COLLISION_MONITOR_TOGGLE
from baobab.nav.errors import ComputeRouteError, GoalRejectedError
from baobab.nav.interfaces import RESULT_KEY
from baobab.nav.navigator_feedback import RunningTask
from baobab.nav.navigator_tasks import NavigatorTasks
from baobab.nav.ros.geographic_msgs.msg import GeoPose
from baobab.nav.ros.nav2_msgs import action
from baobab.nav.ros.nav2_msgs.msg import Route
from baobab.nav.rosmsg import Message
from baobab.nav.rostime import DurationMsg
from baobab.sim.tasks import TaskHandle, TaskStatus

ROUTE_PLANNING_LIMIT = 60.0
"""Sim seconds ``getRoute`` waits for the route server before giving up (TIMEOUT)."""

_SERVERS = {
    "follow_gps_waypoints": ("FollowGPSWaypoints", "GPS waypoint follower"),
    "dock_robot": ("DockRobot", "docking"),
    "undock_robot": ("UndockRobot", "docking"),
    "follow_object": ("FollowObject", "following"),
    "compute_route": ("ComputeRoute", "route"),
    "compute_and_track_route": ("ComputeAndTrackRoute", "route"),
}


class NavigatorExternal(NavigatorTasks):
    """The calls of :class:`~baobab.nav.navigator.BasicNavigator` for the newer servers."""

    def _send_external(
        self, kind: RunningTask, action_name: str, goal: Message
    ) -> RunningTask | None:
        return self._send(kind, lambda: self._external_goal(action_name, goal), external=True)

    def _external_goal(self, action_name: str, goal: Message) -> TaskHandle:
        server = self._live_server().action_servers.get(action_name)
        if server is None:
            label, kind = _SERVERS[action_name]
            raise GoalRejectedError(
                f"'{label}' action server ('{action_name}') not available: baobab has no "
                f"{kind} server"
            )
        return server.send_goal(goal)

    # -- GPS waypoints, docking, following ----------------------------------------------------

    def followGpsWaypoints(self, gps_poses: Sequence[GeoPose]) -> RunningTask | None:
        """Follow GPS poses in turn (Jazzy+); needs a GPS waypoint follower."""
        goal = action.FollowGPSWaypoints.Goal(gps_poses=list(gps_poses))
        self.info(f"Following {len(goal.gps_poses)} gps goals....")
        return self._send_external(RunningTask.FOLLOW_GPS_WAYPOINTS, "follow_gps_waypoints", goal)

    def dockRobotByPose(
        self, dock_pose: msgs.PoseStamped, dock_type: str = "", nav_to_dock: bool = True
    ) -> RunningTask | None:
        """Dock at ``dock_pose`` (a dock of ``dock_type``), navigating to its staging pose
        first with ``nav_to_dock``; needs a docking server."""
        goal = action.DockRobot.Goal(
            use_dock_id=False,
            dock_pose=dock_pose,
            dock_type=dock_type,
            navigate_to_staging_pose=nav_to_dock,
        )
        self.info(f"Docking at pose: {dock_pose}...")
        return self._send_external(RunningTask.DOCK_ROBOT, "dock_robot", goal)

    def dockRobotByID(self, dock_id: str, nav_to_dock: bool = True) -> RunningTask | None:
        """Dock at the dock named ``dock_id`` in the dock database; needs a docking server."""
        goal = action.DockRobot.Goal(
            use_dock_id=True, dock_id=dock_id, navigate_to_staging_pose=nav_to_dock
        )
        self.info(f"Docking at dock ID: {dock_id}...")
        return self._send_external(RunningTask.DOCK_ROBOT, "dock_robot", goal)

    def undockRobot(self, dock_type: str = "") -> RunningTask | None:
        """Undock from the current dock; needs a docking server."""
        goal = action.UndockRobot.Goal(dock_type=dock_type)
        self.info(f"Undocking from dock of type: {dock_type}...")
        return self._send_external(RunningTask.UNDOCK_ROBOT, "undock_robot", goal)

    def followObjectByTopic(self, topic: str, max_duration: int = 0) -> RunningTask | None:
        """Follow the poses published on ``topic`` for ``max_duration`` s (0: no limit)."""
        goal = action.FollowObject.Goal(
            pose_topic=topic, max_duration=DurationMsg(sec=int(max_duration))
        )
        self.info(f"Following object from topic: {topic}...")
        return self._send_external(RunningTask.FOLLOW_OBJECT, "follow_object", goal)

    def followObjectByFrame(self, frame: str, max_duration: int = 0) -> RunningTask | None:
        """Follow the TF frame ``frame`` for ``max_duration`` s (0: no limit)."""
        goal = action.FollowObject.Goal(
            tracked_frame=frame, max_duration=DurationMsg(sec=int(max_duration))
        )
        self.info(f"Following object with frame: {frame}...")
        return self._send_external(RunningTask.FOLLOW_OBJECT, "follow_object", goal)

    # -- routes -------------------------------------------------------------------------------

    def getAndTrackRoute(
        self,
        start: int | msgs.PoseStamped,
        goal: int | msgs.PoseStamped,
        use_start: bool = False,
    ) -> RunningTask | None:
        """Plan a route and track it as the robot drives (Kilted+); needs a route server.

        ``start`` and ``goal`` are both graph node ids or both poses. The route task runs
        beside the tracked task: poll it with ``isTaskComplete(RunningTask.
        COMPUTE_AND_TRACK_ROUTE)``; its feedback queues (``getFeedback`` of that task).
        """
        message = _route_goal(action.ComputeAndTrackRoute.Goal(), start, goal, use_start)
        self.info("Computing and tracking route...")
        return self._send_external(
            RunningTask.COMPUTE_AND_TRACK_ROUTE, "compute_and_track_route", message
        )

    def getRoute(
        self,
        start: int | msgs.PoseStamped,
        goal: int | msgs.PoseStamped,
        use_start: bool = False,
    ) -> list[msgs.Path | Route] | None:
        """``[path, route]`` from ``start`` to ``goal`` (Kilted+), or None on failure (its code
        and message in ``getTaskError()``); blocks for up to 60 s of sim time.

        Nav2 sends ``use_start`` as False whatever it is given; here it is passed on.
        """
        self.info("Getting route...")
        self._live_server()
        self._set_task_error((0, ""))
        message = _route_goal(action.ComputeRoute.Goal(), start, goal, use_start)
        try:
            handle = self._external_goal("compute_route", message)
        except GoalRejectedError as exc:
            self._request_failed("Getting route", exc, ComputeRouteError.UNKNOWN)
            return None
        self._advance(
            ROUTE_PLANNING_LIMIT, lambda: handle.outcome is not None, changes_in_callbacks=True
        )
        outcome = handle.outcome
        if outcome is None:
            handle.cancel()
            self.warn("Getting route failed: the route server did not answer in time")
            self._set_task_error((int(ComputeRouteError.TIMEOUT), "route planning timed out"))
            return None
        if outcome.status is not TaskStatus.SUCCEEDED:
            self.warn(f"Getting route failed: {outcome.error_code}: {outcome.error_msg}")
            self._set_task_error((outcome.error_code, outcome.error_msg))
            return None
        result = handle.feedback[RESULT_KEY]
        return [result.path, result.route]

    # -- collision monitor --------------------------------------------------------------------

    def toggleCollisionMonitor(self, enable: bool) -> None:
        """Turn the collision monitor's zones on or off (Rolling); needs a collision monitor.

        Off, commands pass unchanged and the controller's own collision checks act alone;
        stale sensor data still stops the robot (Nav2's ``Toggle`` service).
        """
        service = self._live_server().services.get(COLLISION_MONITOR_TOGGLE)
        if service is None:
            self.error(
                f"Toggle collision monitor service '{COLLISION_MONITOR_TOGGLE}' not available: "
                "this robot has no collision monitor (give the navigator collision_monitor "
                "parameters, or its world a collision_monitor: block)"
            )
            return
        success, reason = service(bool(enable))
        if success:
            self.info(f"Collision monitor {'enabled' if enable else 'disabled'}")
        else:
            self.error(f"Toggle collision monitor failed: {reason}")


def _route_goal(
    message: Message,
    start: int | msgs.PoseStamped,
    goal: int | msgs.PoseStamped,
    use_start: bool,
) -> Message:
    """Fill a ComputeRoute or ComputeAndTrackRoute goal from node ids or poses.

    Raises:
        TypeError: ``start`` and ``goal`` are not both ints or both ``PoseStamped``.
    """
    if isinstance(start, int) and isinstance(goal, int):
        message.start_id, message.goal_id = start, goal  # type: ignore[attr-defined]
        message.use_poses = False  # type: ignore[attr-defined]
    elif isinstance(start, msgs.PoseStamped) and isinstance(goal, msgs.PoseStamped):
        message.start, message.goal = start, goal  # type: ignore[attr-defined]
        message.use_poses = True  # type: ignore[attr-defined]
    else:
        raise TypeError(
            "start and goal must both be route graph node ids (int) or both PoseStamped, not "
            f"{type(start).__name__} and {type(goal).__name__}"
        )
    message.use_start = bool(use_start)  # type: ignore[attr-defined]
    return message
