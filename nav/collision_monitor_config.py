"""Reading a ``collision_monitor:`` block into Nav2's collision monitor parameters.

:func:`parse_collision_monitor` checks one mapping (the format is in
:mod:`baobab.nav.collision_monitor_params`) and returns
:class:`~baobab.nav.collision_monitor_params.CollisionMonitorParams`; each mistake is a
:class:`~baobab.nav.collision_monitor_params.CollisionMonitorConfigError` that names the key
path, so a file's loader can locate it. A dynamic polygon (``polygon_sub_topic``) and sources
other than the lidar's ``scan`` are refused. Layers (the world's block, then the mission's or
the navigator's) merge parameter by parameter, as Nav2's parameter files do
(:func:`merge_layers`), and
:func:`layered_collision_monitor` checks the result against the robot's footprint (an
``approach`` zone must hold the robot). Nothing here loads numpy: ``baobab validate`` uses it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from baobab.nav.collision_monitor_geometry import (
    Point,
    contains_footprint,
    describe_footprint,
    parse_points,
    polygon_problem,
)
from baobab.nav.collision_monitor_params import (
    ACTION_TYPES,
    BOOLEAN,
    INTEGER,
    NAMES,
    NODE_PARAMETERS,
    NUMBER,
    OTHER_SOURCE_TYPES,
    POLYGON_PARAMETERS,
    POLYGON_TYPES,
    SCAN_TOPICS,
    SOURCE_PARAMETERS,
    STRING,
    VELOCITY_SUBPOLYGON_PARAMETERS,
    ActionType,
    CollisionMonitorConfigError,
    CollisionMonitorParams,
    KeyPath,
    PolygonParams,
    SourceParams,
    VelocityPolygon,
)
from baobab.robots.catalog import RobotInfo
from baobab.robots.footprint import Footprint
from baobab.sim.errors import unknown_name


def parse_collision_monitor(data: Any) -> CollisionMonitorParams:
    """Read a ``collision_monitor:`` mapping (see the module docstring).

    Raises:
        CollisionMonitorConfigError: the first mistake, with its key path.
    """
    node = _Block(data, (), "collision_monitor", NODE_PARAMETERS, named_blocks=True)
    polygon_names = node.names("polygons", required=True)
    source_names = node.names("observation_sources", required=True)
    for key, names in (("polygons", polygon_names), ("observation_sources", source_names)):
        for index, name in enumerate(names):
            if name in NODE_PARAMETERS:
                raise node.error((key, index), f"'{name}' is a node parameter's name")
            if key == "observation_sources" and name in polygon_names:
                raise node.error((key, index), f"'{name}' names a polygon too")
    sources = tuple(
        _source(node, name, ("observation_sources", index))
        for index, name in enumerate(source_names)
    )
    polygons = tuple(
        _polygon(node, name, ("polygons", index), source_names)
        for index, name in enumerate(polygon_names)
    )
    return CollisionMonitorParams(
        polygons=polygons,
        observation_sources=sources,
        enabled=node.boolean("enabled", True),
        source_timeout=node.number("source_timeout", 2.0, minimum=0.0),
        base_shift_correction=node.boolean("base_shift_correction", True),
        stop_pub_timeout=node.number("stop_pub_timeout", 1.0, minimum=0.0),
        state_topic=node.string("state_topic", ""),
    )


def footprint_problem(
    params: CollisionMonitorParams, footprint: Footprint
) -> CollisionMonitorConfigError | None:
    """The error of the first ``approach`` zone that does not hold the robot's footprint.

    Nav2's approach model moves the zone ahead as the robot's footprint: a zone that leaves
    part of the robot out lets an obstacle reach the robot unseen.
    """
    for polygon in params.polygons:
        if polygon.action_type is not ActionType.APPROACH or polygon.is_footprint:
            continue
        points = polygon.points if polygon.type == "polygon" else None
        if not contains_footprint(points, polygon.radius, footprint):
            key = "points" if points is not None else "radius"
            return CollisionMonitorConfigError(
                (polygon.name, key),
                "an approach zone is the robot's footprint and must contain the robot "
                f"({describe_footprint(footprint)} around base_footprint); leave out points "
                "to use the robot's own footprint",
            )
    return None


def layered_collision_monitor(
    layers: Sequence[Mapping[str, Any] | None], footprint: Footprint
) -> CollisionMonitorParams | None:
    """The monitor the ``collision_monitor:`` blocks of ``layers`` (world, then mission: the
    later wins, parameter by parameter) configure, checked against the robot's ``footprint``;
    None when no layer has a block.

    Raises:
        CollisionMonitorConfigError: the first mistake; its ``layer`` is the index in
            ``layers`` of the block that holds it.
    """
    given = [(index, layer) for index, layer in enumerate(layers) if layer is not None]
    if not given:
        return None
    for index, layer in given:
        if not isinstance(layer, Mapping):
            error = CollisionMonitorConfigError((), "expected a mapping of parameters")
            error.layer = index
            raise error
    blocks = [layer for _, layer in given]
    try:
        params = parse_collision_monitor(merge_layers(blocks))
        problem = footprint_problem(params, footprint)
        if problem is not None:
            raise problem
    except CollisionMonitorConfigError as exc:
        exc.layer = given[layer_of(blocks, exc.key_path)][0]
        raise
    return params


def robot_footprint(robot: RobotInfo) -> Footprint:
    """The footprint the monitor gives ``robot`` (its real, unpadded outline).

    Raises:
        ValueError: for a fixed robot (a programming error: only mobile robots have one).
    """
    if robot.footprint is None:
        raise ValueError(f"robot '{robot.name}' has no footprint")
    return robot.footprint


def merge_layers(layers: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """The layers' parameters merged in order: a later layer's value replaces an earlier
    one's, mapping by mapping (a mission's ``PolygonStop: {enabled: false}`` keeps the
    world's other ``PolygonStop`` parameters); lists are replaced whole."""
    merged: dict[str, Any] = {}
    for layer in layers:
        _merge_into(merged, layer)
    return merged


def layer_of(layers: Sequence[Mapping[str, Any]], key_path: KeyPath) -> int:
    """The index of the layer that gave the value at ``key_path`` (or its deepest prefix)."""
    for length in range(len(key_path), 0, -1):
        for index in range(len(layers) - 1, -1, -1):
            if _holds(layers[index], key_path[:length]):
                return index
    return len(layers) - 1


def _merge_into(target: dict[str, Any], layer: Mapping[str, Any]) -> None:
    for key, value in layer.items():
        held = target.get(key)
        if isinstance(value, Mapping) and isinstance(held, dict):
            _merge_into(held, value)
        else:
            target[key] = dict(value) if isinstance(value, Mapping) else value


def _holds(data: Any, key_path: KeyPath) -> bool:
    for part in key_path:
        if isinstance(data, Mapping) and part in data:
            data = data[part]
            continue
        if not (isinstance(data, list) and isinstance(part, int) and 0 <= part < len(data)):
            return False
        data = data[part]
    return True


def _source(node: _Block, name: str, listed_at: KeyPath) -> SourceParams:
    block = node.block(name, listed_at, "observation source", SOURCE_PARAMETERS)
    kind = block.string("type", "scan")
    if kind in OTHER_SOURCE_TYPES:
        raise block.error("type", f"a {kind} source is not supported: the robot has a 2D lidar")
    if kind != "scan":
        raise block.error("type", unknown_name("source type", kind, ["scan", *OTHER_SOURCE_TYPES]))
    topic = block.string("topic", "scan")
    if topic not in SCAN_TOPICS:
        raise block.error("topic", f"no topic '{topic}': the robot's lidar publishes /scan")
    timeout = block.optional_number("source_timeout", minimum=0.0)
    return SourceParams(name, kind, topic, block.boolean("enabled", True), timeout)


def _polygon(
    node: _Block, name: str, listed_at: KeyPath, source_names: tuple[str, ...]
) -> PolygonParams:
    block = node.block(name, listed_at, "polygon", POLYGON_PARAMETERS, named_blocks=True)
    kind = block.choice("type", POLYGON_TYPES)
    if kind != "velocity_polygon":
        block.refuse_named_blocks()
    action = ACTION_TYPES[block.choice("action_type", tuple(ACTION_TYPES))]
    min_points = block.integer("min_points", 4, minimum=1)
    if block.has("max_points"):
        if block.has("min_points"):
            raise block.error("max_points", "give min_points or Humble's max_points, not both")
        min_points = block.integer("max_points", 3, minimum=0) + 1
    sources = block.names("sources_names", required=False) or None
    for index, source in enumerate(sources or ()):
        if source not in source_names:
            raise block.error(
                ("sources_names", index), unknown_name("source", source, source_names)
            )
    points, radius, velocity = _shape(block, kind, action)
    step = block.number("simulation_time_step", 0.1, minimum=0.0, exclusive=True)
    horizon = block.number("time_before_collision", 2.0, minimum=0.0, exclusive=True)
    if action is ActionType.APPROACH and step > horizon:
        raise block.error("simulation_time_step", f"exceeds time_before_collision {horizon:g} s")
    return PolygonParams(
        name=name,
        type=kind,
        action_type=action,
        points=points,
        radius=radius,
        enabled=block.boolean("enabled", True),
        min_points=min_points,
        trigger_consecutive_points=block.integer("trigger_consecutive_points", 1, minimum=1),
        release_consecutive_points=block.integer("release_consecutive_points", 1, minimum=1),
        slowdown_ratio=block.number("slowdown_ratio", 0.5, minimum=0.0, maximum=1.0),
        linear_limit=block.number("linear_limit", 0.5, minimum=0.0),
        angular_limit=block.number("angular_limit", 0.5, minimum=0.0),
        time_before_collision=horizon,
        simulation_time_step=step,
        sources_names=sources,
        velocity_polygons=velocity,
        holonomic=block.boolean("holonomic", False),
    )


def _shape(
    block: _Block, kind: str, action: ActionType
) -> tuple[tuple[Point, ...], float, tuple[VelocityPolygon, ...]]:
    """``points``, ``radius`` and sub-polygons of a zone of type ``kind``."""
    if kind == "circle":
        if not block.has("radius"):
            topic = " (a radius from polygon_sub_topic is not supported)"
            raise block.error((), f"a circle needs radius{topic}")
        return (), block.number("radius", 0.0, minimum=0.0, exclusive=True), ()
    if kind == "velocity_polygon":
        if action is ActionType.APPROACH:
            raise block.error("action_type", "a velocity_polygon takes stop, slowdown or limit")
        names = block.names("velocity_polygons", required=True)
        return (
            (),
            0.0,
            tuple(
                _velocity_polygon(block, name, ("velocity_polygons", index))
                for index, name in enumerate(names)
            ),
        )
    if block.has("points"):
        return block.points("points"), 0.0, ()
    if action is ActionType.APPROACH:
        return (), 0.0, ()  # the robot's footprint (Nav2: footprint_topic)
    where = "polygon_sub_topic" if block.has("polygon_sub_topic") else ()
    raise block.error(where, "give points (a polygon from polygon_sub_topic is not supported)")


def _velocity_polygon(parent: _Block, name: str, listed_at: KeyPath) -> VelocityPolygon:
    block = parent.block(name, listed_at, "velocity polygon", VELOCITY_SUBPOLYGON_PARAMETERS)
    ranges = {}
    for low, high in (("linear_min", "linear_max"), ("theta_min", "theta_max")):
        ranges[low], ranges[high] = block.number(low, None), block.number(high, None)
        if ranges[low] > ranges[high]:
            raise block.error(high, f"{ranges[high]:g} is below {low} {ranges[low]:g}")
    return VelocityPolygon(
        name=name,
        points=block.points("points", required=True),
        direction_start_angle=block.number("direction_start_angle", -math.pi),
        direction_end_angle=block.number("direction_end_angle", math.pi),
        **ranges,
    )


class _Block:
    """One mapping of parameters at ``path``, read by name with its checks."""

    def __init__(
        self,
        data: Any,
        path: KeyPath,
        what: str,
        known: Mapping[str, tuple[str, str]],
        *,
        named_blocks: bool = False,
    ) -> None:
        self.path, self.what, self.data, self.known = path, what, data, known
        if not isinstance(data, Mapping):
            raise CollisionMonitorConfigError(path, "expected a mapping of parameters")
        for key, value in data.items():
            if key not in known and not (named_blocks and isinstance(value, Mapping)):
                raise self.error(key, unknown_name("parameter", str(key), known, what))

    def error(self, key: str | int | KeyPath, message: str) -> CollisionMonitorConfigError:
        """An error at ``key`` (or a key path) below this block."""
        below = key if isinstance(key, tuple) else (key,)
        return CollisionMonitorConfigError(self.path + below, message)

    def has(self, key: str) -> bool:
        """True when the parameter is given."""
        return key in self.data

    def block(
        self,
        name: str,
        listed_at: KeyPath,
        what: str,
        known: Mapping[str, tuple[str, str]],
        *,
        named_blocks: bool = False,
    ) -> _Block:
        """The mapping of the zone, source or sub-polygon ``name``, listed at ``listed_at``."""
        if name not in self.data:
            import difflib  # only for the message

            named = [str(key) for key, value in self.data.items() if isinstance(value, Mapping)]
            close = difflib.get_close_matches(name, named, n=1, cutoff=0.6)
            hint = f"; did you mean '{close[0]}'?" if close else ""
            raise self.error(listed_at, f"{what} '{name}' has no mapping of parameters{hint}")
        path = (*self.path, name)
        return _Block(self.data[name], path, f"{what} '{name}'", known, named_blocks=named_blocks)

    def refuse_named_blocks(self) -> None:
        """Refuse the mappings under unknown keys that a velocity_polygon would take."""
        for key in self.data:
            if key not in self.known:
                raise self.error(key, unknown_name("parameter", str(key), self.known, self.what))

    def _value(self, key: str, kind: str, check: type | tuple[type, ...]) -> Any:
        value = self.data[key]
        wrong = isinstance(value, bool) and kind != BOOLEAN
        if wrong or not isinstance(value, check):
            raise self.error(key, f"expected {_KIND_WORDS[kind]}, got {value!r}")
        return value

    def number(
        self,
        key: str,
        default: float | None,
        *,
        minimum: float | None = None,
        exclusive: bool = False,
        maximum: float | None = None,
    ) -> float:
        """A float parameter; ``default`` None makes it required."""
        if key not in self.data:
            if default is None:
                raise self.error((), f"missing required parameter '{key}'")
            return default
        value = float(self._value(key, NUMBER, (int, float)))
        low = minimum is not None and (value <= minimum if exclusive else value < minimum)
        if not math.isfinite(value) or low or (maximum is not None and value > maximum):
            bounds = "a finite number"
            if minimum is not None:
                bounds += f" {'>' if exclusive else '>='} {minimum:g}"
            if maximum is not None:
                bounds += f" and <= {maximum:g}"
            raise self.error(key, f"got {value:g}; expected {bounds}")
        return value

    def optional_number(self, key: str, *, minimum: float) -> float | None:
        """A float parameter that may be left out (None)."""
        return self.number(key, 0.0, minimum=minimum) if key in self.data else None

    def integer(self, key: str, default: int, *, minimum: int) -> int:
        """An int parameter of at least ``minimum``."""
        if key not in self.data:
            return default
        value = int(self._value(key, INTEGER, int))
        if value < minimum:
            raise self.error(key, f"got {value}; expected an integer >= {minimum}")
        return value

    def boolean(self, key: str, default: bool) -> bool:
        """A bool parameter."""
        return bool(self._value(key, BOOLEAN, bool)) if key in self.data else default

    def string(self, key: str, default: str) -> str:
        """A string parameter."""
        return str(self._value(key, STRING, str)) if key in self.data else default

    def choice(self, key: str, choices: Sequence[str]) -> str:
        """A required string parameter, one of ``choices``."""
        if key not in self.data:
            raise self.error((), f"missing required parameter '{key}'")
        value = self.string(key, "")
        if value not in choices:
            raise self.error(key, unknown_name(key, value, choices, self.what))
        return value

    def names(self, key: str, *, required: bool) -> tuple[str, ...]:
        """A list of names (Nav2's string arrays), without repeats."""
        if key not in self.data:
            if required:
                raise self.error((), f"missing required parameter '{key}'")
            return ()
        value = self._value(key, NAMES, list)
        if required and not value:
            raise self.error(key, "give at least one name")
        for index, name in enumerate(value):
            if not isinstance(name, str) or not name:
                raise self.error((key, index), f"expected a name, got {name!r}")
            if name in value[:index]:
                raise self.error((key, index), f"'{name}' is listed twice")
        return tuple(value)

    def points(self, key: str, *, required: bool = False) -> tuple[Point, ...]:
        """A polygon's vertices, checked usable."""
        if key not in self.data:
            if required:
                raise self.error((), f"missing required parameter '{key}'")
            return ()
        try:
            points = parse_points(self.data[key])
        except ValueError as exc:
            raise self.error(key, str(exc)) from None
        problem = polygon_problem(points)
        if problem is not None:
            raise self.error(key, f"{problem}")
        return points


_KIND_WORDS = {
    NUMBER: "a number",
    INTEGER: "an integer",
    BOOLEAN: "true or false",
    STRING: "a string",
    NAMES: "a list of names",
}
