"""The ``collision_monitor`` node of a Nav2 parameter file, as one layer of the monitor.

A parameter file holds Nav2's collision monitor under ``collision_monitor: ros__parameters:``
with the names a ``collision_monitor:`` block takes (:mod:`baobab.nav.collision_monitor_params`).
:func:`file_monitor_block` turns the file's dotted parameters back into that mapping, so the
file is one more layer between the world's block and the mission's (or the navigator's)
(:func:`~baobab.nav.collision_monitor_config.layered_collision_monitor`);
:func:`file_monitor_error` locates a mistake of that layer at the parameter that holds it.
Nothing here loads numpy: ``baobab validate`` uses it.
"""

from __future__ import annotations

from typing import Any

from baobab.nav.collision_monitor_params import CollisionMonitorConfigError
from baobab.nav.nav2_params_file import Nav2Parameter, Nav2ParamsError, Nav2ParamsFile

NODE = "collision_monitor"
"""The node's name in a Nav2 parameter file."""


def file_monitor_block(file: Nav2ParamsFile | None) -> dict[str, Any] | None:
    """The file's ``collision_monitor`` parameters as a nested mapping (dotted names split),
    or None when the file does not configure the node (or there is no file).

    Raises:
        Nav2ParamsError: a name that is both a value and a mapping (``a: 1`` and ``a.b: 2``).
    """
    if file is None or not file.nodes.get(NODE):
        return None
    block: dict[str, Any] = {}
    for parameter in file.names(NODE):
        *parents, leaf = parameter.name.split(".")
        target = block
        for part in parents:
            target = target.setdefault(part, {})
            if not isinstance(target, dict):
                raise file.error(parameter, f"'{part}' is a value and a mapping of parameters")
        if isinstance(target.get(leaf), dict):
            raise file.error(parameter, f"'{leaf}' is a value and a mapping of parameters")
        target[leaf] = parameter.value
    return block


def file_monitor_error(file: Nav2ParamsFile, error: CollisionMonitorConfigError) -> Nav2ParamsError:
    """``error`` located in ``file``: at the parameter its key path names (or the nearest one
    below it, or the node's section)."""
    message = error.describe(NODE)
    parameter = _parameter_at(file, tuple(str(p) for p in error.key_path if isinstance(p, str)))
    if parameter is None:
        return file.node_error(NODE, message)
    return file.error(parameter, message)


def _parameter_at(file: Nav2ParamsFile, names: tuple[str, ...]) -> Nav2Parameter | None:
    for length in range(len(names), 0, -1):
        dotted = ".".join(names[:length])
        found = file.nodes.get(NODE, {}).get(dotted)
        if found is not None:
            return found
        below = next(file.names(NODE, dotted + "."), None)
        if below is not None:
            return below
    return None
