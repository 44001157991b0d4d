"""Nav2's route tracker: where the robot is on its route, the operations, the reroutes.

One ComputeAndTrackRoute goal: plan, then watch the robot at ``tracker_update_rate`` (50 Hz of
sim time). It does not drive: a script follows the feedback's ``path`` with FollowPath
(Nav2's ``example_route.py``), or the ``follow_route`` task does (:mod:`.route_drive`).

A node counts as reached when the robot came within ``radius_to_achieve_node`` (2 m) and has
crossed the bisector of the edges before and after it, or has left that radius again; the
route's first and last nodes need only ``boundary_radius_to_achieve_node`` (1 m).
Feedback (``ComputeAndTrackRoute.Feedback``, queued as Nav2 queues it) comes after every
(re)plan with ``rerouted`` true, on each node reached or operation that acted, and once at the
end with the goal as ``last_node_id``.

Operations: the collision monitor looks ``max_collision_dist`` (3 m) ahead along the route on
the local costmap once a second and, on an edge with a cell of ``max_cost`` (253) or more,
blocks that edge and reroutes from the last node reached; :meth:`RouteTracking.reroute` is
the rerouting service. Nav2 lists every query operation in ``operations_triggered`` on every
cycle; here only the operations that acted are listed. An operation the graph file names on
a node or edge runs when its trigger comes; baobab has none of Nav2's graph-triggered plugins
(TriggerEvent, TimeMarker), so such an operation fails the goal with OPERATION_FAILED, as
Nav2 does for an operation it has not loaded.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from baobab.nav import msgs
from baobab.nav.costmap import Costmap2D
from baobab.nav.errors import ComputeAndTrackRouteError, NavigationError
from baobab.nav.interfaces import FEEDBACK_KEY, FEEDBACK_QUEUE_KEY, MobileBase
from baobab.nav.navigator_messages import path_message
from baobab.nav.path import Path
from baobab.nav.ros.nav2_msgs import action
from baobab.nav.ros.nav2_msgs.msg import Route as RouteMessage
from baobab.nav.ros.nav2_msgs.msg import RouteEdge, RouteNode
from baobab.nav.rostime import ClockType, Time
from baobab.nav.route_graph import Route, RouteParams
from baobab.nav.route_planner import line_blocked
from baobab.nav.route_requests import Rerouting, RoutePlanning, RouteRequest, closest_point
from baobab.sim.route_graph_file import GraphEdge, GraphNode
from baobab.sim.tasks import TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D

COLLISION_MONITOR = "CollisionMonitor"
REROUTING_SERVICE = "ReroutingService"


@dataclass
class TrackingState:
    """Progress along the current route (Nav2's ``RouteTrackingState``)."""

    next_node: GraphNode | None
    last_node: GraphNode | None = None
    current_edge: GraphEdge | None = None
    edge_index: int = -1
    within_radius: bool = False


def stamp_at(seconds: float) -> msgs.TimeMsg:
    """A ROS-time stamp at sim time ``seconds``."""
    return Time(seconds=max(seconds, 0.0), clock_type=ClockType.ROS_TIME).to_msg()


def route_message(route: Route, planning: RoutePlanning, stamp: msgs.TimeMsg) -> RouteMessage:
    """The ``nav2_msgs/Route`` of ``route``."""
    graph = planning.graph

    def point(node_id: int) -> msgs.Point:
        node = graph.node(node_id)
        return msgs.Point(x=node.x, y=node.y)

    return RouteMessage(
        header=msgs.Header(stamp=stamp, frame_id="map"),
        route_cost=float(route.cost),
        nodes=[RouteNode(nodeid=node_id, position=point(node_id)) for node_id in route.node_ids()],
        edges=[
            RouteEdge(edgeid=edge.id, start=point(edge.start), end=point(edge.end))
            for edge in route.edges
        ],
    )


class RouteTracking:
    """One ComputeAndTrackRoute goal, ticked by the route server.

    Args:
        request: the goal.
        planning: plans on the server's graph.
        base: the robot (its pose, map frame).
        local_costmap: the local costmap now (collision monitor).
        params: settings.
        feedback: the goal handle's feedback dict (messages under FEEDBACK_KEY and
            FEEDBACK_QUEUE_KEY).
    """

    def __init__(
        self,
        request: RouteRequest,
        planning: RoutePlanning,
        base: MobileBase,
        local_costmap: Callable[[], Costmap2D],
        params: RouteParams,
        feedback: dict[str, Any],
    ) -> None:
        self.request = request
        self.planning = planning
        self.base = base
        self.local_costmap = local_costmap
        self.params = params
        self.feedback = feedback
        feedback.setdefault(FEEDBACK_QUEUE_KEY, [])
        self.rerouting = Rerouting()
        self.route: Route | None = None
        self.path: Path | None = None
        self.state = TrackingState(None)
        self.reroutes = 0
        self._reroute_requested = False
        self._next_collision_check = -math.inf

    def preempt(self, request: RouteRequest) -> None:
        """Take a new goal in place: plan afresh on the next tick."""
        self.request = request
        self.rerouting = Rerouting()
        self.route = None

    def reroute(self) -> None:
        """Ask for a new route from where the robot is (Nav2's ReroutingService)."""
        self._reroute_requested = True

    def tick(self, now: float) -> TaskOutcome | None:
        """One tracker cycle at sim time ``now`` (s); the outcome once the goal ended."""
        try:
            if self.route is None:
                self._plan(now)
            return self._track(now)
        except NavigationError as exc:
            code = ComputeAndTrackRouteError(int(exc.code))
            return TaskOutcome(TaskStatus.FAILED, int(code), exc.message, code.name)

    def _plan(self, now: float) -> None:
        route = self.planning.plan(self.request, self.base.pose(), self.rerouting)
        self.route = route
        self.path = self.planning.densify(route, self.rerouting)
        state = TrackingState(route.start)
        kept = self.rerouting.current_edge
        if kept is not None:
            state.current_edge, state.last_node = kept, self.planning.graph.node(kept.start)
        self.state = state
        last = 0 if state.last_node is None else state.last_node.id
        edge = 0 if state.current_edge is None else state.current_edge.id
        self._publish(now, rerouted=True, next_id=route.start.id, last_id=last, edge_id=edge)

    def _track(self, now: float) -> TaskOutcome | None:
        route, state = self.route, self.state
        assert route is not None and state.next_node is not None  # planned just before
        pose = self.base.pose()
        status_change = completed = False
        if self._node_achieved(pose, state, route):
            status_change, state.within_radius = True, False
            state.last_node = state.next_node
            state.edge_index += 1
            if state.edge_index < len(route.edges):
                state.current_edge = route.edges[state.edge_index]
                state.next_node = self.planning.graph.node(state.current_edge.end)
            else:
                state.current_edge, state.next_node, completed = None, None, True
        triggered, blocked, reroute = self._operations(now, status_change, pose)
        if completed:
            last = state.last_node.id if state.last_node is not None else 0
            self._publish(now, rerouted=False, next_id=0, last_id=last, edge_id=0, ops=triggered)
            return TaskOutcome(TaskStatus.SUCCEEDED)
        if (status_change or triggered) and state.current_edge is not None:
            assert state.next_node is not None and state.last_node is not None
            self._publish(
                now,
                rerouted=False,
                next_id=state.next_node.id,
                last_id=state.last_node.id,
                edge_id=state.current_edge.id,
                ops=triggered,
            )
        if reroute:
            rerouting = self.rerouting
            if self.params.aggregate_blocked_ids:
                rerouting.blocked_ids.extend(blocked)
            else:
                rerouting.blocked_ids = list(blocked)
            last_node = state.last_node
            rerouting.start_id = None if last_node is None else last_node.id
            rerouting.start_pose = None if last_node is None else pose
            rerouting.current_edge = state.current_edge
            self.reroutes += 1
            self._plan(now)
        return None

    def _node_achieved(self, pose: Pose2D, state: TrackingState, route: Route) -> bool:
        node = state.next_node
        assert node is not None
        dx, dy = node.x - pose.x, node.y - pose.y
        distance = math.hypot(dx, dy)
        boundary = state.edge_index == len(route.edges) - 1 or (
            state.edge_index == -1 and state.current_edge is None
        )
        radius = (
            self.params.boundary_radius_to_achieve_node
            if boundary
            else self.params.radius_to_achieve_node
        )
        in_radius = distance <= radius
        if distance < 1e-4 or (not in_radius and state.within_radius):
            return True
        state.within_radius = in_radius
        if boundary or not in_radius:
            return in_radius
        assert state.current_edge is not None  # not a boundary node: an edge leads here
        graph = self.planning.graph
        last = graph.node(state.current_edge.start)
        after = graph.node(route.edges[state.edge_index + 1].end)
        nx, ny = node.x - last.x, node.y - last.y
        mx, my = after.x - node.x, after.y - node.y
        n_len, m_len = math.hypot(nx, ny), math.hypot(mx, my)
        if n_len < 1e-6 or m_len < 1e-6:
            return True
        bx, by = nx * m_len + mx * n_len, ny * m_len + my * n_len  # the edges' bisector
        return bx * dx + by * dy <= 0

    def _operations(
        self, now: float, status_change: bool, pose: Pose2D
    ) -> tuple[list[str], list[int], bool]:
        """Run the operations due: (names that acted, blocked ids, reroute asked)."""
        triggered: list[str] = []
        blocked: list[int] = []
        reroute = False
        state = self.state
        if status_change:
            self._graph_operations()
        if self._reroute_requested:
            self._reroute_requested = False
            triggered.append(REROUTING_SERVICE)
            reroute = True
        due = now >= self._next_collision_check - 1e-9
        if self.params.collision_monitor and state.current_edge is not None and due:
            self._next_collision_check = now + 1.0 / self.params.collision_check_rate
            hit = self._collision_ahead(pose)
            if hit is not None:
                if not self.params.reroute_on_collision:
                    raise NavigationError(
                        ComputeAndTrackRouteError.OPERATION_FAILED,
                        "Collision detected, but rerouting is not enabled, canceling "
                        "tracking task.",
                    )
                triggered.append(COLLISION_MONITOR)
                blocked.append(hit)
                reroute = True
        return triggered, blocked, reroute

    def _graph_operations(self) -> None:
        """Operations the graph file puts on the node reached and the edges entered and left."""
        state, route = self.state, self.route
        assert route is not None
        exited = route.edges[state.edge_index - 1] if state.edge_index > 0 else None
        if state.edge_index == 0 and self.rerouting.current_edge is not None:
            exited = self.rerouting.current_edge
        wanted = [
            (state.last_node, "NODE"),
            (state.current_edge, "ON_ENTER"),
            (exited, "ON_EXIT"),
        ]
        for owner, trigger in wanted:
            for operation in () if owner is None else owner.operations:
                if operation.trigger == trigger:
                    raise NavigationError(
                        ComputeAndTrackRouteError.OPERATION_FAILED,
                        f"Operation {operation.type} does not exist in route operations loaded!",
                    )

    def _collision_ahead(self, pose: Pose2D) -> int | None:
        """The id of the first edge ahead with a blocked cell within ``max_collision_dist``."""
        route, state = self.route, self.state
        assert route is not None and state.current_edge is not None
        graph = self.planning.graph
        costmap = self.local_costmap()
        edge = state.current_edge
        start_node, end_node = graph.node(edge.start), graph.node(edge.end)
        start = closest_point(pose, start_node, end_node)
        budget = self.params.max_collision_dist if self.params.max_collision_dist > 0 else math.inf
        following = list(route.edges[state.edge_index + 1 :])
        while True:
            end = (end_node.x, end_node.y)
            length = math.dist(start, end)
            last = length >= budget
            if last:
                fraction = budget / length
                end = (
                    start[0] + fraction * (end[0] - start[0]),
                    start[1] + fraction * (end[1] - start[1]),
                )
            if line_blocked(costmap, start, end, self.params.max_cost):
                return edge.id
            budget -= length
            if last or not following:
                return None
            edge = following.pop(0)
            start, end_node = end, graph.node(edge.end)

    def _publish(
        self,
        now: float,
        *,
        rerouted: bool,
        next_id: int,
        last_id: int,
        edge_id: int,
        ops: list[str] | None = None,
    ) -> None:
        assert self.route is not None and self.path is not None
        stamp = stamp_at(now)
        message = action.ComputeAndTrackRoute.Feedback(
            last_node_id=last_id,
            next_node_id=next_id,
            current_edge_id=edge_id,
            route=route_message(self.route, self.planning, stamp),
            path=path_message(self.path, stamp),
            operations_triggered=list(ops or ()),
            rerouted=rerouted,
        )
        self.feedback[FEEDBACK_KEY] = message
        self.feedback[FEEDBACK_QUEUE_KEY].append(message)
