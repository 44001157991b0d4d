"""Driving a route: ComputeAndTrackRoute with FollowPath on each new route (``follow_route``).

Nav2 leaves the driving to its caller: its ``example_route.py`` hands every rerouted
feedback's ``path`` to FollowPath, and its route behaviour trees join the robot to the route
with the planner first ("first mile", when the robot is more than 0.3 m from the path's start)
and the route's end to a goal pose ("last mile", beyond 0.1 m). :class:`RouteDrive` does the
same as one task of the navigation server, so a mission leaf can drive a route:

- it sends the tracking goal, reads each feedback message as it comes, and follows each new
  route's path (preempting the controller in place);
- it ends SUCCEEDED when the controller reached the end of the last path, FAILED with the
  tracker's code (4xx: no route, an operation failed), the controller's (1xx) or the
  planner's (2xx, the first or last mile), CANCELED on cancel (tracking canceled too).

Feedback (plain values): the tracker's ``last_node_id``, ``next_node_id``,
``current_edge_id``, the route's node ids (``route_nodes``), ``reroutes`` and the nodes reached
in order (``nodes_reached``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from baobab.nav.controller_server import FollowPathTask
from baobab.nav.errors import NavigationError
from baobab.nav.interfaces import FEEDBACK_QUEUE_KEY, ServerTask
from baobab.nav.navigator_messages import path_from_message
from baobab.nav.path import Path
from baobab.nav.route_requests import RouteRequest
from baobab.nav.route_server import RouteAction, RouteServer, route_request
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D

FIRST_MILE_TOLERANCE = 0.3
"""How far (m) the robot may be from a route path's start before the planner joins them."""
LAST_MILE_TOLERANCE = 0.1
"""How far (m) a route's end may be from a goal pose before the planner joins them."""


FOLLOW_ROUTE = "follow_route"
"""The action name (and task name) of driving a route."""


def register_route_driving(routes: RouteServer) -> None:
    """Serve ``follow_route`` beside the route server's actions (goals: ComputeAndTrackRoute's)."""
    routes.navigation.action_servers[FOLLOW_ROUTE] = RouteAction(
        lambda goal: drive_route(routes, route_request(goal))
    )


def drive_route(routes: RouteServer, request: RouteRequest) -> TaskHandle:
    """Start driving ``request``'s route on the navigation server (task ``follow_route``)."""

    def preempt(task: ServerTask) -> bool:
        if not isinstance(task, RouteDrive):
            return False
        task.preempt(request)
        return True

    return routes.navigation.tasks.submit(
        FOLLOW_ROUTE, lambda: RouteDrive(routes, request), preempt
    )


class RouteDrive:
    """One ``follow_route`` goal (the navigation server's task protocol)."""

    def __init__(self, routes: RouteServer, request: RouteRequest) -> None:
        self.routes = routes
        self.request = request
        navigation = routes.navigation
        self.period = 1.0 / navigation.follower.params.controller_frequency
        self.feedback: dict[str, Any] = {"reroutes": 0, "nodes_reached": []}
        self._tracking: TaskHandle | None = None
        self._read = 0
        self._plans = 0
        self._child: FollowPathTask | None = None

    def preempt(self, request: RouteRequest) -> None:
        """Drive to a new goal: tracking starts again from the robot's pose."""
        self.halt()
        self.request = request
        self.feedback.clear()
        self.feedback.update(reroutes=0, nodes_reached=[])

    def tick(self, now: float) -> TaskOutcome | None:
        """One cycle at sim time ``now`` (s); the outcome once the route is driven."""
        if self._tracking is None:
            self._tracking, self._read, self._plans = self.routes.track(self.request), 0, 0
        try:
            self._read_feedback()
        except NavigationError as exc:
            self.halt()
            return TaskOutcome(TaskStatus.FAILED, int(exc.code), exc.message, exc.code_name)
        tracked = self._tracking.outcome
        if tracked is not None and tracked.status is not TaskStatus.SUCCEEDED:
            self.halt()
            return tracked
        if self._child is None:
            return None
        outcome = self._child.tick(now)
        self.feedback.update(self._child.feedback)
        if outcome is None:
            return None
        self._child = None
        self.halt()
        return outcome

    def _read_feedback(self) -> None:
        assert self._tracking is not None
        queue = self._tracking.feedback.get(FEEDBACK_QUEUE_KEY, [])
        newest_path = None
        while self._read < len(queue):
            message = queue[self._read]
            self._read += 1
            reached = self.feedback["nodes_reached"]
            if not message.rerouted and (not reached or reached[-1] != message.last_node_id):
                reached.append(message.last_node_id)
            self.feedback.update(
                last_node_id=message.last_node_id,
                next_node_id=message.next_node_id,
                current_edge_id=message.current_edge_id,
                route_nodes=[node.nodeid for node in message.route.nodes],
            )
            if message.rerouted:
                self._plans += 1
                self.feedback["reroutes"] = self._plans - 1
                newest_path = message.path
        if newest_path is not None:
            self._follow(self._joined(path_from_message(newest_path)))

    def _joined(self, route_path: Path) -> Path:
        """The route's path with the first and last miles planned on, where needed."""
        navigation = self.routes.navigation
        robot = navigation.robot_pose()
        parts = [route_path.poses]
        start = route_path.pose(0)
        if math.hypot(start.x - robot.x, start.y - robot.y) > FIRST_MILE_TOLERANCE:
            parts.insert(0, navigation.compute_path(robot, start).poses[:-1])
        goal = self.request.goal if self.request.use_poses else None
        end = route_path.goal
        if goal is not None and math.hypot(goal.x - end.x, goal.y - end.y) > LAST_MILE_TOLERANCE:
            parts.append(
                navigation.compute_path(Pose2D(x=end.x, y=end.y, yaw=end.yaw), goal).poses[1:]
            )
        return Path(np.concatenate(parts))

    def _follow(self, path: Path) -> None:
        if self._child is None:
            self._child = FollowPathTask(path, self.routes.navigation.follower)
        else:
            self._child.preempt(path)

    def halt(self) -> None:
        """Stop the controller and the tracking."""
        if self._child is not None:
            self._child.halt()
            self._child = None
        if self._tracking is not None and self._tracking.outcome is None:
            self._tracking.cancel()
        self._tracking = None
