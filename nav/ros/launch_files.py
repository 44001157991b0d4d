"""Python launch files: what ``baobab ros launch FILE.launch.py name:=value`` runs.

The file's ``generate_launch_description()`` is called with the ROS modules served, and its
entities are evaluated in order, as ``ros2 launch`` does:

* ``DeclareLaunchArgument``: the value given on the command line, else the default; an
  argument without either, or outside its ``choices``, is an error;
* ``LaunchConfiguration``: the argument's value (its ``default`` when not declared);
* ``IncludeLaunchDescription(PythonLaunchDescriptionSource(path), launch_arguments=...)``:
  another local launch file (a relative path is taken from the including file's folder),
  with the given arguments on top of the current ones;
* ``LogInfo``: prints its message;
* ``launch_ros.actions.Node``: a node file found from ``executable`` (``EXECUTABLE.py`` next to
  the launch file, in its parent folder, or in ``PACKAGE/`` there, as a ROS package lays out
  ``launch/`` beside ``package_name/``), run with ``arguments``, then ``--ros-args`` with
  ``ros_arguments``, its ``name`` and ``namespace``, ``remappings`` and ``parameters``
  (mappings become ``-p`` overrides, with launch_ros's rule that a substituted text is read
  as YAML; other entries are params files).

Every mistake is reported at the line of the launch file that made the entity.
"""

from __future__ import annotations

import runpy
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from baobab.nav.ros import ros_shims
from baobab.nav.ros.launch._entities import (
    DeclareLaunchArgument,
    IncludeLaunchDescription,
    LaunchConfiguration,
    LaunchDescription,
    LaunchFileError,
    Located,
    LogInfo,
    Node,
    ParameterValue,
    PythonLaunchDescriptionSource,
    Substitution,
    TextSubstitution,
)
from baobab.nav.ros.script_files import check_script

MAX_INCLUDE_DEPTH = 20
"""How deeply launch files may include each other (a cycle stops here)."""


@dataclass(frozen=True)
class LaunchedNode:
    """A node file a launch file starts, with its command line after its own path."""

    path: Path
    argv: list[str]


def _description(path: Path) -> LaunchDescription:
    check_script(path)
    namespace = runpy.run_path(str(path), run_name="__launch__")
    generate = namespace.get("generate_launch_description")
    if not callable(generate):
        raise LaunchFileError(
            str(path), 1, 1, "a launch file defines generate_launch_description()"
        )
    description = generate()
    if not isinstance(description, LaunchDescription):
        raise LaunchFileError(
            str(path), 1, 1, "generate_launch_description() must return a LaunchDescription"
        )
    return description


def describe_arguments(path: Path) -> str:
    """``ros2 launch --show-args``: the arguments the file declares, with their defaults."""
    with ros_shims():
        entities = _description(path).entities
    lines = ["Arguments (pass arguments as '<name>:=<value>'):", ""]
    declared = [entity for entity in entities if isinstance(entity, DeclareLaunchArgument)]
    for argument in declared:
        default = argument.default_value
        shown = "(required)" if default is None else f"(default: '{_text(default, {})}')"
        lines += [
            f"    '{argument.name}':",
            f"        {argument.description}",
            f"        {shown}",
            "",
        ]
    if not declared:
        lines.append("  No arguments.")
    return "\n".join(lines) + "\n"


def nodes_of_launch_file(path: Path, arguments: Mapping[str, str]) -> list[LaunchedNode]:
    """The node files ``path`` starts with the launch ``arguments`` (module docstring).

    Raises:
        LaunchFileError, ScriptError: a located mistake in the launch file.
    """
    nodes: list[LaunchedNode] = []
    with ros_shims():
        _evaluate(path, dict(arguments), nodes, depth=0)
    return nodes


def _evaluate(path: Path, context: dict[str, str], nodes: list[LaunchedNode], depth: int) -> None:
    if depth > MAX_INCLUDE_DEPTH:
        raise LaunchFileError(
            str(path), 1, 1, f"launch files include each other over {MAX_INCLUDE_DEPTH} deep"
        )
    for entity in _description(path).entities:
        if isinstance(entity, DeclareLaunchArgument):
            _declare(entity, context)
        elif isinstance(entity, IncludeLaunchDescription):
            _include(entity, path, context, nodes, depth)
        elif isinstance(entity, LogInfo):
            print(f"[INFO] [launch.user]: {_text(entity.msg, context)}")
        elif isinstance(entity, Node):
            nodes.append(_node(entity, path, context))
        elif isinstance(entity, Located):
            raise entity.error(f"{type(entity).__name__} cannot stand alone in a LaunchDescription")
        else:
            raise LaunchFileError(
                str(path), 1, 1, f"a LaunchDescription holds actions, not {type(entity).__name__}"
            )


def _declare(argument: DeclareLaunchArgument, context: dict[str, str]) -> None:
    if argument.name not in context:
        if argument.default_value is None:
            raise argument.error(
                f"launch argument '{argument.name}' is required ({argument.description}); "
                f"give it as {argument.name}:=VALUE"
            )
        context[argument.name] = _text(argument.default_value, context)
    if argument.choices is not None and context[argument.name] not in argument.choices:
        raise argument.error(
            f"launch argument '{argument.name}' is '{context[argument.name]}', expected one of "
            f"{argument.choices}"
        )


def _include(
    entity: IncludeLaunchDescription,
    path: Path,
    context: dict[str, str],
    nodes: list[LaunchedNode],
    depth: int,
) -> None:
    source = entity.source
    if not isinstance(source, PythonLaunchDescriptionSource):
        raise entity.error("IncludeLaunchDescription takes a PythonLaunchDescriptionSource")
    target = Path(_text(source.launch_file_path, context))
    if not target.is_absolute():
        target = path.parent / target
    scoped = dict(context)
    for pair in entity.launch_arguments:
        if not isinstance(pair, tuple) or len(pair) != 2:
            raise entity.error("launch_arguments are (name, value) pairs, e.g. {...}.items()")
        scoped[_text(pair[0], context)] = _text(pair[1], context)
    if not target.is_file():
        raise source.error(f"included launch file {target} does not exist")
    _evaluate(target, scoped, nodes, depth + 1)


def _text(value: Any, context: Mapping[str, str]) -> str:
    """The text of a value made of strings and substitutions."""
    if isinstance(value, list | tuple):
        return "".join(_text(part, context) for part in value)
    if isinstance(value, LaunchConfiguration):
        name = _text(value.variable_name, context)
        if name in context:
            return context[name]
        if value.default is not None:
            return _text(value.default, context)
        raise value.error(f"launch configuration '{name}' does not exist (declare the argument)")
    if isinstance(value, TextSubstitution):
        return value.text
    if isinstance(value, Substitution):
        raise value.error(f"{type(value).__name__} is not supported by baobab ros launch")
    if isinstance(value, str | Path):
        return str(value)
    raise LaunchFileError("<launch>", 1, 1, f"cannot use {value!r} as text")


def _node(node: Node, path: Path, context: Mapping[str, str]) -> LaunchedNode:
    executable = _text(node.executable, context).removesuffix(".py")
    package = None if node.package is None else _text(node.package, context)
    folder = path.parent
    candidates = [folder / f"{executable}.py", folder.parent / f"{executable}.py"]
    if package is not None:
        candidates += [
            folder.parent / package / f"{executable}.py",
            folder / package / f"{executable}.py",
        ]
    found = next((candidate for candidate in candidates if candidate.is_file()), None)
    if found is None:
        looked = ", ".join(str(candidate) for candidate in candidates)
        raise node.error(f"node executable '{executable}' not found: looked for {looked}")
    argv = [_text(argument, context) for argument in node.arguments]
    argv += ["--ros-args", *(_text(argument, context) for argument in node.ros_arguments)]
    if node.name is not None:
        argv += ["-r", f"__node:={_text(node.name, context)}"]
    if node.namespace is not None:
        argv += ["-r", f"__ns:=/{_text(node.namespace, context).strip('/')}"]
    for pair in node.remappings:
        source, target = pair
        argv += ["-r", f"{_text(source, context)}:={_text(target, context)}"]
    for entry in node.parameters:
        argv += _parameter_arguments(node, entry, context)
    return LaunchedNode(found, argv)


def _parameter_arguments(node: Node, entry: Any, context: Mapping[str, str]) -> list[str]:
    if not isinstance(entry, Mapping):
        return ["--params-file", _text(entry, context)]
    words = []
    for name, value in _flat(entry, ""):
        words += ["-p", f"{name}:={_parameter_text(node, name, value, context)}"]
    return words


def _flat(values: Mapping[Any, Any], prefix: str) -> list[tuple[str, Any]]:
    flat = []
    for key, value in values.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping):
            flat += _flat(value, f"{name}.")
        else:
            flat.append((name, value))
    return flat


def _parameter_text(node: Node, name: str, value: Any, context: Mapping[str, str]) -> str:
    """The ``-p`` text of one parameter, evaluated as launch_ros evaluates it."""
    if isinstance(value, ParameterValue):
        text = _text(value.value, context)
        return yaml.safe_dump(text, default_style="'").strip() if value.value_type is str else text
    if isinstance(value, bool | int | float):
        return yaml.safe_dump(value).strip().removesuffix("...").strip()
    if isinstance(value, list | tuple) and not any(
        isinstance(item, Substitution) for item in value
    ):
        return yaml.safe_dump(list(value), default_flow_style=True).strip()
    text = _text(value, context)
    try:
        parsed = yaml.safe_load(text)
    except yaml.YAMLError:
        raise node.error(
            f"parameter '{name}': cannot read '{text}' as YAML; wrap a text in "
            "ParameterValue(value, value_type=str)"
        ) from None
    if isinstance(parsed, list) and len(parsed) == 1 and isinstance(parsed[0], list):
        parsed = parsed[0]  # `goal:="[[T, x, ...]]"`, as the course passes an array argument
    if isinstance(parsed, list) and (
        not parsed
        or len({type(item) for item in parsed}) != 1
        or not isinstance(parsed[0], bool | int | float | str)
    ):
        raise node.error(
            f"parameter '{name}' = {text}: Expected a non-empty sequence, with items of uniform "
            "type. Allowed sequence item types are bool, int, float, str."
        )
    return yaml.safe_dump(parsed, default_flow_style=True).strip().removesuffix("...").strip()
