"""A Nav2 parameter file applied to baobab's navigation settings.

:func:`configure_navigation` takes the parameters a file sets (:mod:`baobab.nav.nav2_params_file`)
and the settings the robot would run with otherwise (its :class:`NavigationParams`), and returns
a :class:`Nav2Configuration`: the settings with every parameter baobab has an equivalent for
replaced by the file's value (:mod:`baobab.nav.nav2_param_table`), where each mapped value came
from (the file or the default), what the file sets that baobab does not use (grouped by node and
plugin, for one warning), and which unsupported plugins were substituted.

A plugin baobab does not run is an error naming it, the plugins baobab has, and
``--nav2-substitute`` (``substitute=True``) with the substitute it would accept
(:mod:`baobab.nav.nav2_plugins`). Every value is checked for its type and range against the row
that maps it; every error is located in the file.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path as FilePath
from typing import Any

from baobab.nav.collision_monitor_config import parse_collision_monitor
from baobab.nav.collision_monitor_params import CollisionMonitorConfigError
from baobab.nav.nav2_collision_monitor import NODE as MONITOR_NODE
from baobab.nav.nav2_collision_monitor import file_monitor_block, file_monitor_error
from baobab.nav.nav2_filters import NavFilterMasks, apply_filters, filter_masks
from baobab.nav.nav2_footprint import costmap_footprint
from baobab.nav.nav2_param_rows import Mapped
from baobab.nav.nav2_param_table import NODE_ROWS, is_ros_only
from baobab.nav.nav2_params_file import (
    ALL_NODES,
    MAPPED_NODES,
    Nav2Parameter,
    Nav2ParamsFile,
    read_nav2_params,
)
from baobab.nav.nav2_plugin_lists import PluginUse, plugin_uses
from baobab.nav.navigation_params import NavigationParams
from baobab.sim.world import World

FILE = "file"
DEFAULT = "default"


@dataclass(frozen=True)
class Setting:
    """One mapped Nav2 parameter as baobab runs it.

    Attributes:
        node: the Nav2 node (``controller_server``).
        name: the parameter's full name in that node (``FollowPath.desired_linear_vel``).
        value: the value in Nav2's units (the file's, or the default baobab runs with).
        unit: Nav2's unit ("" for none).
        origin: ``"file"`` or ``"default"``.
        targets: the ``NavigationParams`` fields it sets.
        meaning: what it does, in a few words.
        line: where the file sets it (0 for a default).
    """

    node: str
    name: str
    value: Any
    unit: str
    origin: str
    targets: tuple[str, ...]
    meaning: str
    line: int = 0


@dataclass
class Nav2Configuration:
    """The navigation settings a Nav2 parameter file gives, and how they were made.

    Attributes:
        params: the settings baobab runs with.
        settings: every mapped parameter, in file order per node, with its origin.
        unused: group (``node`` or ``node/instance (class)``) -> names the file sets there
            that baobab does not use.
        substitutions: one line per unsupported plugin that runs as a substitute.
        path: the parameter file.
    """

    params: NavigationParams
    settings: list[Setting] = field(default_factory=list)
    unused: dict[str, list[str]] = field(default_factory=dict)
    ros_only: list[str] = field(default_factory=list)
    substitutions: list[str] = field(default_factory=list)
    ignored_nodes: list[str] = field(default_factory=list)
    path: str = ""
    masks: NavFilterMasks | None = None
    file: Nav2ParamsFile | None = None

    def filtered(self, world: World) -> World:
        """``world`` with the file's keepout and speed masks (itself when the file has none).

        Raises:
            Nav2ParamsError: a mask that does not fit the world (located in the file).
        """
        if self.masks is None or self.file is None:
            return world
        return apply_filters(world, self.file, self.masks)

    def value(self, node: str, name: str) -> Any:
        """The value a mapped parameter has (KeyError for one that is not mapped)."""
        for setting in self.settings:
            if setting.node == node and setting.name == name:
                return setting.value
        raise KeyError(f"{node}: {name}")

    def warning(self) -> str | None:
        """The one warning listing the unused parameters by plugin, or None when all are used."""
        if not self.unused:
            return None
        groups = "; ".join(f"{group}: {', '.join(names)}" for group, names in self.unused.items())
        count = sum(len(names) for names in self.unused.values())
        return f"{self.path}: {count} parameter(s) baobab does not use: {groups}"


class _Builder:
    """Collects the changes, settings and leftovers of one file against base settings."""

    def __init__(self, file: Nav2ParamsFile, base: NavigationParams) -> None:
        self.file = file
        self.base = base
        self.changes: dict[str, Any] = {}
        self.used: set[tuple[str, str]] = set()
        self.result = Nav2Configuration(base, path=file.path, file=file)

    def apply_rows(self, node: str, prefix: str, rows: Iterable[Mapped]) -> None:
        """Apply ``rows`` to the parameters ``prefix + row.name`` of ``node``."""
        for row in rows:
            self.apply_row(node, prefix, row)

    def apply_row(self, node: str, prefix: str, row: Mapped) -> None:
        targets = tuple(target.replace("{costmap}", node) for target in row.targets)
        parameter = self._find(node, prefix, row)
        if parameter is None:
            current = _get(self.base, targets[0])
            shown = row.default if current is None and row.default is not None else current
            self.result.settings.append(
                Setting(node, prefix + row.name, shown, row.unit, DEFAULT, targets, row.meaning)
            )
            return
        problem = row.problem(parameter.value)
        if problem is not None:
            raise self.file.error(
                parameter, f"{parameter.name} ({row.unit or row.meaning}) {problem}"
            )
        for target in targets:
            self.changes[target] = row.baobab_value(parameter.value)
        self.result.settings.append(
            Setting(
                node,
                parameter.name,
                parameter.value,
                row.unit,
                FILE,
                targets,
                row.meaning,
                parameter.line,
            )
        )

    def _find(self, node: str, prefix: str, row: Mapped) -> Nav2Parameter | None:
        found = None
        for name in (row.name, *row.aliases):
            parameter = self.file.get(node, prefix + name)
            if parameter is None:
                continue
            self.used.add((parameter.node, parameter.name))
            if found is None:
                found = parameter
        return found

    def set(self, target: str, value: Any) -> None:
        """Set one field outright (a layer left out, a plugin's consequence)."""
        self.changes[target] = value

    def mark_used(self, parameter: Nav2Parameter | None) -> None:
        if parameter is not None:
            self.used.add((parameter.node, parameter.name))


def configure_navigation(
    file: Nav2ParamsFile, base: NavigationParams | None = None, *, substitute: bool = False
) -> Nav2Configuration:
    """Apply a Nav2 parameter file to ``base`` (the robot's settings; default: bare defaults).

    Args:
        file: the file's parameters.
        base: the settings before the file.
        substitute: run a stated substitute for each plugin baobab does not have, instead of
            refusing the file.

    Raises:
        Nav2ParamsError: a wrong type or range, an unsupported plugin without ``substitute``,
            a plugin list that is not a list of names, an instance without its ``plugin``
            (located in the file).
    """
    builder = _Builder(file, base or NavigationParams())
    for node, rows in NODE_ROWS.items():
        builder.apply_rows(node, "", rows)
    if file.nodes.get("velocity_smoother"):
        _smoother_in_chain(builder)
    for node in ("global_costmap", "local_costmap"):
        _footprint(builder, node)
    uses = plugin_uses(file, substitute=substitute)
    for use in uses:
        _apply_plugin(builder, use)
    _collision_monitor(builder)
    masks, used = filter_masks(file, uses)
    for parameter in used:
        builder.mark_used(parameter)
    builder.result.masks = masks
    result = builder.result
    result.params = _with_changes(builder.base, builder.changes)
    _sort_leftovers(builder, uses)
    return result


def _footprint(builder: _Builder, node: str) -> None:
    """The costmap's footprint from ``robot_radius``, ``footprint``, ``footprint_padding``."""
    found = costmap_footprint(builder.file, node)
    target = f"{node}.footprint"
    for parameter in found.parameters:
        if parameter not in found.unused:
            builder.mark_used(parameter)
    if found.footprint is None:
        current = _get(builder.base, target)
        shown = current.radius if current.is_circle else [list(p) for p in current.polygon]
        builder.result.settings.append(
            Setting(node, "robot_radius / footprint", shown, "m", DEFAULT, (target,), _FOOTPRINT)
        )
        return
    builder.set(target, found.footprint)
    decided = next(p for p in found.parameters if p.name in ("footprint", "robot_radius"))
    if decided.name == "robot_radius" and len(found.parameters) > 1:
        decided = next((p for p in found.parameters if p.name == "footprint"), decided)
    builder.result.settings.append(
        Setting(node, decided.name, decided.value, "m", FILE, (target,), _FOOTPRINT, decided.line)
    )


_FOOTPRINT = "the robot's outline (a polygon padded by footprint_padding)"


def _collision_monitor(builder: _Builder) -> None:
    """The file's ``collision_monitor`` node, each of its parameters listed as used.

    A node that names its ``polygons`` and ``observation_sources`` is checked on its own here;
    one that only changes a world's monitor, and the robot's footprint, are checked where the
    monitor is built (the world's, the file's and the mission's layers merged).
    """
    block = file_monitor_block(builder.file)
    if block is None:
        return
    if "polygons" in block and "observation_sources" in block:
        try:
            parse_collision_monitor(block)
        except CollisionMonitorConfigError as exc:
            raise file_monitor_error(builder.file, exc) from None
    for parameter in builder.file.names(MONITOR_NODE):
        builder.mark_used(parameter)
        builder.result.settings.append(
            Setting(
                MONITOR_NODE,
                parameter.name,
                parameter.value,
                "",
                FILE,
                ("collision_monitor",),
                "Nav2's collision monitor between the stack and the base",
                parameter.line,
            )
        )


def _smoother_in_chain(builder: _Builder) -> None:
    """A file that configures the velocity smoother runs it (baobab's stack has none else)."""
    target = "velocity_smoother.enabled"
    builder.set(target, True)
    line = builder.file.node_marks["velocity_smoother"][0]
    builder.result.settings.append(
        Setting(
            "velocity_smoother",
            "(the file configures it)",
            True,
            "",
            FILE,
            (target,),
            "the smoother runs between the stack and the base",
            line,
        )
    )


def _apply_plugin(builder: _Builder, use: PluginUse) -> None:
    """Apply one plugin instance's rows (and its consequences) to the settings."""
    for parameter in use.consumed:
        builder.mark_used(parameter)
    if use.substitution:
        builder.result.substitutions.append(use.substitution)
    for target, value in use.sets.items():
        builder.set(target, value)
    if not use.active:
        return
    builder.apply_rows(use.node, f"{use.instance}.", use.rows)
    for source in use.sources:
        builder.apply_rows(use.node, f"{use.instance}.{source}.", use.source_rows)


def _sort_leftovers(builder: _Builder, uses: Iterable[PluginUse]) -> None:
    """File parameters nobody used: ROS-only ones, unused ones by plugin (``uses``), other
    nodes."""
    result = builder.result
    groups = _instance_groups(uses)
    for node, parameters in builder.file.nodes.items():
        if node != ALL_NODES and node not in MAPPED_NODES:
            if not any(user == node for user, _ in builder.used):  # not a filter's server
                result.ignored_nodes.append(node)
            continue
        for name in parameters:
            if (node, name) in builder.used:
                continue
            if is_ros_only(name) or node == ALL_NODES:
                result.ros_only.append(f"{node}: {name}")
                continue
            instance = name.split(".", 1)[0]
            group = groups.get((node, instance), node)
            result.unused.setdefault(group, []).append(name)


def _instance_groups(uses: Iterable[PluginUse]) -> dict[tuple[str, str], str]:
    """(node, instance) -> ``node/instance (Class)`` for the plugin instances the file has."""
    groups: dict[tuple[str, str], str] = {}
    for use in uses:
        groups[(use.node, use.instance)] = f"{use.node}/{use.instance} ({use.plugin_class})"
    return groups


def _get(params: Any, target: str) -> Any:
    value = params
    for part in target.split("."):
        value = value[int(part)] if isinstance(value, tuple) else getattr(value, part)
    return value


def _with_changes(params: NavigationParams, changes: dict[str, Any]) -> NavigationParams:
    """``params`` with each dotted field of ``changes`` replaced (frozen records rebuilt)."""
    for target, value in changes.items():
        params = _replaced(params, target.split("."), value)
    return params


def _replaced(record: Any, parts: list[str], value: Any) -> Any:
    head, rest = parts[0], parts[1:]
    if isinstance(record, tuple):
        items = list(record)
        index = int(head)
        items[index] = _replaced(items[index], rest, value) if rest else value
        return tuple(items)
    new = _replaced(getattr(record, head), rest, value) if rest else value
    return dataclasses.replace(record, **{head: new})


def load_nav2_params(
    path: str | FilePath, base: NavigationParams | None = None, *, substitute: bool = False
) -> Nav2Configuration:
    """Read the Nav2 parameter file at ``path`` and apply it to ``base``
    (:func:`~baobab.nav.nav2_params_file.read_nav2_params`, then :func:`configure_navigation`).

    Raises:
        Nav2ParamsError: anything wrong with the file (located).
    """
    return configure_navigation(read_nav2_params(path), base, substitute=substitute)
