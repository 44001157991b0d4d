"""Nav2's GPS waypoint follower: FollowGPSWaypoints over the world's datum.

As Nav2's waypoint follower does (reference/nav2_ros_facts.md §9): every GeoPose of the goal
is converted to the map frame at once (``fromLL``: :class:`~baobab.sim.geodesy.MapDatum`),
its orientation copied unchanged (so it is taken as a map-frame heading); a pose that cannot be
converted (a latitude or longitude out of range, not a number, a zero quaternion) is skipped,
or, with ``stop_on_failure``, leaves no waypoints at all. Then the poses run as FollowWaypoints
does (:class:`~baobab.nav.waypoints.WaypointFollower`): NavigateToPose to each in turn,
``number_of_loops`` and ``goal_index`` as the goal says. No waypoints: NO_WAYPOINTS_GIVEN
(602). The server's ``stop_on_failure`` is nav2_bringup's (false).

Registered as ``follow_gps_waypoints`` in ``NavigationServer.action_servers``; the task runs
in the navigation server's slot (it drives the robot), named ``follow_gps_waypoints``. Its
handle holds ``FollowGPSWaypoints.Feedback`` (``current_waypoint``) under ``FEEDBACK_KEY`` and,
once it ended, the Result (``missed_waypoints``, ``error_code``, ``error_msg``) under
``RESULT_KEY``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from baobab.nav import msgs
from baobab.nav.errors import FollowGPSWaypointsError
from baobab.nav.gps_goal import GpsGoal
from baobab.nav.interfaces import FEEDBACK_KEY, RESULT_KEY, ServerTask
from baobab.nav.navigator_feedback import missed_waypoints
from baobab.nav.ros.geographic_msgs.msg import GeoPose
from baobab.nav.ros.nav2_msgs import action
from baobab.nav.waypoints import WaypointFollower
from baobab.sim.datum import Datum
from baobab.sim.geodesy import GeodesyError, GeoWaypoint, MapDatum
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D

if TYPE_CHECKING:
    from baobab.nav.server import NavigationServer

FOLLOW_GPS_WAYPOINTS = "follow_gps_waypoints"


class GpsWaypointFollower:
    """The ``follow_gps_waypoints`` action server of one navigation server.

    Args:
        navigation: the navigation server the waypoints are driven on.
        datum: where the world's map frame lies on the Earth.
        stop_on_failure: end the goal at the first missed (or unconvertible) waypoint.
    """

    def __init__(
        self, navigation: NavigationServer, datum: Datum, *, stop_on_failure: bool = False
    ) -> None:
        self.navigation = navigation
        self.map = MapDatum(datum)
        self.stop_on_failure = stop_on_failure

    def register(self) -> None:
        """Serve ``follow_gps_waypoints``."""
        self.navigation.action_servers[FOLLOW_GPS_WAYPOINTS] = self

    def to_map(self, gps_poses: Sequence[GeoPose | GeoWaypoint]) -> tuple[list[Pose2D], list[int]]:
        """The map poses of ``gps_poses`` and the indices of those that could not be converted
        (``fromLL``, orientation copied)."""
        poses: list[Pose2D] = []
        failed: list[int] = []
        for index, geo in enumerate(gps_poses):
            try:
                waypoint = geo if isinstance(geo, GeoWaypoint) else _waypoint(geo)
                x, y = self.map.to_map(waypoint.latitude, waypoint.longitude, waypoint.altitude)
                yaw = waypoint.yaw
            except (GeodesyError, msgs.MessageValueError):
                failed.append(index)
                if self.stop_on_failure:
                    return [], failed
                continue
            poses.append(Pose2D(x=x, y=y, yaw=yaw))
        return poses, failed

    def send_goal(self, goal: Any) -> TaskHandle:
        """Convert the goal's waypoints and follow them (a ``FollowGPSWaypoints.Goal`` or a
        :class:`~baobab.sim.geodesy.GpsGoal`)."""
        given = goal.waypoints if isinstance(goal, GpsGoal) else goal.gps_poses
        poses, _failed = self.to_map(list(given))
        loops, start = int(goal.number_of_loops), int(goal.goal_index)
        stop = self.stop_on_failure
        navigation = self.navigation

        def follower() -> WaypointFollower:
            return WaypointFollower(
                poses,
                lambda pose: navigation.navigate_task([pose], through_poses=False),
                stop_on_failure=stop,
                loop_rate=navigation.params.waypoint_loop_rate,
                number_of_loops=loops,
                goal_index=start,
            )

        def preempt(task: ServerTask) -> bool:
            if not isinstance(task, GpsWaypointTask):
                return False
            task.preempt(follower())
            return True

        return navigation.tasks.submit(
            FOLLOW_GPS_WAYPOINTS, lambda: GpsWaypointTask(follower()), preempt
        )


class GpsWaypointTask:
    """One FollowGPSWaypoints goal in the navigation server's slot (messages in feedback)."""

    def __init__(self, follower: WaypointFollower) -> None:
        self.follower = follower
        self.period = follower.period
        self.feedback: dict[str, Any] = {}

    def preempt(self, follower: WaypointFollower) -> None:
        """Take a new goal in place: the current navigation stops, the index starts again."""
        self.follower.halt()
        self.follower = follower
        self.feedback.clear()

    def tick(self, now: float) -> TaskOutcome | None:
        """One loop of the waypoint follower at sim time ``now`` (s)."""
        follower = self.follower
        outcome: TaskOutcome | None
        if not follower.waypoints:
            code = FollowGPSWaypointsError.NO_WAYPOINTS_GIVEN
            outcome = TaskOutcome(TaskStatus.FAILED, int(code), "no waypoints given", code.name)
        else:
            outcome = follower.tick(now)
            if outcome is not None and outcome.error_code:
                code = FollowGPSWaypointsError(outcome.error_code)
                outcome = TaskOutcome(outcome.status, int(code), outcome.error_msg, code.name)
        self.feedback[FEEDBACK_KEY] = action.FollowGPSWaypoints.Feedback(
            current_waypoint=follower.index
        )
        if outcome is not None:
            self._result(outcome)
        return outcome

    def halt(self) -> None:
        """Stop the navigation in progress (cancel): the result holds the waypoints missed."""
        self.follower.halt()
        self._result(TaskOutcome(TaskStatus.CANCELED))

    def _result(self, outcome: TaskOutcome) -> None:
        if RESULT_KEY in self.feedback:
            return
        self.feedback[RESULT_KEY] = action.FollowGPSWaypoints.Result(
            missed_waypoints=missed_waypoints(self.follower.missed_waypoints),
            error_code=int(outcome.error_code),
            error_msg=outcome.error_msg,
        )


def _waypoint(geo: GeoPose) -> GeoWaypoint:
    """The waypoint of a ``GeoPose`` (its orientation's yaw).

    Raises:
        MessageValueError: a zero quaternion.
    """
    point = geo.position
    yaw = msgs.yaw_from_quaternion(geo.orientation)
    return GeoWaypoint(point.latitude, point.longitude, yaw, point.altitude)
