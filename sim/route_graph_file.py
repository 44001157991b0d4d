"""Route graph files: Nav2's GeoJSON graph of nodes and directed edges, read and checked.

The format is the one Nav2's route server loads (``GeoJsonGraphFileLoader``): a
``FeatureCollection`` whose ``Point`` features are nodes (``coordinates`` [x, y] in map metres,
``properties.id``) and whose ``LineString`` / ``MultiLineString`` features are edges
(``properties.id``, ``startid``, ``endid``, optional ``cost`` (default 0, meaning "let the
scorers decide"), ``overridable`` (default true); the edge's geometry is ignored, as Nav2
ignores it). Each may carry ``metadata`` (any JSON object) and ``operations`` (a mapping of
names to ``{type, trigger: NODE | ON_ENTER | ON_EXIT, metadata}``). Edges are directed: a
two-way lane is two edges. Ids are unsigned 16-bit (Nav2's message type) and unique across
nodes and edges together. A node's ``frame``, if given, must be ``map``.

Every mistake is a located error in the graph file: a dangling edge (an end id no node has),
a duplicate id, a missing or mistyped key. :mod:`baobab.sim.route_graph_geometry` adds the
world's geometry. This module is data only; what a route means to a robot is ``baobab.nav``'s.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from baobab.sim.errors import SourceError, WorldError
from baobab.sim.json_source import load_located_json
from baobab.sim.yaml_source import KeyPath, LocatedDocument

MAX_ID = 65_535
"""Largest node or edge id (``uint16`` in Nav2's route messages)."""
TRIGGERS = ("NODE", "ON_ENTER", "ON_EXIT")
"""When a graph operation runs: on achieving its node, on entering or on leaving its edge."""
MAP_FRAME = "map"


@dataclass(frozen=True)
class GraphOperation:
    """An operation a node or edge asks for: its ``name``, plugin ``type``, ``trigger``."""

    name: str
    type: str
    trigger: str
    metadata: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class GraphNode:
    """A node: ``id`` and position ``x``, ``y`` (m, map frame)."""

    id: int
    x: float
    y: float
    metadata: Mapping[str, Any] = field(default_factory=dict)
    operations: tuple[GraphOperation, ...] = ()


@dataclass(frozen=True)
class GraphEdge:
    """A directed edge from node ``start`` to node ``end`` (ids).

    ``cost`` is the file's cost (0: none given); ``overridable`` lets edge scorers replace it.
    """

    id: int
    start: int
    end: int
    cost: float = 0.0
    overridable: bool = True
    metadata: Mapping[str, Any] = field(default_factory=dict)
    operations: tuple[GraphOperation, ...] = ()


@dataclass(frozen=True)
class RouteGraph:
    """The nodes and edges of one graph file, in file order, and where each was written.

    Attributes:
        path: the file, as named.
        nodes: the nodes.
        edges: the edges.
        node_lines: (line, column) of each node's feature, by node id.
        edge_lines: (line, column) of each edge's feature, by edge id.
    """

    path: str
    nodes: tuple[GraphNode, ...]
    edges: tuple[GraphEdge, ...]
    node_lines: Mapping[int, tuple[int, int]] = field(default_factory=dict)
    edge_lines: Mapping[int, tuple[int, int]] = field(default_factory=dict)
    by_id: Mapping[int, GraphNode] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "by_id", {node.id: node for node in self.nodes})

    def node(self, node_id: int) -> GraphNode:
        """The node with id ``node_id`` (KeyError if none)."""
        return self.by_id[node_id]


def load_route_graph(path: str | Path) -> RouteGraph:
    """Read and check a GeoJSON route graph file.

    Raises:
        WorldError: located in the file: unreadable, not JSON, not a FeatureCollection, a
            feature of another geometry, a missing or mistyped key, an id outside 0..65535 or
            used twice, an edge whose ``startid`` or ``endid`` names no node, an edge from a
            node to itself, a negative cost, a frame other than ``map``, no nodes at all.
    """
    document = load_located_json(path, WorldError, what="a GeoJSON route graph file")
    return _GraphReader(document).read()


class _GraphReader:
    def __init__(self, document: LocatedDocument) -> None:
        self.document = document
        self.ids: dict[int, KeyPath] = {}

    def error(self, key_path: KeyPath, message: str) -> SourceError:
        return self.document.error(key_path, message, WorldError)

    def read(self) -> RouteGraph:
        data = self.document.data
        if not isinstance(data, dict) or data.get("type") != "FeatureCollection":
            raise self.error(("type",), 'a route graph is a GeoJSON {"type": "FeatureCollection"}')
        features = data.get("features")
        if not isinstance(features, list):
            raise self.error(("features",), "expected 'features': a list of GeoJSON features")
        nodes: list[GraphNode] = []
        edge_features: list[tuple[KeyPath, dict[str, Any]]] = []
        for index, feature in enumerate(features):
            where: KeyPath = ("features", index)
            properties = self.properties(feature, where)
            kind = feature["geometry"]["type"]
            if kind == "Point":
                nodes.append(self.node(feature, properties, where))
            else:
                edge_features.append((where, properties))
        if not nodes:
            raise self.error(("features",), "the graph has no nodes (Point features)")
        known = {node.id for node in nodes}
        edges = [self.edge(properties, where, known) for where, properties in edge_features]
        return RouteGraph(
            str(self.document.path),
            tuple(nodes),
            tuple(edges),
            {node.id: self.document.locate(self.ids[node.id]) for node in nodes},
            {edge.id: self.document.locate(self.ids[edge.id]) for edge in edges},
        )

    def properties(self, feature: Any, where: KeyPath) -> dict[str, Any]:
        if not isinstance(feature, dict) or feature.get("type") != "Feature":
            raise self.error(where, 'expected a GeoJSON {"type": "Feature"}')
        geometry = feature.get("geometry")
        kinds = ("Point", "LineString", "MultiLineString")
        if not isinstance(geometry, dict) or geometry.get("type") not in kinds:
            raise self.error(
                where + ("geometry",),
                "expected a geometry of type Point (a node) or LineString / MultiLineString "
                "(an edge)",
            )
        properties = feature.get("properties")
        if not isinstance(properties, dict):
            raise self.error(where + ("properties",), "expected 'properties': an object")
        return properties

    def identifier(self, properties: dict[str, Any], key: str, where: KeyPath) -> int:
        value = properties.get(key)
        if key not in properties:
            raise self.error(where + ("properties",), f"missing required key '{key}'")
        if not isinstance(value, int) or isinstance(value, bool) or not 0 <= value <= MAX_ID:
            raise self.error(
                where + ("properties", key), f"{key} {value!r}: expected an integer 0..{MAX_ID}"
            )
        return value

    def unique(self, properties: dict[str, Any], where: KeyPath) -> int:
        identifier = self.identifier(properties, "id", where)
        first = self.ids.get(identifier)
        if first is not None:
            line = self.document.locate(first)[0]
            raise self.error(
                where + ("properties", "id"),
                f"id {identifier} is used twice (first at line {line}); node and edge ids must "
                "all differ",
            )
        self.ids[identifier] = where
        return identifier

    def node(
        self, feature: dict[str, Any], properties: dict[str, Any], where: KeyPath
    ) -> GraphNode:
        identifier = self.unique(properties, where)
        coordinates = feature["geometry"].get("coordinates")
        at = where + ("geometry", "coordinates")
        if (
            not isinstance(coordinates, list)
            or len(coordinates) not in (2, 3)
            or not all(_is_number(value) for value in coordinates)
        ):
            raise self.error(at, "a node's coordinates are [x, y] in metres (finite numbers)")
        frame = properties.get("frame", MAP_FRAME)
        if frame != MAP_FRAME:
            raise self.error(
                where + ("properties", "frame"),
                f"frame {frame!r} cannot be transformed: route nodes must be in '{MAP_FRAME}'",
            )
        return GraphNode(
            identifier,
            float(coordinates[0]),
            float(coordinates[1]),
            self.metadata(properties, where),
            self.operations(properties, where),
        )

    def edge(self, properties: dict[str, Any], where: KeyPath, known: set[int]) -> GraphEdge:
        identifier = self.unique(properties, where)
        ends = []
        for key in ("startid", "endid"):
            node_id = self.identifier(properties, key, where)
            if node_id not in known:
                raise self.error(
                    where + ("properties", key),
                    f"edge {identifier} is dangling: its {key} {node_id} is no node's id",
                )
            ends.append(node_id)
        if ends[0] == ends[1]:
            raise self.error(
                where + ("properties", "endid"),
                f"edge {identifier} goes from node {ends[0]} to itself; expected two nodes",
            )
        cost = properties.get("cost", 0.0)
        if not _is_number(cost) or cost < 0:
            raise self.error(where + ("properties", "cost"), f"cost {cost!r}: expected >= 0")
        overridable = properties.get("overridable", True)
        if not isinstance(overridable, bool):
            raise self.error(
                where + ("properties", "overridable"), "overridable: expected true or false"
            )
        return GraphEdge(
            identifier,
            ends[0],
            ends[1],
            float(cost),
            overridable,
            self.metadata(properties, where),
            self.operations(properties, where),
        )

    def metadata(self, properties: dict[str, Any], where: KeyPath) -> dict[str, Any]:
        metadata = properties.get("metadata", {})
        if not isinstance(metadata, dict):
            raise self.error(where + ("properties", "metadata"), "metadata: expected an object")
        return metadata

    def operations(self, properties: dict[str, Any], where: KeyPath) -> tuple[GraphOperation, ...]:
        operations = properties.get("operations", {})
        at = where + ("properties", "operations")
        if not isinstance(operations, dict):
            raise self.error(at, "operations: expected an object of named operations")
        found = []
        for name, spec in operations.items():
            if not isinstance(spec, dict) or not isinstance(spec.get("type"), str):
                raise self.error(at + (name,), f"operation '{name}' needs a 'type' (a string)")
            trigger = spec.get("trigger")
            if trigger not in TRIGGERS:
                raise self.error(
                    at + (name, "trigger"),
                    f"operation '{name}' trigger {trigger!r}: expected one of "
                    + ", ".join(TRIGGERS),
                )
            metadata = spec.get("metadata", {})
            if not isinstance(metadata, dict):
                raise self.error(at + (name, "metadata"), "metadata: expected an object")
            found.append(GraphOperation(name, spec["type"], trigger, metadata))
        return tuple(found)


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
