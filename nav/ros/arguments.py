"""ROS command-line arguments (``--ros-args ...``), params files and name resolution.

What a node takes from ``--ros-args`` (as rcl reads it):

* ``-p name:=value`` / ``--param``: a parameter override for every node, the value read as YAML
  (``0.1`` is a double, ``1`` an integer, ``[1.0, 2.0]`` a double array, ``tmp`` a string);
* ``--params-file FILE``: ``node: {ros__parameters: {...}}`` entries, the node given by name,
  by fully qualified name, nested under its namespace, or as ``/**`` for every node;
* ``-r from:=to`` / ``--remap`` (or ``node:from:=to``), including ``__node:=name`` and
  ``__ns:=/ns``;
* ``--log-level [name:=]level``; other rcl flags are accepted and ignored.

A lone ``--`` ends the ROS arguments; several ``--ros-args`` sections add up.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import yaml

from baobab.sim.errors import BaobabError

_NAME = re.compile(r"^[A-Za-z_~{/][A-Za-z0-9_/{}~]*$")
_IGNORED_WITH_VALUE = {"--log-config-file", "-e", "--enclave"}
_IGNORED_FLAGS = {
    "--enable-stdout-logs",
    "--disable-stdout-logs",
    "--enable-rosout-logs",
    "--disable-rosout-logs",
    "--enable-external-lib-logs",
    "--disable-external-lib-logs",
}


class RosArgumentError(BaobabError, ValueError):
    """A ``--ros-args`` rule or params file that cannot be read."""


@dataclass(frozen=True)
class Remap:
    """One ``-r`` rule: ``source`` becomes ``target`` (for ``node`` only, when given)."""

    source: str
    target: str
    node: str | None = None


@dataclass
class RosArguments:
    """What ``--ros-args`` sections said (see the module docstring)."""

    parameters: dict[str, Any] = field(default_factory=dict)
    params_files: list[dict[str, dict[str, Any]]] = field(default_factory=list)
    remaps: list[Remap] = field(default_factory=list)
    log_levels: dict[str, str] = field(default_factory=dict)
    other: list[str] = field(default_factory=list)
    """The arguments outside ``--ros-args`` sections (``rclpy.utilities.remove_ros_args``)."""

    def overrides_for(self, node_name: str, namespace: str) -> dict[str, Any]:
        """The parameter overrides that apply to a node: params files, then ``-p``."""
        values: dict[str, Any] = {}
        for entries in self.params_files:
            for pattern, parameters in entries.items():
                if _node_matches(pattern, node_name, namespace):
                    values.update(parameters)
        values.update(self.parameters)
        return values

    def merged(self, other: RosArguments) -> RosArguments:
        """These arguments, then ``other``'s (``other`` wins on the same parameter)."""
        return RosArguments(
            parameters={**self.parameters, **other.parameters},
            params_files=[*self.params_files, *other.params_files],
            remaps=[*other.remaps, *self.remaps],
            log_levels={**self.log_levels, **other.log_levels},
            other=[*self.other, *other.other],
        )


def parse_ros_arguments(argv: Sequence[str]) -> RosArguments:
    """Read every ``--ros-args`` section of ``argv``.

    Raises:
        RosArgumentError: a rule that cannot be read, or a params file that cannot be loaded.
    """
    parsed = RosArguments()
    words = iter(argv)
    inside = False
    for word in words:
        if word == "--ros-args":
            inside = True
        elif not inside:
            parsed.other.append(word)
        elif word == "--":
            inside = False
        else:
            _read_rule(word, words, parsed)
    return parsed


def _read_rule(flag: str, words: Iterator[str], parsed: RosArguments) -> None:
    if flag in _IGNORED_FLAGS:
        return
    if flag not in ("-p", "--param", "-r", "--remap", "--params-file", "--log-level"):
        if flag in _IGNORED_WITH_VALUE:
            next(words, None)
            return
        raise RosArgumentError(f"--ros-args: unknown argument '{flag}'")
    value = next(words, None)
    if value is None:
        raise RosArgumentError(f"--ros-args: '{flag}' needs a value after it")
    if flag in ("-p", "--param"):
        name, separator, text = value.partition(":=")
        if not separator or not name:
            raise RosArgumentError(
                f"--ros-args: cannot read parameter override '{flag} {value}': expected name:=value"
            )
        parsed.parameters[name] = parameter_value_from_text(text)
    elif flag in ("-r", "--remap"):
        parsed.remaps.append(_remap_rule(flag, value))
    elif flag == "--params-file":
        parsed.params_files.append(load_params_file(Path(value)))
    else:
        name, separator, level = value.rpartition(":=")
        parsed.log_levels[name if separator else ""] = level.upper()


def _remap_rule(flag: str, rule: str) -> Remap:
    source, separator, target = rule.partition(":=")
    if not separator or not source or not target:
        raise RosArgumentError(
            f"--ros-args: cannot read remapping '{flag} {rule}': expected from:=to"
        )
    node, colon, name = source.rpartition(":")
    return Remap(name, target, node) if colon and node else Remap(source, target)


def parameter_value_from_text(text: str) -> Any:
    """A parameter value from its command-line text, read as YAML as rcl does.

    Raises:
        RosArgumentError: a mapping, or a list mixing types.
    """
    try:
        value = yaml.safe_load(text) if text.strip() else text
    except yaml.YAMLError:
        return text
    return _parameter_value(value, text)


def _parameter_value(value: Any, shown: str) -> Any:
    if value is None:
        return shown if shown.strip() not in ("", "~", "null", "Null", "NULL") else None
    if isinstance(value, bool | int | float | str):
        return value
    if isinstance(value, list):
        kinds = {float if type(item) is int else type(item) for item in value}
        if kinds == {float} and any(type(item) is float for item in value):
            return [float(item) for item in value]
        if len(kinds) <= 1 and all(isinstance(item, bool | int | float | str) for item in value):
            return value
    raise RosArgumentError(
        f"parameter value {shown!r} is not a boolean, integer, double, string or a list of "
        "one of these"
    )


def load_params_file(path: Path) -> dict[str, dict[str, Any]]:
    """The ``ros__parameters`` of a params file, by node pattern (``/**``, ``/ns/node``).

    Raises:
        RosArgumentError: the file cannot be read, is not YAML, or is not shaped as ROS's.
    """
    try:
        document = yaml.safe_load(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise RosArgumentError(f"{path}: cannot read the params file: {exc.strerror}") from None
    except yaml.YAMLError as exc:
        raise RosArgumentError(f"{path}: not a YAML params file: {exc}") from None
    if not isinstance(document, dict):
        raise RosArgumentError(f"{path}:1:1: a params file maps node names to ros__parameters")
    entries: dict[str, dict[str, Any]] = {}
    _collect(document, "", entries, path)
    return entries


def _collect(
    document: dict[Any, Any], prefix: str, out: dict[str, dict[str, Any]], path: Path
) -> None:
    for key, value in document.items():
        name = f"{prefix}/{str(key).strip('/')}" if prefix else str(key)
        if not isinstance(value, dict):
            raise RosArgumentError(f"{path}: '{name}' must map to ros__parameters")
        if "ros__parameters" in value:
            parameters = value["ros__parameters"]
            if not isinstance(parameters, dict):
                raise RosArgumentError(f"{path}: '{name}.ros__parameters' must be a mapping")
            flat: dict[str, Any] = {}
            _flatten(parameters, "", flat, path)
            out.setdefault(name, {}).update(flat)
        else:
            _collect(value, name, out, path)


def _flatten(values: dict[Any, Any], prefix: str, out: dict[str, Any], path: Path) -> None:
    for key, value in values.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            _flatten(value, f"{name}.", out, path)
        else:
            try:
                out[name] = _parameter_value(value, str(value))
            except RosArgumentError as exc:
                raise RosArgumentError(f"{path}: parameter '{name}': {exc}") from None


def _node_matches(pattern: str, node_name: str, namespace: str) -> bool:
    if pattern in ("/**", "**"):
        return True
    full = f"{namespace.rstrip('/')}/{node_name}"
    if pattern.startswith("/**/"):
        return pattern[4:] == node_name
    return pattern.lstrip("/") in (node_name, full.lstrip("/"))


def expand_topic_name(name: str, node_name: str, namespace: str) -> str:
    """The fully qualified name of ``name`` for a node (``~`` is the node's private namespace).

    Raises:
        ValueError: ``name`` breaks ROS's naming rules (rclpy raises
            ``InvalidTopicNameException`` from this).
    """
    if name != "/" and (not _NAME.match(name) or "//" in name or name.endswith("/")):
        raise ValueError(
            "topic and service names must not be empty, must start with a letter, '_', "
            "'~' or '/', and hold only letters, digits, '_' and single '/'"
        )
    base = namespace.rstrip("/")
    if name.startswith("~"):
        return f"{base}/{node_name}{name[1:]}" if len(name) > 1 else f"{base}/{node_name}"
    return name if name.startswith("/") else f"{base}/{name}"


def remap_topic(name: str, remaps: Sequence[Remap], node_name: str, namespace: str) -> str:
    """``name`` (fully qualified) after the first ``-r`` rule that matches it."""
    for rule in remaps:
        if rule.source.startswith("__") or (rule.node is not None and rule.node != node_name):
            continue
        try:
            if expand_topic_name(rule.source, node_name, namespace) == name:
                return expand_topic_name(rule.target, node_name, namespace)
        except ValueError:
            continue
    return name


def node_identity(
    node_name: str, namespace: str | None, remaps: Sequence[Remap]
) -> tuple[str, str]:
    """The node's name and namespace after ``__node``/``__name`` and ``__ns`` rules."""
    name, space = node_name, "/" + (namespace or "").strip("/")
    for rule in remaps:
        if rule.node is not None and rule.node != node_name:
            continue
        if rule.source in ("__node", "__name"):
            name = rule.target
        elif rule.source == "__ns":
            space = "/" + rule.target.strip("/")
    return name, space
