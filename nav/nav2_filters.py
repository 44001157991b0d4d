"""A Nav2 parameter file's costmap filters: which mask files the keepout and speed filters read.

Nav2 wires a costmap filter through three nodes: the filter plugin in a costmap's ``filters``
(``keepout_filter.filter_info_topic``), a ``costmap_filter_info_server`` publishing that topic
with the filter's ``type``, ``base``, ``multiplier`` and ``mask_topic``, and a map server
(``filter_mask_server``) publishing the mask on that topic (``topic_name``) from its
``yaml_filename``. :func:`filter_masks` follows the same links through the file and returns
baobab's :class:`~baobab.sim.world_map.FilterSettings` (mask paths relative to the parameter
file's folder, as a mission's ``filters:`` are to the mission's), which the world takes in place
of its own masks (:meth:`~baobab.sim.world.World.with_filters`). Every broken link, a mask file
that does not exist, and a filter type that does not fit its plugin is a located error.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from baobab.nav.nav2_params_file import Nav2Parameter, Nav2ParamsFile
from baobab.nav.nav2_plugin_lists import PluginUse
from baobab.sim.errors import WorldError, clip
from baobab.sim.world import World
from baobab.sim.world_map import (
    KEEPOUT,
    SPEED_FILTER_ABSOLUTE,
    SPEED_FILTER_PERCENT,
    FilterSettings,
    KeepoutSettings,
    SpeedSettings,
)
from baobab.sim.yaml_source import FieldValueError

KEEPOUT_CLASS = "nav2_costmap_2d::KeepoutFilter"
SPEED_CLASS = "nav2_costmap_2d::SpeedFilter"
_DEFAULT_MASK_TOPIC = "filter_mask"
_DEFAULT_MAP_TOPIC = "map"


@dataclass(frozen=True)
class NavFilterMasks:
    """The masks a file's filters read, and where the file names each (for messages).

    Attributes:
        settings: the keepout and speed masks with their filter info.
        sources: ``keepout`` / ``speed`` -> the mask server's ``yaml_filename``.
    """

    settings: FilterSettings
    sources: dict[str, Nav2Parameter]


def filter_masks(
    file: Nav2ParamsFile, uses: Iterable[PluginUse]
) -> tuple[NavFilterMasks | None, list[Nav2Parameter]]:
    """The keepout and speed masks the file's active filters read, and the parameters used.

    Raises:
        Nav2ParamsError: located: a filter without ``filter_info_topic``, no info server
            publishing it, no mask server on its ``mask_topic``, a mask file that does not
            exist, a ``type`` that is not the filter's.
    """
    keepout: KeepoutSettings | None = None
    speed: SpeedSettings | None = None
    used: list[Nav2Parameter] = []
    sources: dict[str, Nav2Parameter] = {}
    for use in uses:
        if not use.active or use.plugin_class not in (KEEPOUT_CLASS, SPEED_CLASS):
            continue
        topic = _required(file, use.node, f"{use.instance}.filter_info_topic", used)
        info = _node_with(file, "filter_info_topic", topic)
        if info is None:
            raise file.error(
                topic, f"no costmap_filter_info_server publishes '{clip(topic.value)}'"
            )
        mask_path, filter_type, base, multiplier = _info(file, info, used)
        kind = "keepout" if use.plugin_class == KEEPOUT_CLASS else "speed"
        sources.setdefault(kind, used[-1])
        if use.plugin_class == KEEPOUT_CLASS:
            _check_type(file, filter_type, (KEEPOUT,), "a keepout filter's type is 0")
            keepout = keepout or KeepoutSettings(mask=mask_path)
        else:
            types = (SPEED_FILTER_PERCENT, SPEED_FILTER_ABSOLUTE)
            _check_type(file, filter_type, types, "a speed filter's type is 1 (%) or 2 (m/s)")
            speed = speed or SpeedSettings(
                mask=mask_path,
                type=(
                    SPEED_FILTER_ABSOLUTE
                    if filter_type and filter_type.value == SPEED_FILTER_ABSOLUTE
                    else SPEED_FILTER_PERCENT
                ),
                base=base,
                multiplier=multiplier,
            )
    if keepout is None and speed is None:
        return None, used
    return NavFilterMasks(FilterSettings(keepout=keepout, speed=speed), sources), used


def _required(
    file: Nav2ParamsFile, node: str, name: str, used: list[Nav2Parameter]
) -> Nav2Parameter:
    parameter = file.get(node, name)
    if parameter is None or not isinstance(parameter.value, str) or not parameter.value:
        where = file.get(node, name.split(".")[0] + ".plugin") if parameter is None else parameter
        raise file.error(where, f"{name} must name the topic of its costmap_filter_info_server")
    used.append(parameter)
    return parameter


def _node_with(file: Nav2ParamsFile, name: str, topic: Nav2Parameter) -> str | None:
    """The node whose ``name`` parameter is ``topic``'s value (leading slashes aside)."""
    wanted = str(topic.value).strip("/")
    for node, parameters in file.nodes.items():
        value = parameters.get(name)
        if value is not None and str(value.value).strip("/") == wanted:
            return node
    return None


def _info(
    file: Nav2ParamsFile, node: str, used: list[Nav2Parameter]
) -> tuple[str, Nav2Parameter | None, float, float]:
    """An info server's mask path (relative to the file's folder), type, base, multiplier."""
    numbers = {}
    for name, default in (("base", 0.0), ("multiplier", 1.0)):
        parameter = file.get(node, name)
        value = default if parameter is None else parameter.value
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise file.error(parameter, f"{name} must be a number, got {clip(value)}")
        numbers[name] = float(value)
        if parameter is not None:
            used.append(parameter)
    filter_type = file.get(node, "type")
    if filter_type is not None:
        used.append(filter_type)
    mask_topic = file.get(node, "mask_topic")
    topic_value = _DEFAULT_MASK_TOPIC if mask_topic is None else str(mask_topic.value)
    server = next(
        (
            name
            for name, parameters in file.nodes.items()
            if "yaml_filename" in parameters
            and str(getattr(parameters.get("topic_name"), "value", _DEFAULT_MAP_TOPIC)).strip("/")
            == topic_value.strip("/")
        ),
        None,
    )
    if server is None:
        raise (
            file.error(
                mask_topic, f"no filter mask server (map_server) publishes '{clip(topic_value)}'"
            )
            if mask_topic is not None
            else file.node_error(
                node, f"no filter mask server (map_server) publishes '{topic_value}'"
            )
        )
    yaml_filename = file.nodes[server]["yaml_filename"]
    used.append(yaml_filename)
    return (
        _mask_path(file, yaml_filename),
        filter_type,
        numbers["base"],
        numbers["multiplier"],
    )


def _mask_path(file: Nav2ParamsFile, parameter: Nav2Parameter) -> str:
    """The mask YAML, checked to exist, relative to the parameter file's folder."""
    value = parameter.value
    if not isinstance(value, str) or not value:
        raise file.error(parameter, "yaml_filename must name a mask's map_server YAML file")
    folder = Path(file.path).parent.resolve()
    path = (folder / value).resolve()
    if Path(value).is_absolute() or not path.is_relative_to(folder):
        raise file.error(
            parameter, f"mask file '{clip(value)}' must be inside the parameter file's folder"
        )
    if not path.is_file():
        raise file.error(parameter, f"mask file '{clip(value)}' does not exist")
    return value


def apply_filters(world: World, file: Nav2ParamsFile, masks: NavFilterMasks) -> World:
    """``world`` with the file's keepout and speed masks in place of its own of those kinds.

    Raises:
        Nav2ParamsError: a mask baobab cannot lay on the world (off the map, not a map_server
            map), located at its ``yaml_filename``.
    """
    try:
        return world.with_filters(masks.settings, Path(file.path).parent.resolve())
    except FieldValueError as exc:
        kind = str(exc.key_path[0]) if exc.key_path else "keepout"
        raise file.error(masks.sources.get(kind), str(exc)) from None
    except WorldError as exc:
        raise file.error(
            masks.sources.get("keepout") or masks.sources.get("speed"), str(exc)
        ) from None


def _check_type(
    file: Nav2ParamsFile, parameter: Nav2Parameter | None, allowed: tuple[int, ...], rule: str
) -> None:
    if parameter is None:
        return
    value = parameter.value
    if isinstance(value, bool) or value not in allowed:
        raise file.error(parameter, f"type {clip(value)} does not fit its filter: {rule}")
