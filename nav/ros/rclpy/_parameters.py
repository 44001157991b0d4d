"""A node's parameters with rclpy's rules: declaration, overrides, static typing, descriptors,
read-only parameters and the on-set callbacks.

:class:`~baobab.nav.ros.rclpy.node.Node` delegates its parameter methods here. The rules, as in
rclpy (Humble):

* ``declare_parameter(name, value)`` types the parameter by its value; an override (``--ros-args
  -p``, a params file, a launch file) replaces the value, and one of another type raises
  ``InvalidParameterTypeException`` unless the descriptor allows ``dynamic_typing``;
* a ``Parameter.Type`` instead of a value declares a typed parameter without a value, which
  raises ``ParameterUninitializedException`` when read before it is set;
* the descriptor's ranges and ``read_only`` are enforced; the on-set callbacks run on each
  declaration and set, newest first, and any of them can refuse;
* ``set_parameters`` answers a ``SetParametersResult`` per parameter.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from typing import Any

from baobab.nav.ros.rcl_interfaces.msg import ParameterDescriptor, SetParametersResult
from baobab.nav.ros.rclpy.exceptions import (
    InvalidParameterTypeException,
    InvalidParameterValueException,
    ParameterAlreadyDeclaredException,
    ParameterImmutableException,
    ParameterNotDeclaredException,
    ParameterUninitializedException,
)
from baobab.nav.ros.rclpy.parameter import Parameter, ParameterType

SetCallback = Callable[[list[Parameter]], SetParametersResult]
"""An on-set parameters callback: the parameters about to be set -> accept or refuse."""


class ParameterStore:
    """The parameters of one node.

    Args:
        node_name: the node's name (for messages).
        overrides: values given from outside (command line, params files, launch), by name.
        allow_undeclared: rclpy's ``allow_undeclared_parameters``.
        declare_overrides: rclpy's ``automatically_declare_parameters_from_overrides``.
    """

    def __init__(
        self,
        node_name: str,
        overrides: Mapping[str, Any],
        *,
        allow_undeclared: bool = False,
        declare_overrides: bool = False,
    ) -> None:
        self._node_name = node_name
        self._overrides = dict(overrides)
        self._allow_undeclared = allow_undeclared
        self._values: dict[str, Parameter] = {}
        self._descriptors: dict[str, ParameterDescriptor] = {}
        self._callbacks: list[SetCallback] = []
        if declare_overrides:
            for name, value in self._overrides.items():
                self._values[name] = Parameter(name, value=value)
                self._descriptors[name] = ParameterDescriptor(name=name, dynamic_typing=True)

    # -- declaring --------------------------------------------------------------------------

    def declare(
        self,
        name: str,
        value: Any = None,
        descriptor: ParameterDescriptor | None = None,
        ignore_override: bool = False,
    ) -> Parameter:
        """``Node.declare_parameter``: see the module docstring.

        Raises:
            ParameterAlreadyDeclaredException, InvalidParameterTypeException,
            InvalidParameterValueException, TypeError: as rclpy raises them.
        """
        if not isinstance(name, str):
            raise TypeError("The name must be a string")
        if name in self._values:
            raise ParameterAlreadyDeclaredException([name])
        descriptor = ParameterDescriptor() if descriptor is None else descriptor
        descriptor.name = name
        if isinstance(value, Parameter.Type):
            declared_type, initial = value, None
        else:
            if isinstance(value, Parameter):
                value = value.value
            declared_type = Parameter.Type.from_parameter_value(value)
            initial = value
        if value is None:
            descriptor.dynamic_typing = True
        if descriptor.type == 0 and not descriptor.dynamic_typing:
            descriptor.type = int(declared_type)
        if not ignore_override and name in self._overrides:
            initial = self._overrides[name]
        parameter = self._typed(name, initial, declared_type, descriptor)
        self._check_range(parameter, descriptor, raise_on_failure=True)
        result = self._run_callbacks([parameter])
        if not result.successful:
            raise InvalidParameterValueException(name, parameter.value, result.reason)
        self._values[name] = parameter
        self._descriptors[name] = descriptor
        return parameter

    def _typed(
        self, name: str, value: Any, declared: ParameterType, descriptor: ParameterDescriptor
    ) -> Parameter:
        if value is None:
            return Parameter(name, Parameter.Type.NOT_SET)
        parameter = Parameter(name, value=value)
        if descriptor.dynamic_typing or declared is Parameter.Type.NOT_SET:
            return parameter
        if parameter.type_ is not declared and declared.check(parameter.value):
            return Parameter(name, declared, parameter.value)  # an empty list fits any array
        if parameter.type_ is not declared:
            raise InvalidParameterTypeException(parameter, declared.name)
        return parameter

    def declare_many(
        self, namespace: str, parameters: Iterable[tuple[Any, ...]], ignore_override: bool = False
    ) -> list[Parameter]:
        """``Node.declare_parameters``: ``(name,)``, ``(name, value)`` or ``(name, value,
        descriptor)`` tuples, named ``namespace.name``."""
        declared = []
        for entry in parameters:
            if not isinstance(entry, tuple) or not 1 <= len(entry) <= 3:
                raise TypeError("Invalid parameter tuple: expected (name[, value[, descriptor]])")
            name = f"{namespace}.{entry[0]}" if namespace else entry[0]
            value = entry[1] if len(entry) > 1 else None
            descriptor = entry[2] if len(entry) > 2 else None
            declared.append(self.declare(name, value, descriptor, ignore_override))
        return declared

    def undeclare(self, name: str) -> None:
        """``Node.undeclare_parameter``.

        Raises:
            ParameterNotDeclaredException: ``name`` is not declared.
            ParameterImmutableException: ``name`` is read-only.
        """
        if name not in self._values:
            raise ParameterNotDeclaredException(name)
        if self._descriptors[name].read_only:
            raise ParameterImmutableException(name)
        del self._values[name]
        del self._descriptors[name]

    # -- reading ----------------------------------------------------------------------------

    def has(self, name: str) -> bool:
        """True when ``name`` is declared."""
        return name in self._values

    def get(self, name: str) -> Parameter:
        """``Node.get_parameter``.

        Raises:
            ParameterNotDeclaredException: ``name`` is not declared (and undeclared
                parameters are not allowed).
            ParameterUninitializedException: ``name`` was declared by type and never set.
        """
        if name not in self._values:
            if self._allow_undeclared:
                return Parameter(name, Parameter.Type.NOT_SET)
            raise ParameterNotDeclaredException(name)
        parameter = self._values[name]
        descriptor = self._descriptors[name]
        if parameter.type_ is Parameter.Type.NOT_SET and not descriptor.dynamic_typing:
            raise ParameterUninitializedException(name)
        return parameter

    def get_or(self, name: str, alternative: Parameter | None = None) -> Parameter:
        """``Node.get_parameter_or``: the parameter, or ``alternative`` when not declared."""
        if name in self._values:
            return self._values[name]
        return Parameter(name, Parameter.Type.NOT_SET) if alternative is None else alternative

    def by_prefix(self, prefix: str) -> dict[str, Parameter]:
        """``Node.get_parameters_by_prefix``: ``{name after "prefix.": parameter}``."""
        start = f"{prefix}." if prefix else ""
        return {
            name[len(start) :]: parameter
            for name, parameter in self._values.items()
            if name.startswith(start)
        }

    def describe(self, name: str) -> ParameterDescriptor:
        """``Node.describe_parameter``.

        Raises:
            ParameterNotDeclaredException: ``name`` is not declared.
        """
        if name not in self._descriptors:
            raise ParameterNotDeclaredException(name)
        return self._descriptors[name]

    def set_descriptor(self, name: str, descriptor: ParameterDescriptor) -> None:
        """``Node.set_descriptor`` (the type stays the declared one)."""
        current = self.describe(name)
        if current.read_only:
            raise ParameterImmutableException(name)
        descriptor.name, descriptor.type = name, current.type
        self._descriptors[name] = descriptor

    # -- setting ----------------------------------------------------------------------------

    def set_many(self, parameters: list[Parameter], *, atomically: bool = False) -> list[Any]:
        """``Node.set_parameters`` (one result each) or ``set_parameters_atomically`` (one).

        Raises:
            ParameterNotDeclaredException: a parameter is not declared (and undeclared
                parameters are not allowed).
        """
        for parameter in parameters:
            if not isinstance(parameter, Parameter):
                raise TypeError("parameters must be rclpy.parameter.Parameter instances")
            if parameter.name not in self._values and not self._allow_undeclared:
                raise ParameterNotDeclaredException(parameter.name)
        if atomically:
            result = self._check_all(parameters)
            if result.successful:
                for parameter in parameters:
                    self._store(parameter)
            return [result]
        results = []
        for parameter in parameters:
            result = self._check_all([parameter])
            if result.successful:
                self._store(parameter)
            results.append(result)
        return results

    def _store(self, parameter: Parameter) -> None:
        if parameter.name not in self._descriptors:
            self._descriptors[parameter.name] = ParameterDescriptor(
                name=parameter.name, dynamic_typing=True
            )
        if parameter.type_ is Parameter.Type.NOT_SET:
            self._values.pop(parameter.name, None)  # setting NOT_SET undeclares, as in rclpy
            self._descriptors.pop(parameter.name, None)
        else:
            self._values[parameter.name] = parameter

    def _check_all(self, parameters: list[Parameter]) -> SetParametersResult:
        for parameter in parameters:
            descriptor = self._descriptors.get(parameter.name)
            if descriptor is None:
                continue
            if descriptor.read_only:
                return SetParametersResult(
                    successful=False,
                    reason=f"Trying to set a read-only parameter: {parameter.name}.",
                )
            declared = Parameter.Type(descriptor.type)
            if (
                not descriptor.dynamic_typing
                and parameter.type_ is not Parameter.Type.NOT_SET
                and not declared.check(parameter.value)
            ):
                return SetParametersResult(
                    successful=False,
                    reason=(
                        f"Wrong parameter type, parameter {{{parameter.name}}} is of type "
                        f"{{{declared.name}}}, setting it to {{{parameter.type_.name}}} is not "
                        "allowed."
                    ),
                )
            range_result = self._check_range(parameter, descriptor, raise_on_failure=False)
            if not range_result.successful:
                return range_result
        return self._run_callbacks(parameters)

    def _check_range(
        self, parameter: Parameter, descriptor: ParameterDescriptor, *, raise_on_failure: bool
    ) -> SetParametersResult:
        value = parameter.value
        bounds = descriptor.floating_point_range or descriptor.integer_range
        reason = ""
        if bounds and isinstance(value, int | float) and not isinstance(value, bool):
            rule = bounds[0]
            low, high, step = rule.from_value, rule.to_value, rule.step
            tolerance = 1e-9 * max(1.0, abs(high - low))
            if not low - tolerance <= value <= high + tolerance:
                reason = f"Parameter {parameter.name} out of range. Min: {low}, Max: {high}"
            elif step and not _on_step(value, low, high, step, tolerance):
                reason = (
                    f"The parameter value ({value}) is not close enough to a valid step. "
                    f"Min: {low}, Max: {high}, Step: {step}"
                )
        if reason and raise_on_failure:
            raise InvalidParameterValueException(parameter.name, value, reason)
        return SetParametersResult(successful=not reason, reason=reason)

    def _run_callbacks(self, parameters: list[Parameter]) -> SetParametersResult:
        for callback in self._callbacks:
            result = callback(parameters)
            if not isinstance(result, SetParametersResult):
                raise TypeError(
                    "An on-set parameters callback must return a SetParametersResult, "
                    f"got {type(result).__name__}"
                )
            if not result.successful:
                return result
        return SetParametersResult(successful=True)

    def add_callback(self, callback: SetCallback) -> None:
        """``Node.add_on_set_parameters_callback``: run before the earlier ones."""
        self._callbacks.insert(0, callback)

    def remove_callback(self, callback: SetCallback) -> None:
        """``Node.remove_on_set_parameters_callback``.

        Raises:
            ValueError: ``callback`` was not added.
        """
        self._callbacks.remove(callback)


def _on_step(value: float, low: float, high: float, step: float, tolerance: float) -> bool:
    if math.isclose(value, high, abs_tol=tolerance):
        return True
    steps = (value - low) / step
    return abs(steps - round(steps)) * step <= tolerance
