"""From a route request to a route and its dense path (Nav2's goal intent extractor and path
converter).

A request names its start and goal as node ids, or as poses (``use_poses``): a pose maps to
the nearest of the ``num_nearest_nodes`` nodes that it sees in a straight line over the global
costmap (Nav2 searches the costmap breadth-first among the same candidates when the nearest
one is hidden; here the nearest visible one is taken, else the nearest), and the start is the
robot's pose unless ``use_start``. With poses, a first edge the robot is already driving along
and a last edge past the goal are pruned, as Nav2 does. While tracking, a reroute starts from
the last node reached and the robot's pose, and avoids the blocked ids (:class:`Rerouting`).

The dense path has a pose every ``path_density`` m along the edges, each facing the next; the
last faces along the last edge.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from baobab.nav.costmap import Costmap2D
from baobab.nav.errors import ComputeRouteError, NavigationError
from baobab.nav.path import Path
from baobab.nav.route_graph import Route, RouteParams, SearchGraph
from baobab.nav.route_planner import EdgeScorer, find_route, line_blocked
from baobab.sim.route_graph_file import GraphEdge, GraphNode
from baobab.sim.world import Pose2D

EPSILON = 1e-6


@dataclass(frozen=True)
class RouteRequest:
    """A ComputeRoute / ComputeAndTrackRoute goal, map frame (m, rad).

    ``start`` is None when the route starts at the robot (``use_start`` false). With
    ``use_poses``, a ``goal`` of None means the node ``goal_id`` (a mission's ``follow_route``
    to a node from the robot's pose; Nav2's messages always carry a goal pose).
    """

    use_poses: bool
    start_id: int = 0
    goal_id: int = 0
    start: Pose2D | None = None
    goal: Pose2D | None = None

    @classmethod
    def between(cls, start: int | Pose2D | None, goal: int | Pose2D) -> RouteRequest:
        """A request from ``start`` (a node id, a pose, None: the robot) to ``goal`` (a node
        id or a pose): node ids both, else poses, a node-id goal standing for its node."""
        if isinstance(start, int) and isinstance(goal, int):
            return cls(False, start_id=start, goal_id=goal)
        begin = start if isinstance(start, Pose2D) else None
        if isinstance(goal, int):
            return cls(True, goal_id=goal, start=begin)
        return cls(True, start=begin, goal=goal)


@dataclass
class Rerouting:
    """What a tracked route carries into its next plan (Nav2's ``ReroutingState``).

    Attributes:
        blocked_ids: edge (or node) ids the next plan must avoid.
        start_id: the node to replan from (the last one reached), or None.
        start_pose: the robot's pose when the reroute was asked for.
        current_edge: the edge the robot was on, kept when the new route begins with it.
        closest_point: the robot's projection on ``current_edge`` (m).
        first_time: no plan was made yet for this goal.
    """

    blocked_ids: list[int] = field(default_factory=list)
    start_id: int | None = None
    start_pose: Pose2D | None = None
    current_edge: GraphEdge | None = None
    closest_point: tuple[float, float] = (0.0, 0.0)
    first_time: bool = True


class RoutePlanning:
    """Plans routes on one graph with the route server's settings.

    Args:
        graph: the indexed graph.
        params: settings.
        costmap: the global costmap now (edge scoring and node visibility), or None.
    """

    def __init__(
        self,
        graph: SearchGraph,
        params: RouteParams,
        costmap: Callable[[], Costmap2D] | None,
    ) -> None:
        self.graph = graph
        self.params = params
        self._costmap = costmap
        self.scorer = EdgeScorer(graph, params, costmap)

    def plan(self, request: RouteRequest, robot: Pose2D, rerouting: Rerouting) -> Route:
        """The route for ``request`` with the robot at ``robot``, pruned as Nav2 prunes it.

        Raises:
            NavigationError: ComputeRoute codes (INDETERMINANT_NODES_ON_GRAPH for an unknown
                node id, NO_VALID_ROUTE, NO_VALID_GRAPH, TIMEOUT).
        """
        start_id, goal_id, start_pose, goal_pose = self._extents(request, robot)
        if rerouting.start_id is not None and rerouting.start_pose is not None:
            start_id, start_pose = rerouting.start_id, rerouting.start_pose
        route = find_route(self.graph, self.scorer, start_id, goal_id, rerouting.blocked_ids)
        return self._prune(route, request, start_pose, goal_pose, rerouting)

    def _extents(self, request: RouteRequest, robot: Pose2D) -> tuple[int, int, Pose2D, Pose2D]:
        if not request.use_poses:
            self._check_ids(request.start_id, request.goal_id)
            start, goal = self.graph.node(request.start_id), self.graph.node(request.goal_id)
            return start.id, goal.id, _pose_at(start), _pose_at(goal)
        start_pose = request.start if request.start is not None else robot
        if request.goal is None:
            self._check_ids(request.goal_id)
            goal_node = self.graph.node(request.goal_id)
            return self._node_for(start_pose).id, goal_node.id, start_pose, _pose_at(goal_node)
        goal_pose = request.goal
        return self._node_for(start_pose).id, self._node_for(goal_pose).id, start_pose, goal_pose

    def _check_ids(self, *node_ids: int) -> None:
        for node_id in node_ids:
            if not self.graph.has_node(node_id):
                raise NavigationError(
                    ComputeRouteError.INDETERMINANT_NODES_ON_GRAPH,
                    f"no node of the route graph has id {node_id}",
                )

    def _node_for(self, pose: Pose2D) -> GraphNode:
        """The node a pose maps to: the nearest one in sight, else the nearest."""
        candidates = self.graph.nearest_nodes(pose.x, pose.y, self.params.num_nearest_nodes)
        grid = None if self._costmap is None else self._costmap()
        if grid is None:
            return candidates[0]
        for node in candidates:
            if not line_blocked(grid, (pose.x, pose.y), (node.x, node.y), self.params.max_cost):
                return node
        return candidates[0]

    def _prune(
        self,
        route: Route,
        request: RouteRequest,
        start: Pose2D,
        goal: Pose2D,
        rerouting: Rerouting,
    ) -> Route:
        last_edge, rerouting.current_edge = rerouting.current_edge, None
        first_time, rerouting.first_time = rerouting.first_time, False
        if not route.edges or (not request.use_poses and first_time):
            return route
        edges, cost, start_node = list(route.edges), route.cost, route.start
        first, after = start_node, self.graph.node(edges[0].end)
        closest = closest_point(start, first, after)
        if (
            _normalized_dot(
                after.x - first.x, after.y - first.y, start.x - first.x, start.y - first.y
            )
            > EPSILON
            and math.hypot(start.x - first.x, start.y - first.y)
            > self.params.min_prune_dist_from_start
            and math.dist(closest, (start.x, start.y)) <= self.params.max_prune_dist_from_edge
        ):
            if last_edge is not None and last_edge.id == edges[0].id:
                rerouting.closest_point = closest
                rerouting.current_edge = edges[0]
            cost -= self._score(edges[0])
            start_node = after
            edges.pop(0)
        if self.params.prune_goal and request.use_poses and edges:
            before, last = self.graph.node(edges[-1].start), self.graph.node(edges[-1].end)
            closest = closest_point(goal, before, last)
            if (
                _normalized_dot(
                    last.x - before.x, last.y - before.y, goal.x - last.x, goal.y - last.y
                )
                < -EPSILON
                and math.hypot(goal.x - last.x, goal.y - last.y)
                > self.params.min_prune_dist_from_goal
                and math.dist(closest, (goal.x, goal.y)) <= self.params.max_prune_dist_from_edge
            ):
                cost -= self._score(edges[-1])
                edges.pop()
        return Route(start_node, tuple(edges), max(cost, 0.0))

    def _score(self, edge: GraphEdge) -> float:
        score = self.scorer.score(edge)
        return 0.0 if score is None else score

    def densify(self, route: Route, rerouting: Rerouting) -> Path:
        """The dense path of ``route``, beginning with the rest of the edge the robot is on
        when a reroute kept it."""
        points: list[np.ndarray] = []
        if rerouting.current_edge is not None:
            end = self.graph.node(rerouting.current_edge.end)
            points.append(
                _interpolate(rerouting.closest_point, (end.x, end.y), self.params.path_density)
            )
        for edge in route.edges:
            start, end = self.graph.node(edge.start), self.graph.node(edge.end)
            points.append(
                _interpolate((start.x, start.y), (end.x, end.y), self.params.path_density)
            )
        goal = self.graph.node(route.goal_id)
        points.append(np.array([[goal.x, goal.y]]))
        xy = np.concatenate(points)
        if route.edges:
            last = route.edges[-1]
            before, after = self.graph.node(last.start), self.graph.node(last.end)
            final_yaw = math.atan2(after.y - before.y, after.x - before.x)
        else:
            final_yaw = 0.0
        return Path.from_points(xy, final_yaw)


def _interpolate(
    start: tuple[float, float], end: tuple[float, float], density: float
) -> np.ndarray:
    """Points from ``start`` towards ``end`` (m), ``end`` excluded, at most ``density`` apart."""
    length = math.dist(start, end)
    count = math.ceil(length / density)
    if count < 1:
        return np.empty((0, 2))
    steps = np.arange(count)[:, None] / count
    return np.asarray(start) + steps * (np.asarray(end) - np.asarray(start))


def _pose_at(node: GraphNode) -> Pose2D:
    return Pose2D(x=node.x, y=node.y)


def _normalized_dot(ax: float, ay: float, bx: float, by: float) -> float:
    norm_a, norm_b = math.hypot(ax, ay), math.hypot(bx, by)
    if norm_a < 1e-9 or norm_b < 1e-9:
        return 0.0
    return (ax * bx + ay * by) / (norm_a * norm_b)


def closest_point(pose: Pose2D, start: GraphNode, end: GraphNode) -> tuple[float, float]:
    """The point of the segment from ``start`` to ``end`` nearest to ``pose`` (m)."""
    dx, dy = end.x - start.x, end.y - start.y
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 == 0 else ((pose.x - start.x) * dx + (pose.y - start.y) * dy) / length2
    t = min(1.0, max(0.0, t))
    return start.x + t * dx, start.y + t * dy
