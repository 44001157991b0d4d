"""Nav2's route server over a world's route graph: ComputeRoute and ComputeAndTrackRoute.

Registered in ``NavigationServer.action_servers`` as ``compute_route`` and
``compute_and_track_route`` (what :class:`~baobab.nav.navigator.BasicNavigator`'s ``getRoute``
and ``getAndTrackRoute`` send); :mod:`baobab.nav.route_drive` adds ``follow_route``, baobab's
task that drives the tracked route (the mission leaf's). Goals are Nav2's messages;
each handle holds the action's messages (feedback, queued feedback, result) as
:class:`~baobab.nav.interfaces.ActionServer` says.

ComputeRoute answers at once. ComputeAndTrackRoute runs beside whatever task drives the robot,
ticked at ``tracker_update_rate`` on the simulation's clock; one goal tracks at a time, a new
one preempts it in place (the old handle ends FAILED with code 0, as Nav2 aborts it) and
``cancel()`` ends it CANCELED. A goal with a pose outside the ``map`` frame is rejected.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from baobab.nav.errors import ComputeRouteError, NavigationError
from baobab.nav.interfaces import FEEDBACK_QUEUE_KEY, RESULT_KEY
from baobab.nav.navigator_feedback import duration
from baobab.nav.navigator_messages import goal_pose, path_message
from baobab.nav.ros.nav2_msgs import action
from baobab.nav.route_graph import RouteParams, SearchGraph
from baobab.nav.route_requests import Rerouting, RoutePlanning, RouteRequest
from baobab.nav.route_tracker import RouteTracking, route_message, stamp_at
from baobab.nav.task_slot import CANCELED, preempted
from baobab.sim.route_graph_file import RouteGraph
from baobab.sim.simulation import PeriodicHandle
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus

if TYPE_CHECKING:
    from baobab.nav.server import NavigationServer

COMPUTE_ROUTE = "compute_route"
COMPUTE_AND_TRACK_ROUTE = "compute_and_track_route"


def route_request(goal: Any) -> RouteRequest:
    """The request of a ComputeRoute or ComputeAndTrackRoute goal message (a
    :class:`RouteRequest` is taken as it is: the navigation server's ``follow_route``).

    Raises:
        GoalRejectedError: a pose outside the ``map`` frame or not a valid pose.
    """
    if isinstance(goal, RouteRequest):
        return goal
    if not goal.use_poses:
        return RouteRequest(False, int(goal.start_id), int(goal.goal_id))
    start = goal_pose(goal.start, "route start") if goal.use_start else None
    return RouteRequest(True, start=start, goal=goal_pose(goal.goal, "route goal"))


@dataclass
class _Tracked:
    handle: TaskHandle
    tracking: RouteTracking
    timer: PeriodicHandle


@dataclass
class RouteAction:
    """One action name of the route server (the ``ActionServer`` protocol)."""

    send: Callable[[Any], TaskHandle]

    def send_goal(self, goal: Any) -> TaskHandle:
        """Start working on ``goal``."""
        return self.send(goal)


class RouteServer:
    """Routes on one graph for one navigation server.

    Args:
        navigation: the navigation server (its simulation, robot, costmaps, tasks).
        graph: the route graph.
        params: settings (Nav2's defaults when omitted).
    """

    def __init__(
        self,
        navigation: NavigationServer,
        graph: RouteGraph,
        params: RouteParams | None = None,
    ) -> None:
        self.navigation = navigation
        self.params = params or RouteParams()
        self.graph = SearchGraph(graph)
        self.planning = RoutePlanning(self.graph, self.params, navigation.global_costmap)
        self._tracked: _Tracked | None = None
        self._past_reroutes = 0

    def register(self) -> None:
        """Serve ``compute_route`` and ``compute_and_track_route``."""
        servers = self.navigation.action_servers
        servers[COMPUTE_ROUTE] = RouteAction(self.compute_route)
        servers[COMPUTE_AND_TRACK_ROUTE] = RouteAction(lambda goal: self.track(route_request(goal)))

    @property
    def reroutes(self) -> int:
        """Routes planned again for goals being tracked, all goals so far."""
        current = 0 if self._tracked is None else self._tracked.tracking.reroutes
        return self._past_reroutes + current

    @property
    def tracking(self) -> RouteTracking | None:
        """The tracked goal, if one runs."""
        return None if self._tracked is None else self._tracked.tracking

    # -- ComputeRoute -------------------------------------------------------------------------

    def compute_route(self, goal: Any) -> TaskHandle:
        """Plan at once; the handle has ended, its result under ``RESULT_KEY``.

        Raises:
            GoalRejectedError: see :func:`route_request`.
        """
        request = route_request(goal)
        now = self.navigation.sim.time
        handle = TaskHandle(COMPUTE_ROUTE, lambda _: None)
        handle.started_at = handle.ended_at = now
        stamp = stamp_at(now)
        result = action.ComputeRoute.Result(planning_time=duration(0.0))
        try:
            rerouting = Rerouting()
            route = self.planning.plan(request, self.navigation.robot_pose(), rerouting)
            result.route = route_message(route, self.planning, stamp)
            result.path = path_message(self.planning.densify(route, rerouting), stamp)
            outcome = TaskOutcome(TaskStatus.SUCCEEDED)
        except NavigationError as exc:
            code = ComputeRouteError(int(exc.code))
            result.error_code, result.error_msg = int(code), exc.message
            outcome = TaskOutcome(TaskStatus.FAILED, int(code), exc.message, code.name)
        handle.feedback[RESULT_KEY] = result
        handle.finish(outcome)
        return handle

    # -- ComputeAndTrackRoute -----------------------------------------------------------------

    def track(self, request: RouteRequest) -> TaskHandle:
        """Plan ``request`` and track the robot along the route (preempting a tracked goal)."""
        sim = self.navigation.sim
        handle = TaskHandle(COMPUTE_AND_TRACK_ROUTE, self._on_cancel)
        handle.started_at = sim.time
        tracked = self._tracked
        if tracked is not None:
            previous = tracked.handle
            tracked.handle = handle
            tracked.tracking.preempt(request)
            tracked.tracking.feedback = handle.feedback
            handle.feedback.setdefault(FEEDBACK_QUEUE_KEY, [])
            self._finish(previous, preempted(COMPUTE_AND_TRACK_ROUTE))
            return handle
        tracking = RouteTracking(
            request,
            self.planning,
            self.navigation.base,
            self.navigation.local_costmap,
            self.params,
            handle.feedback,
        )
        timer = sim.every(1.0 / self.params.tracker_update_rate, self._tick, name="route tracker")
        self._tracked = _Tracked(handle, tracking, timer)
        return handle

    def reroute(self) -> bool:
        """Ask the tracked goal for a new route (Nav2's ``route_server/ReroutingService/
        reroute``); False when nothing is tracked."""
        if self._tracked is None:
            return False
        self._tracked.tracking.reroute()
        return True

    def cancel(self) -> None:
        """Cancel the tracked goal, if any."""
        if self._tracked is not None:
            self._tracked.handle.cancel()

    def _tick(self, now: float) -> None:
        tracked = self._tracked
        if tracked is None:
            return
        outcome = tracked.tracking.tick(now)
        if outcome is not None and self._tracked is tracked:
            self._stop()
            self._finish(tracked.handle, outcome)

    def _on_cancel(self, handle: TaskHandle) -> None:
        tracked = self._tracked
        if tracked is None or tracked.handle is not handle:
            return
        self._stop()
        self._finish(handle, CANCELED)

    def _stop(self) -> None:
        if self._tracked is not None:
            self._tracked.timer.cancel()
            self._past_reroutes += self._tracked.tracking.reroutes
            self._tracked = None

    def _finish(self, handle: TaskHandle, outcome: TaskOutcome) -> None:
        if handle.outcome is not None:
            return
        handle.ended_at = self.navigation.sim.time
        elapsed = handle.ended_at - (handle.started_at or handle.ended_at)
        handle.feedback[RESULT_KEY] = action.ComputeAndTrackRoute.Result(
            execution_duration=duration(elapsed),
            error_code=int(outcome.error_code),
            error_msg=outcome.error_msg,
        )
        handle.finish(outcome)
