"""The route server's graph, its settings, and a route on it (Nav2's ``nav2_route`` types).

:class:`SearchGraph` indexes a :class:`~baobab.sim.route_graph_file.RouteGraph` for search:
each node's outgoing edges, node positions for nearest-node queries. A :class:`Route` is what
the planner returns: a start node and the edges to follow, with its cost. :class:`RouteParams`
holds the route server's parameters with Nav2's defaults (reference/nav2_ros_facts.md §8), and
nav2_bringup's where the two differ (the edge scorers, the collision monitor operation).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from baobab.sim.route_graph_file import GraphEdge, GraphNode, RouteGraph


@dataclass(frozen=True)
class RouteParams:
    """Route server settings (m, s, Hz), Nav2's names.

    The edge scorers are bringup's DistanceScorer and CostmapScorer (``use_costmap_scorer``;
    ``max_cost`` 253, the maximum along the edge); the tracker's operations are the
    ReroutingService and the CollisionMonitor (bringup's ``max_collision_dist`` 3.0, on the
    local costmap, at ``collision_check_rate``). ``smooth_corners`` is off, the path
    converter's own default.
    """

    path_density: float = 0.05
    max_iterations: int = 0
    use_costmap_scorer: bool = True
    max_cost: int = 253
    tracker_update_rate: float = 50.0
    radius_to_achieve_node: float = 2.0
    boundary_radius_to_achieve_node: float = 1.0
    aggregate_blocked_ids: bool = False
    max_prune_dist_from_edge: float = 8.0
    min_prune_dist_from_goal: float = 0.15
    min_prune_dist_from_start: float = 0.10
    prune_goal: bool = True
    num_nearest_nodes: int = 5
    collision_monitor: bool = True
    collision_check_rate: float = 1.0
    max_collision_dist: float = 3.0
    reroute_on_collision: bool = True


@dataclass(frozen=True)
class Route:
    """A route: ``start`` node id, then ``edges`` in order; ``cost`` is their summed score."""

    start: GraphNode
    edges: tuple[GraphEdge, ...] = ()
    cost: float = 0.0

    def node_ids(self) -> list[int]:
        """The ids of the nodes the route passes, start first."""
        return [self.start.id, *(edge.end for edge in self.edges)]

    @property
    def goal_id(self) -> int:
        """The last node's id."""
        return self.edges[-1].end if self.edges else self.start.id


@dataclass
class SearchGraph:
    """A route graph indexed for search.

    Attributes:
        graph: the graph as read from its file.
        outgoing: each node id's outgoing edges, in file order.
        positions: ``(N, 2)`` node positions (m), in the order of ``graph.nodes``.
    """

    graph: RouteGraph
    outgoing: dict[int, list[GraphEdge]] = field(init=False)
    positions: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        self.outgoing = {node.id: [] for node in self.graph.nodes}
        for edge in self.graph.edges:
            self.outgoing[edge.start].append(edge)
        self.positions = np.array([[node.x, node.y] for node in self.graph.nodes], dtype=float)

    def node(self, node_id: int) -> GraphNode:
        """The node with id ``node_id`` (KeyError if none)."""
        return self.graph.node(node_id)

    def has_node(self, node_id: int) -> bool:
        """Whether a node has id ``node_id``."""
        return node_id in self.outgoing

    def edge_length(self, edge: GraphEdge) -> float:
        """Straight-line length of ``edge`` (m)."""
        start, end = self.node(edge.start), self.node(edge.end)
        return math.hypot(end.x - start.x, end.y - start.y)

    def nearest_nodes(self, x: float, y: float, count: int) -> list[GraphNode]:
        """The ``count`` nodes nearest to (x, y) (m), nearest first (ties in file order)."""
        distances = np.hypot(self.positions[:, 0] - x, self.positions[:, 1] - y)
        order = np.argsort(distances, kind="stable")[: max(1, count)]
        return [self.graph.nodes[int(index)] for index in order]
