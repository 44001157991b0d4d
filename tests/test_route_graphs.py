"""Route graphs (issue 26): Nav2's GeoJSON graph files with located errors, the route planner
against a brute-force search, getRoute's route and dense path, and getAndTrackRoute's tracking
and rerouting round a blocked edge, on real physics in the lanes test world.

The lanes world (tests/missions/worlds/lanes.yaml) is a loop of six nodes round an island:
from node 1 (west) to node 4 (east) the north side (1 -> 2 -> 3 -> 4, 6.61 m) is shorter
than the south side (1 -> 6 -> 5 -> 4, 7.47 m).
"""

from __future__ import annotations

import itertools
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from navigation_rig import ContactWatch

from baobab.missions.cli.command_line import main
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.nav import BasicNavigator, RunningTask, TaskResult
from baobab.nav.errors import ComputeRouteError, NavigationError
from baobab.nav.msgs import pose_stamped
from baobab.nav.route_graph import RouteParams, SearchGraph
from baobab.nav.route_planner import EdgeScorer, find_route
from baobab.sim.builder import movable_slot_name
from baobab.sim.errors import WorldError
from baobab.sim.route_graph_file import GraphEdge, GraphNode, RouteGraph, load_route_graph
from baobab.sim.tasks import TaskStatus
from baobab.sim.world import load_world

WORLDS = Path(__file__).parent / "missions" / "worlds"
LANES = WORLDS / "lanes.yaml"
NORTH = [1, 2, 3, 4]
SOUTH = [1, 6, 5, 4]


# -- graph files -----------------------------------------------------------------------------


def node(node_id: int, x: float, y: float, **properties: Any) -> dict[str, Any]:
    return {
        "type": "Feature",
        "properties": {"id": node_id, **properties},
        "geometry": {"type": "Point", "coordinates": [x, y]},
    }


def edge(edge_id: int, start: int, end: int, **properties: Any) -> dict[str, Any]:
    return {
        "type": "Feature",
        "properties": {"id": edge_id, "startid": start, "endid": end, **properties},
        "geometry": {"type": "LineString", "coordinates": [[0, 0], [1, 1]]},
    }


def write_graph(path: Path, features: list[dict[str, Any]]) -> Path:
    """One feature a line, so that a feature's line number is its index + 3."""
    body = ",\n".join(json.dumps(feature) for feature in features)
    path.write_text(f'{{"type": "FeatureCollection",\n"features": [\n{body}\n]}}\n')
    return path


TWO_NODES = [node(1, 0.0, 0.0), node(2, 1.0, 0.0)]


@pytest.mark.parametrize(
    ("features", "where", "message"),
    [
        ([*TWO_NODES, edge(3, 1, 9)], (5, 1), "edge 3 is dangling: its endid 9 is no node's id"),
        ([*TWO_NODES, edge(3, 7, 2)], (5, 1), "edge 3 is dangling: its startid 7 is no node's id"),
        ([*TWO_NODES, node(2, 3.0, 0.0)], (5, 1), "id 2 is used twice (first at line 4)"),
        ([*TWO_NODES, edge(1, 1, 2)], (5, 1), "id 1 is used twice (first at line 3)"),
        ([*TWO_NODES, edge(3, 1, 1)], (5, 1), "edge 3 goes from node 1 to itself"),
        ([*TWO_NODES, edge(3, 1, 2, cost=-1)], (5, 1), "cost -1: expected >= 0"),
        ([node(70000, 0.0, 0.0)], (3, 1), "id 70000: expected an integer 0..65535"),
        ([node(1, 0.0, 0.0, frame="odom")], (3, 1), "frame 'odom' cannot be transformed"),
        (
            [*TWO_NODES, edge(3, 1, 2, operations={"stop": {"type": "x", "trigger": "NOW"}})],
            (5, 1),
            "operation 'stop' trigger 'NOW': expected one of NODE, ON_ENTER, ON_EXIT",
        ),
        ([edge(3, 1, 2)], (2, 1), "the graph has no nodes"),
    ],
)
def test_a_bad_graph_file_is_a_located_error(
    tmp_path: Path, features: list[dict[str, Any]], where: tuple[int, int], message: str
) -> None:
    path = write_graph(tmp_path / "graph.geojson", features)
    with pytest.raises(WorldError) as caught:
        load_route_graph(path)
    text = str(caught.value)
    assert text.startswith(f"{path}:{where[0]}:"), text
    assert message in text


@pytest.mark.parametrize(
    ("text", "where", "message"),
    [
        ('{"type": "FeatureCollection", "features": [],}', (1, 46), "JSON syntax error"),
        ('{"type": "FeatureCollection",\n "features": [NaN]}', (2, 15), "NaN is not a number"),
        ('{"type": "FeatureCollection", "type": "x"}', (1, 31), "duplicate key 'type'"),
        ('{"type": "Topology"}', (1, 2), "a route graph is a GeoJSON"),
    ],
)
def test_a_graph_file_that_is_not_a_feature_collection_is_a_located_error(
    tmp_path: Path, text: str, where: tuple[int, int], message: str
) -> None:
    path = tmp_path / "graph.geojson"
    path.write_text(text)
    with pytest.raises(WorldError) as caught:
        load_route_graph(path)
    assert str(caught.value).startswith(f"{path}:{where[0]}:{where[1]}: "), str(caught.value)
    assert message in str(caught.value)


def lanes_world_with(tmp_path: Path, features: list[dict[str, Any]]) -> Path:
    text = LANES.read_text().replace("lanes.geojson", "graph.geojson")
    write_graph(tmp_path / "graph.geojson", features)
    (tmp_path / "lanes.yaml").write_text(text)
    return tmp_path / "lanes.yaml"


def test_a_graph_the_world_makes_impossible_is_a_located_error(tmp_path: Path) -> None:
    inside = [node(1, -2.5, 0.0), node(2, 0.5, 0.2)]
    with pytest.raises(WorldError, match=r"graph.geojson:4:1: node 2 at \(0.5, 0.2\) is inside "):
        load_world(lanes_world_with(tmp_path, inside))
    off = [node(1, -2.5, 0.0), node(2, 4.5, 0.0)]
    with pytest.raises(WorldError, match=r"graph.geojson:4:1: node 2 at \(4.5, 0\) is outside "):
        load_world(lanes_world_with(tmp_path, off))
    across = [node(1, -2.5, 0.0), node(2, 2.5, 0.0), edge(3, 1, 2)]
    with pytest.raises(
        WorldError, match=r"graph.geojson:5:1: edge 3 from node 1 to node 2 passes through obstacle"
    ):
        load_world(lanes_world_with(tmp_path, across))
    (tmp_path / "graph.geojson").unlink()
    with pytest.raises(WorldError, match=r"lanes.yaml:\d+:1: route graph file .* not found"):
        load_world(tmp_path / "lanes.yaml")


def test_a_missions_dangling_edge_fails_validation_with_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    write_graph(tmp_path / "lanes.geojson", [node(1, -2.5, 0.0), node(2, -1.5, 1.5), edge(3, 1, 9)])
    for name in ("lanes.yaml",):
        (tmp_path / name).write_text((WORLDS / name).read_text().replace("route_graph: ", "# "))
    mission = tmp_path / "mission.yaml"
    mission.write_text(
        "mission: m\nworld: lanes.yaml\nroute_graph: lanes.geojson\nrobot: turtlebot3\n"
        "tree: {follow_route: 2}\n"
    )
    assert main(["validate", str(mission)]) == 2
    printed = capsys.readouterr()
    assert f"{tmp_path / 'lanes.geojson'}:5:59: " in printed.err + printed.out
    assert "edge 3 is dangling: its endid 9 is no node's id" in printed.err + printed.out
    # Mended, the mission's graph takes the world's place (a world without one of its own).
    lane = [node(1, -2.5, 0.0), node(2, -1.5, 1.5), edge(3, 1, 2)]
    write_graph(tmp_path / "lanes.geojson", lane)
    loaded = load_mission(mission)
    assert loaded.world is not None and loaded.world.routes is not None
    assert [n.id for n in loaded.world.routes.nodes] == [1, 2]
    assert load_world(tmp_path / "lanes.yaml").routes is None
    mission.write_text(mission.read_text().replace("follow_route: 2", "follow_route: 5"))
    with pytest.raises(MissionError, match=r"mission.yaml:5:\d+: .*no node of the route graph"):
        load_mission(mission)


# -- the planner against brute force ---------------------------------------------------------


def random_graph(rng: np.random.Generator, nodes: int, edges: int) -> RouteGraph:
    """Random nodes in a 10 m square and random directed edges: some with a speed limit, some
    with a fixed cost (not overridable)."""
    found = [GraphNode(i, *rng.uniform(0, 10, 2)) for i in range(nodes)]
    pairs = [(a, b) for a in range(nodes) for b in range(nodes) if a != b]
    chosen = rng.choice(len(pairs), size=edges, replace=False)
    links = []
    for number, index in enumerate(chosen):
        start, end = pairs[int(index)]
        kind = rng.integers(3)
        links.append(
            GraphEdge(
                100 + number,
                start,
                end,
                cost=float(rng.uniform(0.5, 8.0)) if kind == 2 else 0.0,
                overridable=kind != 2,
                metadata={"speed_limit": float(rng.uniform(0.3, 1.0))} if kind == 1 else {},
            )
        )
    return RouteGraph("random", tuple(found), tuple(links))


def brute_force(
    graph: SearchGraph, scorer: EdgeScorer, start: int, goal: int, blocked: set[int]
) -> float | None:
    """The cheapest cost over every simple path from ``start`` to ``goal`` (None: no path)."""
    best: float | None = None

    def walk(node_id: int, seen: set[int], cost: float) -> None:
        nonlocal best
        if node_id == goal:
            best = cost if best is None else min(best, cost)
            return
        for link in graph.outgoing[node_id]:
            if link.id in blocked or link.end in blocked or link.end in seen:
                continue
            score = scorer.score(link)
            if score is not None:
                walk(link.end, seen | {link.end}, cost + score)

    walk(start, {start}, 0.0)
    return best


def check_route(graph: SearchGraph, scorer: EdgeScorer, start: int, goal: int, blocked: set[int]):
    expected = brute_force(graph, scorer, start, goal, blocked)
    if expected is None:
        with pytest.raises(NavigationError) as caught:
            find_route(graph, scorer, start, goal, blocked)
        assert caught.value.code == ComputeRouteError.NO_VALID_ROUTE
        return None
    route = find_route(graph, scorer, start, goal, blocked)
    assert route.cost == pytest.approx(expected, abs=1e-9)
    assert route.node_ids()[0] == start and route.goal_id == goal
    assert all(a.end == b.start for a, b in itertools.pairwise(route.edges))
    assert not {link.id for link in route.edges} & blocked
    assert sum(scorer.score(link) or math.inf for link in route.edges) == pytest.approx(route.cost)
    return route


@pytest.mark.parametrize("seed", range(6))
def test_the_cheapest_route_is_the_brute_force_optimum_on_random_graphs(seed: int) -> None:
    rng = np.random.default_rng(seed)
    graph = SearchGraph(random_graph(rng, nodes=8, edges=22))
    scorer = EdgeScorer(graph, RouteParams(use_costmap_scorer=False), None)
    unreachable = 0
    for start, goal in itertools.permutations(range(8), 2):
        blocked = {int(b) for b in rng.choice(122, size=2)} if (start + goal) % 3 == 0 else set()
        unreachable += check_route(graph, scorer, start, goal, blocked) is None
    assert unreachable < 56  # some routes exist: the check is not vacuous


def test_the_town_graph_routes_are_the_brute_force_optima() -> None:
    town = load_world("town")
    assert town.routes is not None
    graph = SearchGraph(town.routes)
    scorer = EdgeScorer(graph, RouteParams(use_costmap_scorer=False), None)
    for start, goal in itertools.permutations([1, 3, 6, 11, 14, 16, 21, 22], 2):
        assert check_route(graph, scorer, start, goal, set()) is not None
    # The north lane's speed limit (0.9) makes the south lane the cheaper way east.
    route = find_route(graph, scorer, 3, 22)
    assert route.node_ids() == [3, 13, 14, 15, 22]
    blocked = check_route(graph, scorer, 14, 22, {next(e.id for e in route.edges if e.start == 14)})
    assert blocked is not None and blocked.node_ids() == [14, 4, 5, 15, 22]


def test_max_iterations_gives_timeout() -> None:
    graph = SearchGraph(load_world("town").routes)  # type: ignore[arg-type]
    scorer = EdgeScorer(graph, RouteParams(use_costmap_scorer=False, max_iterations=3), None)
    with pytest.raises(NavigationError) as caught:
        find_route(graph, scorer, 1, 16)
    assert caught.value.code == ComputeRouteError.TIMEOUT


# -- getRoute and getAndTrackRoute on real physics -------------------------------------------


def node_ids(route: Any) -> list[int]:
    return [node.nodeid for node in route.nodes]


def test_get_route_gives_the_shortest_route_and_its_dense_path(lanes: BasicNavigator) -> None:
    found = lanes.getRoute(1, 4)
    assert found is not None, lanes.getTaskError()
    path, route = found
    assert node_ids(route) == NORTH
    assert [e.edgeid for e in route.edges] == [10, 12, 14]
    length = math.hypot(1.0, 1.5) * 2 + 3.0
    assert route.route_cost == pytest.approx(length, abs=0.05)  # plus the costmap's share
    xy = np.array([[p.pose.position.x, p.pose.position.y] for p in path.poses])
    steps = np.hypot(*np.diff(xy, axis=0).T)
    assert steps.max() <= 0.05 + 1e-9 and steps.min() > 0.03
    assert steps.sum() == pytest.approx(length, abs=1e-6)
    assert tuple(xy[0]) == (-2.5, 0.0) and tuple(xy[-1]) == (2.5, 0.0)
    # From poses: the nearest nodes in sight, and the route pruned as Nav2 prunes it: a start
    # already along the first edge (more than 0.1 m from node 1) drops that edge; a goal
    # short of the last node keeps the last edge.
    found = lanes.getRoute(pose_stamped(-2.5, 0.05), pose_stamped(2.4, -0.2), use_start=True)
    assert found is not None and node_ids(found[1]) == NORTH
    found = lanes.getRoute(pose_stamped(-2.4, 0.1), pose_stamped(2.4, -0.2), use_start=True)
    assert found is not None and node_ids(found[1]) == NORTH[1:]
    # Unknown node ids and unreachable goals give Nav2's codes.
    assert lanes.getRoute(1, 99) is None
    assert lanes.getTaskError()[0] == ComputeRouteError.INDETERMINANT_NODES_ON_GRAPH


def example_route(navigator: BasicNavigator, goal: int, limit: float) -> list[Any]:
    """Nav2's example_route.py: track a route and follow each new route's path; the
    feedback messages in order."""
    task = navigator.getAndTrackRoute(1, goal)
    assert task is RunningTask.COMPUTE_AND_TRACK_ROUTE
    messages: list[Any] = []
    sim = navigator.server.sim
    end = sim.time + limit
    while not navigator.isTaskComplete(task=RunningTask.COMPUTE_AND_TRACK_ROUTE):
        assert sim.time < end, "route still tracked"
        while (
            feedback := navigator.getFeedback(task=RunningTask.COMPUTE_AND_TRACK_ROUTE)
        ) is not None:
            messages.append(feedback)
            if feedback.rerouted:
                navigator.followPath(feedback.path)
    while (feedback := navigator.getFeedback(task=RunningTask.COMPUTE_AND_TRACK_ROUTE)) is not None:
        messages.append(feedback)
    while not navigator.isTaskComplete():  # the path's end: the tracker is done 1 m before
        assert sim.time < end, "path still followed"
    return messages


def test_a_tracked_route_reports_each_node_reached_and_its_next_edge(
    lanes: BasicNavigator,
) -> None:
    spawn = lanes.world.spawn
    lanes.setInitialPose(pose_stamped(spawn.x, spawn.y, spawn.yaw))
    messages = example_route(lanes, 4, 120.0)
    assert lanes.getResult() is TaskResult.SUCCEEDED, lanes.getTaskError()
    assert [node_ids(m.route) for m in messages if m.rerouted] == [NORTH]
    progress = [(m.last_node_id, m.next_node_id, m.current_edge_id) for m in messages[1:]]
    assert progress == [(1, 2, 10), (2, 3, 12), (3, 4, 14), (4, 0, 0)]
    assert all(not m.rerouted and not m.operations_triggered for m in messages[1:])
    pose = lanes.robot_pose()
    assert math.hypot(pose.x - 2.5, pose.y) < 0.3


def test_a_driven_route_reroutes_round_a_blocked_edge(lanes: BasicNavigator) -> None:
    """The follow_route task (the mission leaf's): a box on edge 12 (node 2 -> node 3) comes
    into the local costmap; the collision monitor blocks the edge and the route is planned
    again from the last node reached, round the south side; the planner joins the robot to
    the new route's start."""
    server, sim = lanes.server, lanes.server.sim
    spawn = lanes.world.spawn
    lanes.setInitialPose(pose_stamped(spawn.x, spawn.y, spawn.yaw))
    watch = ContactWatch(sim, server.base.names.body)  # type: ignore[attr-defined]
    body = sim.model.body(movable_slot_name(0))
    sim.data.mocap_pos[body.mocapid[0]] = [0.0, 1.5, 0.25]
    try:
        handle = server.follow_route(1, 4)
        end = sim.time + 150.0
        while not handle.status.done:
            assert sim.time < end, "route still driven"
            sim.step_for(0.5)
    finally:
        sim.data.mocap_pos[body.mocapid[0]] = [100.0, 0.0, 0.25]
    assert handle.status is TaskStatus.SUCCEEDED, handle.outcome
    feedback = handle.feedback
    assert feedback["reroutes"] == 1
    assert feedback["route_nodes"][-3:] == [6, 5, 4]
    assert feedback["nodes_reached"][-3:] == [6, 5, 4] and 3 not in feedback["nodes_reached"]
    assert feedback["last_node_id"] == 4
    assert not watch.touched
    pose = lanes.robot_pose()
    assert math.hypot(pose.x - 2.5, pose.y) < 0.3
