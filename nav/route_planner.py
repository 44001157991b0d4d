"""Nav2's route planner: edge scoring and Dijkstra's search over the route graph.

Each edge's traversal cost is the sum of its scorers' (nav2_bringup's pair): the
DistanceScorer, the edge's length divided by its ``speed_limit`` metadata (a fraction, 1 when
absent), and the CostmapScorer, the highest cost under the edge over ``max_cost`` (253) on the
global costmap. An edge that runs off the costmap or over a cell of ``max_cost`` or more (an
obstacle, or closer to one than the robot's inscribed radius) is invalid and never expanded.
An edge with ``overridable: false`` costs what its file says, which must then be positive, as
in Nav2. Blocked ids (edges, or nodes that may not be entered) are skipped.

Errors are Nav2's ComputeRoute codes: NO_VALID_ROUTE when the goal cannot be reached,
NO_VALID_GRAPH for an edge without a usable cost, TIMEOUT when ``max_iterations`` is spent.
"""

from __future__ import annotations

import heapq
import itertools
import math
from collections.abc import Callable, Collection

import numpy as np

from baobab.nav.costmap import NO_INFORMATION, Costmap2D
from baobab.nav.errors import ComputeRouteError, NavigationError
from baobab.nav.route_graph import Route, RouteParams, SearchGraph
from baobab.sim.route_graph_file import GraphEdge

SPEED_LIMIT_KEY = "speed_limit"
"""Edge metadata read by the DistanceScorer: the fraction of full speed allowed."""


def line_costs(
    costmap: Costmap2D, start: tuple[float, float], end: tuple[float, float]
) -> np.ndarray:
    """Costs of the cells under the segment from ``start`` to ``end`` (m), half a cell apart;
    :data:`NO_INFORMATION` where the segment leaves the grid."""
    length = math.hypot(end[0] - start[0], end[1] - start[1])
    count = max(2, math.ceil(2 * length / costmap.resolution) + 1)
    xs = np.linspace(start[0], end[0], count)
    ys = np.linspace(start[1], end[1], count)
    return costmap.costs(xs, ys)


def line_blocked(
    costmap: Costmap2D, start: tuple[float, float], end: tuple[float, float], max_cost: int
) -> bool:
    """True when a cell under the segment from ``start`` to ``end`` (m) costs ``max_cost`` or
    more; where the segment leaves the grid nothing blocks it."""
    costs = line_costs(costmap, start, end)
    return bool(((costs >= max_cost) & (costs != NO_INFORMATION)).any())


class EdgeScorer:
    """Scores edges for the search; None means the edge may not be used.

    Args:
        graph: the graph.
        params: the route server settings.
        costmap: the global costmap now (None: no CostmapScorer).
    """

    def __init__(
        self,
        graph: SearchGraph,
        params: RouteParams,
        costmap: Callable[[], Costmap2D] | None,
    ) -> None:
        self.graph = graph
        self.params = params
        self._costmap = costmap if params.use_costmap_scorer else None
        self._grid: Costmap2D | None = None

    def prepare(self) -> None:
        """Take the latest costmap before a search (Nav2's ``prepare``)."""
        self._grid = None if self._costmap is None else self._costmap()

    def score(self, edge: GraphEdge) -> float | None:
        """The traversal cost of ``edge``, or None when it is invalid now.

        Raises:
            NavigationError: NO_VALID_GRAPH for a non-overridable edge whose cost is not
                positive.
        """
        if not edge.overridable:
            if edge.cost <= 0:
                raise NavigationError(
                    ComputeRouteError.NO_VALID_GRAPH,
                    f"edge {edge.id} doesn't contain and cannot compute a valid edge cost",
                )
            return edge.cost
        limit = edge.metadata.get(SPEED_LIMIT_KEY, 1.0)
        if not isinstance(limit, int | float) or isinstance(limit, bool):
            limit = 1.0
        if limit <= 0:
            return None
        score = self.graph.edge_length(edge) / float(limit)
        grid = self._grid
        if grid is None:
            return score
        start, end = self.graph.node(edge.start), self.graph.node(edge.end)
        if not (grid.contains(start.x, start.y) and grid.contains(end.x, end.y)):
            return None  # invalid_off_map
        costs = line_costs(grid, (start.x, start.y), (end.x, end.y))
        known = costs[costs != NO_INFORMATION]
        if known.size and int(known.max()) >= self.params.max_cost:
            return None  # invalid_on_collision
        return score + (float(known.max()) if known.size else 0.0) / self.params.max_cost


def find_route(
    graph: SearchGraph,
    scorer: EdgeScorer,
    start_id: int,
    goal_id: int,
    blocked_ids: Collection[int] = (),
) -> Route:
    """The cheapest route from node ``start_id`` to node ``goal_id`` (Dijkstra's search).

    A start equal to the goal is a route of that node alone, at cost 0.

    Raises:
        NavigationError: NO_VALID_ROUTE (unreachable), NO_VALID_GRAPH (an edge without a
            cost), TIMEOUT (``max_iterations`` expansions done).
    """
    start = graph.node(start_id)
    if start_id == goal_id:
        return Route(start)
    scorer.prepare()
    max_iterations = scorer.params.max_iterations or math.inf
    best: dict[int, float] = {start_id: 0.0}
    parent: dict[int, GraphEdge] = {}
    order = itertools.count()
    queue: list[tuple[float, int, int]] = [(0.0, next(order), start_id)]
    blocked = set(blocked_ids)
    iterations = 0
    while queue and iterations < max_iterations:
        iterations += 1
        cost, _, node_id = heapq.heappop(queue)
        if cost != best.get(node_id):
            continue  # a stale entry: the node was reached more cheaply since
        if node_id == goal_id:
            return Route(start, _edges_to(parent, goal_id, start_id), cost)
        for edge in graph.outgoing[node_id]:
            if edge.id in blocked or edge.end in blocked:
                continue
            score = scorer.score(edge)
            if score is None:
                continue
            candidate = cost + score
            if candidate < best.get(edge.end, math.inf):
                best[edge.end] = candidate
                parent[edge.end] = edge
                heapq.heappush(queue, (candidate, next(order), edge.end))
    if queue and iterations >= max_iterations:
        raise NavigationError(ComputeRouteError.TIMEOUT, "Maximum iterations was exceeded!")
    raise NavigationError(
        ComputeRouteError.NO_VALID_ROUTE,
        f"Could not find a route to the requested goal! (node {start_id} to node {goal_id})",
    )


def _edges_to(parent: dict[int, GraphEdge], goal_id: int, start_id: int) -> tuple[GraphEdge, ...]:
    edges: list[GraphEdge] = []
    node_id = goal_id
    while node_id != start_id:
        edge = parent[node_id]
        edges.append(edge)
        node_id = edge.start
    return tuple(reversed(edges))
