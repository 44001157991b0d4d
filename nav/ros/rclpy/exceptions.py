"""``rclpy.exceptions``: the errors rclpy raises for parameters, names and shutdown."""

from __future__ import annotations

__all__ = [
    "InvalidParameterException",
    "InvalidParameterTypeException",
    "InvalidParameterValueException",
    "InvalidTopicNameException",
    "NotInitializedException",
    "ParameterAlreadyDeclaredException",
    "ParameterException",
    "ParameterImmutableException",
    "ParameterNotDeclaredException",
    "ParameterUninitializedException",
    "ROSInterruptException",
]


class NotInitializedException(Exception):
    """rclpy was used before ``rclpy.init()``."""

    def __init__(self, *args: object) -> None:
        super().__init__("rclpy.init() has not been called", *args)


class ROSInterruptException(Exception):
    """A sleep was interrupted by shutdown."""


class InvalidTopicNameException(Exception):
    """A topic name breaks ROS's naming rules."""

    def __init__(self, name: str, reason: str) -> None:
        super().__init__(f"Invalid topic name '{name}': {reason}")


class ParameterException(Exception):
    """Base of the parameter errors: carries the message and the parameter names."""

    def __init__(self, error_msg: str, parameters: object, *args: object) -> None:
        super().__init__(f"{error_msg}: {parameters}", *args)


class ParameterNotDeclaredException(ParameterException):
    """A parameter was used without being declared."""

    def __init__(self, parameters: object, *args: object) -> None:
        super().__init__("Invalid access to undeclared parameter(s)", parameters, *args)


class ParameterAlreadyDeclaredException(ParameterException):
    """A parameter was declared twice."""

    def __init__(self, parameters: object, *args: object) -> None:
        super().__init__("Parameter(s) already declared", parameters, *args)


class InvalidParameterException(ParameterException):
    """A parameter name breaks the naming rules."""

    def __init__(self, parameter: object, *args: object) -> None:
        super().__init__("Invalid parameter name", parameter, *args)


class InvalidParameterTypeException(ParameterException):
    """A value of a type the parameter does not take."""

    def __init__(self, desired_parameter: object, expected_type: str, *args: object) -> None:
        name = getattr(desired_parameter, "name", desired_parameter)
        value_type = getattr(getattr(desired_parameter, "type_", None), "name", "?")
        super().__init__(
            f"Trying to set parameter '{name}' to '{getattr(desired_parameter, 'value', '?')}' "
            f"of type '{value_type}', expecting type '{expected_type}'",
            name,
            *args,
        )


class InvalidParameterValueException(ParameterException):
    """A value the parameter's descriptor or an on-set callback refuses."""

    def __init__(self, parameter: str, value: object, reason: str, *args: object) -> None:
        super().__init__(
            f"Invalid parameter value ({value}) for parameter. Reason: {reason}",
            parameter,
            *args,
        )


class ParameterImmutableException(ParameterException):
    """A read-only parameter was set."""

    def __init__(self, parameter: object, *args: object) -> None:
        super().__init__("Attempted to modify read-only parameter", parameter, *args)


class ParameterUninitializedException(ParameterException):
    """A statically typed parameter declared without a value was read."""

    def __init__(self, parameter: object, *args: object) -> None:
        super().__init__("The parameter is uninitialized", parameter, *args)
