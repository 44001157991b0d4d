"""Nav2's collision monitor parameters: the names, defaults and units of ``nav2_collision_monitor``.

A ``collision_monitor:`` block (in a mission or its world) holds what a Nav2
parameter file holds under ``collision_monitor: ros__parameters:``: the node's parameters,
``polygons: [names]`` and ``observation_sources: [names]``, and one mapping of parameters per
name::

    collision_monitor:
      polygons: [PolygonStop, PolygonSlow]
      PolygonStop: {type: circle, radius: 0.3, action_type: stop, min_points: 4}
      PolygonSlow:
        type: polygon
        points: "[[0.6, 0.3], [0.6, -0.3], [0.0, -0.3], [0.0, 0.3]]"
        action_type: slowdown
        slowdown_ratio: 0.3
      observation_sources: [scan]
      scan: {type: scan, topic: /scan}

This module holds the parameter tables (name, kind, meaning), the checked parameters
(:class:`CollisionMonitorParams`), the error a mistake raises and the block's JSON Schema;
:mod:`baobab.nav.collision_monitor_config` reads a block into the parameters. Parameters Nav2
documents but baobab's simulation makes moot (frames, topics, QoS, real-time priority) are
accepted and have no effect. Nothing here loads numpy: ``baobab validate`` uses it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from enum import IntEnum
from typing import Any

from baobab.nav.collision_monitor_geometry import Point
from baobab.sim.errors import BaobabError

KeyPath = tuple[str | int, ...]


class ActionType(IntEnum):
    """``nav2_msgs/CollisionMonitorState`` action types."""

    DO_NOTHING = 0
    STOP = 1
    SLOWDOWN = 2
    APPROACH = 3
    LIMIT = 4


ACTION_TYPES = {
    "none": ActionType.DO_NOTHING,
    "stop": ActionType.STOP,
    "slowdown": ActionType.SLOWDOWN,
    "approach": ActionType.APPROACH,
    "limit": ActionType.LIMIT,
}
"""``action_type`` values."""
POLYGON_TYPES = ("polygon", "circle", "velocity_polygon")
SCAN_TOPICS = ("scan", "/scan")
"""Where the robot's lidar publishes."""
OTHER_SOURCE_TYPES = ("pointcloud", "range", "polygon", "costmap")

NUMBER, INTEGER, BOOLEAN, STRING = "number", "integer", "boolean", "string"
NAMES, POINTS = "names", "points"
"""The kinds of value a parameter takes (the first item of each table entry)."""

NODE_PARAMETERS: dict[str, tuple[str, str]] = {
    "polygons": (NAMES, "names of the zones, each with its own mapping"),
    "observation_sources": (NAMES, "names of the data sources, each with its own mapping"),
    "enabled": (BOOLEAN, "monitor from the start (Toggle turns it on and off); default true"),
    "source_timeout": (NUMBER, "s a source's data stays valid; older data stops the robot"),
    "base_shift_correction": (BOOLEAN, "move source points by the robot's motion since taken"),
    "stop_pub_timeout": (NUMBER, "s after a stop when zero commands cease to be published"),
    "state_topic": (STRING, "no effect: the run's trace records each CollisionMonitorState"),
    "base_frame_id": (STRING, "no effect (base_footprint)"),
    "odom_frame_id": (STRING, "no effect (odom)"),
    "cmd_vel_in_topic": (STRING, "no effect: every command to the base passes"),
    "cmd_vel_out_topic": (STRING, "no effect"),
    "transform_tolerance": (NUMBER, "no effect: transforms are exact"),
    "use_realtime_priority": (BOOLEAN, "no effect"),
    "enable_stamped_cmd_vel": (BOOLEAN, "no effect"),
    "bond_heartbeat_period": (NUMBER, "no effect"),
    "use_sim_time": (BOOLEAN, "no effect: baobab runs on sim time"),
}
POLYGON_PARAMETERS: dict[str, tuple[str, str]] = {
    "type": (STRING, "polygon, circle or velocity_polygon (required)"),
    "action_type": (STRING, "stop, slowdown, limit, approach or none (required)"),
    "points": (POINTS, '"[[x1, y1], ...]" (m, base_footprint); approach without: footprint'),
    "radius": (NUMBER, "circle radius (m)"),
    "enabled": (BOOLEAN, "use this zone; default true"),
    "min_points": (INTEGER, "readings inside that trigger the action; default 4"),
    "max_points": (INTEGER, "Humble's name: min_points - 1"),
    "trigger_consecutive_points": (INTEGER, "cycles in a row with min_points before it acts"),
    "release_consecutive_points": (INTEGER, "cycles in a row without before it releases"),
    "slowdown_ratio": (NUMBER, "share of the commanded speed kept (slowdown); default 0.5"),
    "linear_limit": (NUMBER, "m/s at most (limit); default 0.5"),
    "angular_limit": (NUMBER, "rad/s at most (limit); default 0.5"),
    "time_before_collision": (NUMBER, "s kept to a collision (approach); default 2.0"),
    "simulation_time_step": (NUMBER, "s between projected poses (approach); default 0.1"),
    "sources_names": (NAMES, "the observation sources this zone uses; default all"),
    "velocity_polygons": (NAMES, "sub-polygons by velocity (velocity_polygon)"),
    "holonomic": (BOOLEAN, "holonomic velocity matching (velocity_polygon); default false"),
    "footprint_topic": (STRING, "no effect: the robot's footprint is the costmap's"),
    "polygon_sub_topic": (STRING, "not supported: give points"),
    "polygon_subscribe_transient_local": (BOOLEAN, "no effect"),
    "visualize": (BOOLEAN, "no effect: the run's trace records the state"),
    "polygon_pub_topic": (STRING, "no effect"),
}
VELOCITY_SUBPOLYGON_PARAMETERS: dict[str, tuple[str, str]] = {
    "points": (POINTS, '"[[x1, y1], ...]" (m, base_footprint; required)'),
    "linear_min": (NUMBER, "m/s (required)"),
    "linear_max": (NUMBER, "m/s (required)"),
    "theta_min": (NUMBER, "rad/s (required)"),
    "theta_max": (NUMBER, "rad/s (required)"),
    "direction_start_angle": (NUMBER, "rad, holonomic only; default -pi"),
    "direction_end_angle": (NUMBER, "rad, holonomic only; default pi"),
}
SOURCE_PARAMETERS: dict[str, tuple[str, str]] = {
    "type": (STRING, "scan (the robot's lidar); default scan"),
    "topic": (STRING, "scan or /scan; default scan"),
    "enabled": (BOOLEAN, "use this source; default true"),
    "source_timeout": (NUMBER, "s; default the node's source_timeout; 0: never stale"),
    "min_height": (NUMBER, "no effect (pointcloud)"),
    "max_height": (NUMBER, "no effect (pointcloud)"),
    "obstacles_angle": (NUMBER, "no effect (range)"),
    "sampling_distance": (NUMBER, "no effect (polygon source)"),
    "transport_type": (STRING, "no effect"),
}


class CollisionMonitorConfigError(BaobabError, ValueError):
    """A mistake in collision monitor parameters: ``problem`` at ``key_path`` in the mapping.

    ``str()`` reads ``PolygonStop.radius: got -1; expected a number > 0``.
    """

    def __init__(self, key_path: KeyPath, problem: str) -> None:
        self.key_path = key_path
        self.problem = problem
        self.layer = 0
        """Which of the merged layers holds the mistake (:func:`layered_collision_monitor`)."""
        super().__init__(self.describe(""))

    def describe(self, block: str = "collision_monitor") -> str:
        """The message, its key path under ``block`` (the block's own key in a file)."""
        dotted = ".".join(str(part) for part in (block, *self.key_path) if part != "")
        return f"{dotted}: {self.problem}" if dotted else self.problem


@dataclass(frozen=True)
class VelocityPolygon:
    """One sub-polygon of a ``velocity_polygon``: used while the command is in its ranges."""

    name: str
    points: tuple[Point, ...]
    linear_min: float
    linear_max: float
    theta_min: float
    theta_max: float
    direction_start_angle: float = -math.pi
    direction_end_angle: float = math.pi


@dataclass(frozen=True)
class PolygonParams:
    """One zone. ``points`` empty and ``radius`` 0 for an ``approach`` polygon: the robot's
    footprint. Units: m, s, m/s, rad/s."""

    name: str
    type: str
    action_type: ActionType
    points: tuple[Point, ...] = ()
    radius: float = 0.0
    enabled: bool = True
    min_points: int = 4
    trigger_consecutive_points: int = 1
    release_consecutive_points: int = 1
    slowdown_ratio: float = 0.5
    linear_limit: float = 0.5
    angular_limit: float = 0.5
    time_before_collision: float = 2.0
    simulation_time_step: float = 0.1
    sources_names: tuple[str, ...] | None = None
    velocity_polygons: tuple[VelocityPolygon, ...] = ()
    holonomic: bool = False

    @property
    def is_footprint(self) -> bool:
        """True for an approach polygon without points: the robot's own footprint."""
        return self.type == "polygon" and not self.points


@dataclass(frozen=True)
class SourceParams:
    """One observation source: the lidar's scans. ``source_timeout`` None: the node's."""

    name: str
    type: str = "scan"
    topic: str = "scan"
    enabled: bool = True
    source_timeout: float | None = None


@dataclass(frozen=True)
class CollisionMonitorParams:
    """The whole collision monitor (Nav2's defaults; times in s)."""

    polygons: tuple[PolygonParams, ...]
    observation_sources: tuple[SourceParams, ...]
    enabled: bool = True
    source_timeout: float = 2.0
    base_shift_correction: bool = True
    stop_pub_timeout: float = 1.0
    state_topic: str = ""

    def timeout_of(self, source: SourceParams) -> float:
        """The source's ``source_timeout`` (s), or the node's."""
        return self.source_timeout if source.source_timeout is None else source.source_timeout


def parameters_schema() -> dict[str, Any]:
    """The JSON Schema of a ``collision_monitor:`` block, for editor completion."""
    zone = _schema_object(POLYGON_PARAMETERS, open_ended=True)
    source = _schema_object(SOURCE_PARAMETERS)
    node = _schema_object(NODE_PARAMETERS)
    node["additionalProperties"] = {"anyOf": [zone, source]}
    node["description"] = "Nav2's collision monitor: its ros__parameters, with Nav2's names"
    return node


def _schema_object(
    table: Mapping[str, tuple[str, str]], *, open_ended: bool = False
) -> dict[str, Any]:
    kinds: dict[str, Any] = {
        NUMBER: {"type": "number"},
        INTEGER: {"type": "integer"},
        BOOLEAN: {"type": "boolean"},
        STRING: {"type": "string"},
        NAMES: {"type": "array", "items": {"type": "string"}},
        POINTS: {"type": ["string", "array"]},
    }
    properties = {
        name: {**kinds[kind], "description": text} for name, (kind, text) in table.items()
    }
    schema: dict[str, Any] = {"type": "object", "properties": properties}
    if open_ended:  # a velocity_polygon's sub-polygons are mappings under their names
        schema["additionalProperties"] = _schema_object(VELOCITY_SUBPOLYGON_PARAMETERS)
    else:
        schema["additionalProperties"] = False
    return schema
