"""What launch files build: descriptions, arguments, includes, substitutions and nodes.

Each object remembers where the launch file made it (``file:line``), so that a mistake found
while the description is evaluated (a missing argument, an unknown executable) is reported
there. Evaluation is :mod:`baobab.nav.ros.launch_files`'s job; these classes only hold what the
file said. Anything else a launch file asks of ``launch`` or ``launch_ros`` is refused with a
located error naming it (:func:`unsupported`).
"""

from __future__ import annotations

import sys
from collections.abc import Iterable
from typing import Any

from baobab.sim.errors import SourceError


class LaunchFileError(SourceError):
    """A launch file asks for something baobab cannot do, located where it asks."""


def caller_location(depth: int = 2) -> tuple[str, int]:
    """The file and line of the launch-file code that called (skipping baobab's frames)."""
    frame = sys._getframe(depth)
    while frame.f_back is not None and frame.f_globals.get("__name__", "").startswith(
        "baobab.nav.ros"
    ):
        frame = frame.f_back
    return frame.f_code.co_filename, frame.f_lineno


class Located:
    """Remembers where the launch file created it."""

    def __init__(self) -> None:
        self.location = caller_location(3)

    def error(self, message: str) -> LaunchFileError:
        """A located error at this object's creation."""
        path, line = self.location
        return LaunchFileError(path, line, 1, message)


class Substitution(Located):
    """A value resolved when the description is evaluated."""


class LaunchConfiguration(Substitution):
    """The value of a launch argument (``launch.substitutions.LaunchConfiguration``)."""

    def __init__(self, variable_name: Any, *, default: Any = None) -> None:
        super().__init__()
        self.variable_name = variable_name
        self.default = default


class TextSubstitution(Substitution):
    """A fixed text."""

    def __init__(self, *, text: str) -> None:
        super().__init__()
        self.text = text


class LaunchDescription(Located):
    """The entities a launch file's ``generate_launch_description()`` returns."""

    def __init__(self, initial_entities: Iterable[Any] | None = None, **kwargs: Any) -> None:
        super().__init__()
        self.entities: list[Any] = list(initial_entities or [])

    def add_action(self, action: Any) -> None:
        """Append an action."""
        self.entities.append(action)

    def add_entity(self, entity: Any) -> None:
        """Append an entity."""
        self.entities.append(entity)


class DeclareLaunchArgument(Located):
    """A launch argument with an optional default and allowed values."""

    def __init__(
        self,
        name: str,
        *,
        default_value: Any = None,
        description: str | None = None,
        choices: list[str] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__()
        self.name = name
        self.default_value = default_value
        self.description = description or "no description given"
        self.choices = choices


class PythonLaunchDescriptionSource(Located):
    """A Python launch file to include."""

    def __init__(self, launch_file_path: Any) -> None:
        super().__init__()
        self.launch_file_path = launch_file_path


class IncludeLaunchDescription(Located):
    """Another local launch file, with arguments for it."""

    def __init__(
        self, launch_description_source: Any, *, launch_arguments: Any = None, **kwargs: Any
    ):
        super().__init__()
        self.source = launch_description_source
        self.launch_arguments = list(launch_arguments or [])


class LogInfo(Located):
    """A message printed when the description is evaluated."""

    def __init__(self, *, msg: Any, **kwargs: Any) -> None:
        super().__init__()
        self.msg = msg


NODE_OPTIONS_ACCEPTED = frozenset(
    {
        "output",
        "emulate_tty",
        "respawn",
        "respawn_delay",
        "sigterm_timeout",
        "sigkill_timeout",
        "additional_env",
    }
)


class Node(Located):
    """``launch_ros.actions.Node``: a node file with parameters, arguments and remappings."""

    def __init__(
        self,
        *,
        executable: Any,
        package: Any = None,
        name: Any = None,
        namespace: Any = None,
        exec_name: Any = None,
        parameters: Any = None,
        remappings: Any = None,
        ros_arguments: Any = None,
        arguments: Any = None,
        **options: Any,
    ) -> None:
        super().__init__()
        unknown = sorted(set(options) - NODE_OPTIONS_ACCEPTED)
        if unknown:
            raise self.error(
                f"launch_ros Node option {', '.join(unknown)} is not supported by baobab ros "
                "launch (it supports executable, package, name, namespace, parameters, "
                "remappings, ros_arguments and arguments)"
            )
        self.executable = executable
        self.package = package
        self.name = name
        self.namespace = namespace
        self.parameters = list(parameters or [])
        self.remappings = list(remappings or [])
        self.ros_arguments = list(ros_arguments or [])
        self.arguments = list(arguments or [])


class ParameterValue(Located):
    """``launch_ros.parameter_descriptions.ParameterValue``: a value with an explicit type."""

    def __init__(self, value: Any, *, value_type: Any = None) -> None:
        super().__init__()
        self.value = value
        self.value_type = value_type


def unsupported(module: str, name: str) -> Any:
    """A stand-in for ``module.name`` that refuses to be used, located where it is used."""
    if name.startswith("__"):
        raise AttributeError(name)

    def refuse(*args: Any, **kwargs: Any) -> Any:
        path, line = caller_location(2)
        raise LaunchFileError(
            path,
            line,
            1,
            f"{module}.{name} is not supported by baobab ros launch; it runs LaunchDescription, "
            "DeclareLaunchArgument, LaunchConfiguration, IncludeLaunchDescription of a local "
            "file, LogInfo and launch_ros Node",
        )

    refuse.__name__ = name
    return refuse
