"""The ``follow_route`` leaf: drive the world's (or the mission's) Nav2 route graph.

What Nav2's route behaviour trees do with ComputeAndTrackRoute: plan the cheapest route on the
graph, follow its dense path with the controller (joining the robot to the route's start and
the route's end to a goal pose with the planner where needed), and reroute from the last node
reached when the route server's collision monitor finds an edge ahead blocked. ``goal`` and
``start`` are node ids, location names or poses; without ``start`` the route begins at the
robot. The leaf fails with the route server's code (4xx) when no route exists, or with the
controller's or planner's. Node ids are checked against the graph while the mission loads.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated

from pydantic import Field, ValidationInfo, model_validator

from baobab.behaviours.ports import NAVIGATION
from baobab.behaviours.poses import GoalPose, MissionScope, Pose, PoseRef
from baobab.behaviours.registry import BehaviourType, BuildRequest, NodeKind, NodeParams
from baobab.sim.route_graph_file import MAX_ID
from baobab.sim.yaml_source import FieldValueError

if TYPE_CHECKING:  # imported by the factory, when a tree is built (validation needs none)
    import py_trees

NodeId = Annotated[int, Field(ge=0, le=MAX_ID, description="a route graph node id")]


class FollowRouteParams(NodeParams):
    """Drive the route graph from ``start`` (default: the robot) to ``goal``."""

    goal: NodeId | GoalPose = Field(description="node id, location name or pose")
    start: NodeId | PoseRef | None = Field(
        default=None, description="node id, location name or pose; default: the robot's pose"
    )

    @model_validator(mode="after")
    def _on_the_graph(self, info: ValidationInfo) -> FollowRouteParams:
        world = MissionScope.of(info).world
        if world is None:
            return self
        graph = world.routes
        if graph is None:
            raise FieldValueError(
                ("goal",),
                f"world '{world.name}' has no route graph; name one with route_graph: in the "
                "world or the mission",
            )
        for key in ("goal", "start"):
            value = getattr(self, key)
            if isinstance(value, int) and value not in graph.by_id:
                known = ", ".join(str(node.id) for node in graph.nodes[:12])
                raise FieldValueError(
                    (key,), f"no node of the route graph has id {value}; its nodes: {known}"
                )
        if isinstance(self.start, int) and not isinstance(self.goal, int):
            raise FieldValueError(
                ("goal",),
                "start is a node id, so goal must be one too (Nav2's routes go between two "
                "node ids or two poses); give start as a pose or leave it out",
            )
        return self

    def summary(self) -> str:
        """``node 3 -> node 7``."""
        ends = [_where(self.start), _where(self.goal)] if self.start is not None else []
        return " -> ".join(ends) if ends else f"to {_where(self.goal)}"


def _where(end: int | Pose | None) -> str:
    if isinstance(end, Pose):
        return end.location or f"({end.x:.2f}, {end.y:.2f})"
    return f"node {end}"


def _follow_route(request: BuildRequest) -> py_trees.behaviour.Behaviour:
    params = request.params_as(FollowRouteParams)
    start = params.start.pose2d() if isinstance(params.start, Pose) else params.start
    goal = params.goal.pose2d() if isinstance(params.goal, Pose) else params.goal
    return request.goal_task(lambda caps: caps.navigation_port().follow_route(start, goal))


NODE_TYPES = (
    BehaviourType(
        "follow_route",
        NodeKind.ACTION,
        FollowRouteParams,
        "drive the route graph to a node or pose, rerouting round blocked edges",
        _follow_route,
        capability=NAVIGATION,
        shorthand="goal",
    ),
)
"""The route graph node types."""
