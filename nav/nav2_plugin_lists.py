"""Which plugin instances a Nav2 parameter file loads, and which of them baobab runs.

For every plugin list of :data:`~baobab.nav.nav2_plugins.PLUGIN_LISTS` (``controller_plugins``,
a costmap's ``plugins`` ...), :func:`plugin_uses` reads the instance names (Nav2's defaults
when the file lists none), each instance's class (``<instance>.plugin``), and decides:

- a class baobab runs: its rows apply to ``<instance>.*``; of a kind baobab runs once (one
  controller, one planner ...), only the instance named like Nav2's default, else the first;
- a class baobab does not run: a located error naming it, the classes baobab has and
  ``--nav2-substitute``; with ``substitute``, its stated substitute runs (with the rows it
  takes over, e.g. MPPI's ``vx_max`` as RPP's speed);
- a costmap's layers: which of baobab's static, obstacle and inflation layers are on
  (``enabled``), the obstacle layer's observation source (the lidar: the first LaserScan
  source), and that inflation comes after the layers it inflates.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from baobab.nav.nav2_param_rows import Mapped
from baobab.nav.nav2_param_table import OBSERVATION_ROWS
from baobab.nav.nav2_params_file import Nav2Parameter, Nav2ParamsFile
from baobab.nav.nav2_plugins import (
    PLUGIN_LISTS,
    PLUGINS,
    PluginInfo,
    PluginKind,
    canonical_class,
    native_classes,
)
from baobab.sim.errors import clip

STATIC = "nav2_costmap_2d::StaticLayer"
OBSTACLE_CLASSES = ("nav2_costmap_2d::ObstacleLayer", "nav2_costmap_2d::VoxelLayer")
INFLATION = "nav2_costmap_2d::InflationLayer"


@dataclass
class PluginUse:
    """One plugin instance of the file, and what baobab does with it.

    Attributes:
        node: the server node.
        instance: the instance name (``FollowPath``).
        plugin_class: its canonical class.
        kind: the kind of plugin.
        active: whether its parameters apply (False: an instance baobab does not run).
        rows: the rows applied to ``<instance>.*``.
        sets: ``NavigationParams`` fields set by the instance's presence or absence.
        sources: observation sources whose ``<instance>.<source>.*`` take ``source_rows``.
        source_rows: rows of one observation source.
        consumed: file parameters read here (the list, ``plugin``, ``enabled`` ...).
        substitution: a line saying what runs instead of an unsupported class ("" if none).
    """

    node: str
    instance: str
    plugin_class: str
    kind: PluginKind
    active: bool = True
    rows: tuple[Mapped, ...] = ()
    sets: dict[str, Any] = field(default_factory=dict)
    sources: list[str] = field(default_factory=list)
    source_rows: tuple[Mapped, ...] = ()
    consumed: list[Nav2Parameter] = field(default_factory=list)
    substitution: str = ""


def plugin_uses(file: Nav2ParamsFile, *, substitute: bool) -> list[PluginUse]:
    """Every plugin instance of every list baobab reads, in the file's order per list.

    Raises:
        Nav2ParamsError: located: a list that is not names, an instance without a class, an
            ``enabled`` that is not true/false, an unsupported class (without ``substitute``),
            inflation before a layer it would inflate (without ``substitute``).
    """
    uses: list[PluginUse] = []
    for kind in PLUGIN_LISTS:
        listed = _listed(file, kind)
        if listed is None and not file.nodes.get(kind.node):
            continue  # the node is not in the file: its plugins stay baobab's defaults
        names, list_parameter = listed or (list(kind.defaults), None)
        kind_uses = [
            _use(file, kind, name, list_parameter, substitute=substitute) for name in names
        ]
        if list_parameter is not None and kind_uses:
            kind_uses[0].consumed.append(list_parameter)
        if kind.single:
            _keep_one(kind, kind_uses)
        if kind.label == "costmap layer":
            _layers(file, kind, kind_uses, list_parameter, substitute=substitute)
        elif kind.label in ("costmap filter", "waypoint task executor"):
            for use in kind_uses:
                if not _enabled(file, use):  # a disabled filter or task runs nothing
                    use.active = False
                    use.sets.update(kind.disabled)
        uses.extend(kind_uses)
    return uses


def _listed(file: Nav2ParamsFile, kind: PluginKind) -> tuple[list[str], Nav2Parameter] | None:
    for list_name in kind.list_names:
        parameter = file.get(kind.node, list_name)
        if parameter is None:
            continue
        return _names(file, parameter), parameter
    return None


def _names(file: Nav2ParamsFile, parameter: Nav2Parameter) -> list[str]:
    """A plugin list's names: a list of strings, or one string (Humble's singular lists)."""
    value = parameter.value
    if isinstance(value, str):
        return value.split()
    if isinstance(value, list) and all(isinstance(name, str) and name for name in value):
        return list(value)
    raise file.error(
        parameter, f"{parameter.name} must be a list of plugin names, got {clip(value)}"
    )


def _use(
    file: Nav2ParamsFile,
    kind: PluginKind,
    instance: str,
    list_parameter: Nav2Parameter | None,
    *,
    substitute: bool,
) -> PluginUse:
    class_parameter = file.get(kind.node, f"{instance}.plugin")
    if class_parameter is None:
        if instance not in kind.defaults:
            raise file.error(
                list_parameter,
                f"{kind.label} '{clip(instance)}' has no '{clip(instance)}.plugin' (its class)",
            )
        plugin_class = kind.defaults[instance]
    elif not isinstance(class_parameter.value, str):
        raise file.error(class_parameter, f"{class_parameter.name} must be a plugin class name")
    else:
        plugin_class = canonical_class(class_parameter.value)
    use = PluginUse(kind.node, instance, plugin_class, kind)
    if class_parameter is not None:
        use.consumed.append(class_parameter)
    info = PLUGINS.get(plugin_class)
    if info is None or info.kind != kind.label:
        info = PluginInfo(kind.label, False, (), kind.substitute)
    if not info.native:
        where = class_parameter or list_parameter
        if not substitute:
            natives = ", ".join(native_classes(kind.label)) or "(none)"
            raise file.error(
                where,
                f"{kind.label} plugin '{clip(plugin_class)}' ({clip(instance)}) is not in baobab;"
                f" baobab has: {natives}; --nav2-substitute runs {info.substitute} instead",
            )
        use.substitution = f"{kind.node}/{instance}: {plugin_class} -> {info.substitute}"
        use.active = bool(info.rows) or kind.single
    use.rows = info.rows
    return use


def _keep_one(kind: PluginKind, uses: list[PluginUse]) -> None:
    """Of a kind baobab runs once: the instance with Nav2's default name, else the first."""
    chosen = next((use for use in uses if use.instance in kind.defaults), uses[0] if uses else None)
    for use in uses:
        use.active = use is chosen and use.active


def _layers(
    file: Nav2ParamsFile,
    kind: PluginKind,
    uses: list[PluginUse],
    list_parameter: Nav2Parameter | None,
    *,
    substitute: bool,
) -> None:
    """baobab's layers on or off as the file's list says; the obstacle layer's lidar source."""
    node = kind.node
    enabled = {id(use): _enabled(file, use) for use in uses}
    on = [use for use in uses if use.active and enabled[id(use)]]
    obstacle = next((use for use in on if use.plugin_class in OBSTACLE_CLASSES), None)
    for use in on:
        if use.plugin_class in OBSTACLE_CLASSES and use is not obstacle:
            use.active = False  # one lidar, one obstacle layer
    if obstacle is not None:
        _observation_source(file, obstacle)
    inflation = next((use for use in on if use.plugin_class == INFLATION), None)
    if list_parameter is None and not uses:
        return
    holder = uses[0]
    holder.sets[f"{node}.use_static_layer"] = any(use.plugin_class == STATIC for use in on)
    holder.sets[f"{node}.use_obstacle_layer"] = obstacle is not None
    if inflation is None:
        holder.sets[f"{node}.inflation_radius"] = 0.0
        return
    inflated = [use for use in on if use.plugin_class in (STATIC, *OBSTACLE_CLASSES)]
    late = [use for use in inflated if uses.index(use) > uses.index(inflation)]
    if late and not substitute:
        raise file.error(
            list_parameter,
            f"'{late[0].instance}' comes after '{inflation.instance}' in {node}'s plugins, so"
            " Nav2 leaves it uninflated; baobab inflates every layer: put the inflation layer"
            " last, or --nav2-substitute to run baobab's order",
        )
    if late:
        inflation.substitution = f"{node}/plugins: layers run as static, obstacle, inflation"


def _enabled(file: Nav2ParamsFile, use: PluginUse) -> bool:
    parameter = file.get(use.node, f"{use.instance}.enabled")
    if parameter is None:
        return True
    if not isinstance(parameter.value, bool):
        raise file.error(parameter, f"{parameter.name} must be true or false")
    use.consumed.append(parameter)
    return parameter.value


def _observation_source(file: Nav2ParamsFile, layer: PluginUse) -> None:
    """The obstacle layer's lidar: its first LaserScan source (else its first source)."""
    parameter = file.get(layer.node, f"{layer.instance}.observation_sources")
    if parameter is None:
        return
    layer.consumed.append(parameter)
    sources = _names(file, parameter)
    types = {}
    for source in sources:
        data_type = file.get(layer.node, f"{layer.instance}.{source}.data_type")
        if data_type is not None:
            layer.consumed.append(data_type)
        types[source] = data_type.value if data_type is not None else "PointCloud2"
    scans = [source for source in sources if types[source] == "LaserScan"]
    chosen = (scans or sources)[:1]
    layer.sources = chosen
    layer.source_rows = OBSERVATION_ROWS
