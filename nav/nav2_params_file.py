"""Reading a Nav2 parameter file (``nav2_params.yaml``) into located parameters per node.

The format is ROS 2's (rcl_yaml_param_parser): each top-level key is a node name, optionally
nested under its namespace (``local_costmap: local_costmap: ros__parameters:``) or written as
one slash-separated name (``/local_costmap/local_costmap``); ``/**`` names every node. Below a
node's ``ros__parameters``, nested mappings are dotted parameter names
(``FollowPath: {desired_linear_vel: 0.5}`` is ``FollowPath.desired_linear_vel``), which is how
Nav2 namespaces a plugin's parameters under its instance name.

:func:`read_nav2_params` keeps where each parameter was written, so every later complaint
(a wrong type, an unsupported plugin) names ``file:line:col``. Which nodes and parameters
baobab uses is :mod:`baobab.nav.nav2_param_table`'s business; this module only knows the
names of Nav2's nodes, so a misspelt one is an error with its near miss.

Example:
    >>> params = read_nav2_params("nav2_params.yaml")  # doctest: +SKIP
    >>> params.get("controller_server", "FollowPath.desired_linear_vel").value  # doctest: +SKIP
    0.5
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from baobab.sim.errors import SourceError, clip, unknown_name
from baobab.sim.yaml_source import KeyPath, LocatedDocument, load_located_yaml

ROS_PARAMETERS = "ros__parameters"
ALL_NODES = "/**"
"""The node name a ``/**`` (or ``**``) section stands for: its parameters apply to every node."""

MAPPED_NODES = (
    "global_costmap",
    "local_costmap",
    "planner_server",
    "smoother_server",
    "controller_server",
    "behavior_server",
    "bt_navigator",
    "waypoint_follower",
    "velocity_smoother",
    "collision_monitor",
)
"""The Nav2 nodes whose parameters baobab's navigation stack reads."""

OTHER_NAV2_NODES = (
    "amcl",
    "map_server",
    "map_saver",
    "slam_toolbox",
    "lifecycle_manager",
    "lifecycle_manager_localization",
    "lifecycle_manager_navigation",
    "robot_state_publisher",
    "docking_server",
    "route_server",
    "following_server",
    "loopback_simulator",
    "costmap_filter_info_server",
    "filter_mask_server",
    "keepout_filter_mask_server",
    "speed_filter_mask_server",
    "keepout_costmap_filter_info_server",
    "speed_costmap_filter_info_server",
    "binary_filter_mask_server",
    "binary_costmap_filter_info_server",
    "ekf_filter_node",
    "navsat_transform",
    "recoveries_server",
)
"""Nodes of a Nav2 bringup (or its usual companions) that a parameter file may configure and
baobab accepts without reading: localisation, maps, lifecycle, servers baobab runs otherwise."""

KNOWN_NODES = frozenset(MAPPED_NODES + OTHER_NAV2_NODES)
_FILTER_SERVER_SUFFIXES = ("_mask_server", "_filter_info_server")
MAX_NAMESPACE_DEPTH = 4
"""How many namespace levels may wrap a node's section (``ns: local_costmap: local_costmap:``)."""


class Nav2ParamsError(SourceError):
    """A Nav2 parameter file that cannot be used: located as ``file:line:col: message``."""


@dataclass(frozen=True)
class Nav2Parameter:
    """One parameter as the file sets it.

    Attributes:
        node: the node's name without its namespace (``controller_server``; ``/**`` for all).
        name: the dotted parameter name (``FollowPath.desired_linear_vel``).
        value: the YAML value (bool, int, float, str or a list of them).
        line: 1-based line of the parameter's key.
        column: 1-based column of the parameter's key.
    """

    node: str
    name: str
    value: Any
    line: int
    column: int


@dataclass
class Nav2ParamsFile:
    """The parameters of a Nav2 parameter file, by node and name, each with its place.

    Attributes:
        path: the file as the user named it (messages show it).
        nodes: node name -> parameter name -> parameter; node ``/**`` holds the parameters
            that apply to every node.
        node_marks: node name -> (line, column) of its section's key.
    """

    path: str
    nodes: dict[str, dict[str, Nav2Parameter]] = field(default_factory=dict)
    node_marks: dict[str, tuple[int, int]] = field(default_factory=dict)

    def get(self, node: str, name: str) -> Nav2Parameter | None:
        """The parameter ``name`` of ``node`` (else of ``/**``), or None when the file lacks it."""
        found = self.nodes.get(node, {}).get(name)
        return found if found is not None else self.nodes.get(ALL_NODES, {}).get(name)

    def names(self, node: str, prefix: str = "") -> Iterator[Nav2Parameter]:
        """The parameters of ``node`` (not of ``/**``) whose names start with ``prefix``."""
        for name, parameter in self.nodes.get(node, {}).items():
            if name.startswith(prefix):
                yield parameter

    def error(self, parameter: Nav2Parameter | None, message: str) -> Nav2ParamsError:
        """A located error at ``parameter`` (None: the start of the file)."""
        if parameter is None:
            return Nav2ParamsError(self.path, 1, 1, message)
        return Nav2ParamsError(self.path, parameter.line, parameter.column, message)

    def node_error(self, node: str, message: str) -> Nav2ParamsError:
        """A located error at the section of ``node``."""
        line, column = self.node_marks.get(node, (1, 1))
        return Nav2ParamsError(self.path, line, column, message)


def read_nav2_params(path: str | Path) -> Nav2ParamsFile:
    """Read a Nav2 parameter file.

    Raises:
        Nav2ParamsError: an unreadable file, YAML errors (:mod:`baobab.sim.yaml_source`), a
            section without ``ros__parameters``, a node name that is not Nav2's (with its near
            miss), a parameter set twice for one node.
    """
    document = load_located_yaml(path, Nav2ParamsError)
    result = Nav2ParamsFile(document.path)
    if not isinstance(document.data, dict):
        raise document.error((), "a Nav2 parameter file is a mapping of node names", _error)
    for key, value in document.data.items():
        _read_section(document, result, (key,), value, depth=0)
    return result


def _error(path: str, line: int, column: int, message: str) -> Nav2ParamsError:
    return Nav2ParamsError(path, line, column, message)


def _read_section(
    document: LocatedDocument, result: Nav2ParamsFile, key_path: KeyPath, value: Any, depth: int
) -> None:
    """Read the section at ``key_path``: a node's (with ``ros__parameters``) or a namespace."""
    key = str(key_path[-1])
    if not isinstance(value, dict):
        raise document.error(
            key_path,
            f"'{clip(key)}' must be a node name with a 'ros__parameters' mapping below it",
            _error,
        )
    node = _node_name(key)
    if ROS_PARAMETERS in value:
        extra = [other for other in value if other != ROS_PARAMETERS]
        if extra:
            raise document.error(
                key_path + (extra[0],),
                f"unexpected key '{clip(extra[0])}' beside ros__parameters of '{clip(key)}'",
                _error,
            )
        _check_node(document, key_path, node)
        result.node_marks.setdefault(node, document.locate(key_path))
        parameters = value[ROS_PARAMETERS]
        where = key_path + (ROS_PARAMETERS,)
        if parameters is None:
            return
        if not isinstance(parameters, dict):
            raise document.error(
                where, f"ros__parameters of '{clip(key)}' must be a mapping", _error
            )
        _read_parameters(document, result, node, where, parameters, "")
        return
    if depth >= MAX_NAMESPACE_DEPTH or not value:
        raise document.error(key_path, f"'{clip(key)}' has no ros__parameters below it", _error)
    if node in KNOWN_NODES and not any(isinstance(inner, dict) for inner in value.values()):
        raise document.error(
            key_path, f"node '{clip(key)}' needs 'ros__parameters:' above its parameters", _error
        )
    for inner_key, inner_value in value.items():
        _read_section(document, result, key_path + (inner_key,), inner_value, depth + 1)


def _node_name(key: str) -> str:
    """The node a section key names: the last part of a slash-separated name, or ``/**``."""
    parts = [part for part in key.split("/") if part]
    if not parts or parts[-1] in ("**", "*"):
        return ALL_NODES
    return parts[-1]


def _check_node(document: LocatedDocument, key_path: KeyPath, node: str) -> None:
    if node == ALL_NODES or node in KNOWN_NODES or node.endswith(_FILTER_SERVER_SUFFIXES):
        return
    message = unknown_name("Nav2 node", node, KNOWN_NODES)
    raise document.error(key_path, message, _error)


def _read_parameters(
    document: LocatedDocument,
    result: Nav2ParamsFile,
    node: str,
    where: KeyPath,
    values: dict[str, Any],
    prefix: str,
) -> None:
    """Flatten nested mappings into dotted names, keeping each key's place."""
    table = result.nodes.setdefault(node, {})
    for key, value in values.items():
        name = f"{prefix}{key}"
        key_path = where + (key,)
        if isinstance(value, dict) and value:
            _read_parameters(document, result, node, key_path, value, f"{name}.")
            continue
        line, column = document.locate(key_path)
        if name in table:
            first = table[name]
            raise Nav2ParamsError(
                document.path,
                line,
                column,
                f"parameter '{clip(name)}' of '{node}' set twice (first at line {first.line})",
            )
        table[name] = Nav2Parameter(node, name, value, line, column)
