"""``rclpy.parameter``: a named, typed parameter value (``Parameter`` and ``Parameter.Type``)."""

from __future__ import annotations

from array import array
from enum import IntEnum
from typing import Any

from baobab.nav.ros.rcl_interfaces.msg import ParameterValue

__all__ = ["Parameter", "ParameterType", "parameter_value_to_python"]


class ParameterType(IntEnum):
    NOT_SET = 0
    BOOL = 1
    INTEGER = 2
    DOUBLE = 3
    STRING = 4
    BYTE_ARRAY = 5
    BOOL_ARRAY = 6
    INTEGER_ARRAY = 7
    DOUBLE_ARRAY = 8
    STRING_ARRAY = 9

    @classmethod
    def from_parameter_value(cls, value: Any) -> ParameterType:
        """The type rclpy infers from a Python value (an empty list is a BYTE_ARRAY, as there).

        Raises:
            TypeError: a value no parameter type holds.
        """
        if value is None:
            return cls.NOT_SET
        if isinstance(value, bool):
            return cls.BOOL
        if isinstance(value, int):
            return cls.INTEGER
        if isinstance(value, float):
            return cls.DOUBLE
        if isinstance(value, str):
            return cls.STRING
        if isinstance(value, list | tuple | array):
            for kind, item_type in _ARRAY_ITEMS.items():
                if all(_is_item(item, item_type) for item in value):
                    return kind
            raise TypeError("The given value is not a list of one of the allowed types")
        raise TypeError(f"The given value is not one of the allowed types '{type(value)}'.")

    def check(self, value: Any) -> bool:
        """True when ``value`` is of this type."""
        if self is ParameterType.NOT_SET:
            return value is None
        try:
            inferred = ParameterType.from_parameter_value(value)
        except TypeError:
            return False
        if inferred is self:
            return True
        is_list = isinstance(value, list | tuple | array)
        return (
            is_list
            and self in _ARRAY_ITEMS
            and all(_is_item(item, _ARRAY_ITEMS[self]) for item in value)
        )


_ARRAY_ITEMS: dict[ParameterType, type] = {
    ParameterType.BYTE_ARRAY: bytes,
    ParameterType.BOOL_ARRAY: bool,
    ParameterType.INTEGER_ARRAY: int,
    ParameterType.DOUBLE_ARRAY: float,
    ParameterType.STRING_ARRAY: str,
}


def _is_item(item: Any, item_type: type) -> bool:
    if item_type is int:
        return isinstance(item, int) and not isinstance(item, bool)
    return isinstance(item, item_type)


_VALUE_FIELDS = {
    ParameterType.BOOL: "bool_value",
    ParameterType.INTEGER: "integer_value",
    ParameterType.DOUBLE: "double_value",
    ParameterType.STRING: "string_value",
    ParameterType.BYTE_ARRAY: "byte_array_value",
    ParameterType.BOOL_ARRAY: "bool_array_value",
    ParameterType.INTEGER_ARRAY: "integer_array_value",
    ParameterType.DOUBLE_ARRAY: "double_array_value",
    ParameterType.STRING_ARRAY: "string_array_value",
}


class Parameter:
    """A parameter: ``name``, ``type_`` and ``value`` (``rclpy.parameter.Parameter``).

    Args:
        name: the parameter's name.
        type_: its type; inferred from ``value`` when None.
        value: its value (lists for the array types).

    Raises:
        TypeError: ``type_`` is not a ``Parameter.Type``.
        ValueError: ``value`` is not of type ``type_``.
    """

    Type = ParameterType
    """The parameter types (``Parameter.Type.DOUBLE``, ...)."""

    def __init__(self, name: str, type_: ParameterType | None = None, value: Any = None) -> None:
        if type_ is None:
            type_ = ParameterType.from_parameter_value(value)
        if not isinstance(type_, ParameterType):
            raise TypeError(f"type must be an instance of '{ParameterType!r}'")
        if not type_.check(value):
            raise ValueError(f"Type '{type_}' and value '{value}' do not agree")
        self._name = name
        self._type_ = type_
        self._value = list(value) if isinstance(value, tuple | array) else value

    @property
    def name(self) -> str:
        """The parameter's name."""
        return self._name

    @property
    def type_(self) -> ParameterType:
        """The parameter's type."""
        return self._type_

    @property
    def value(self) -> Any:
        """The parameter's value (None when NOT_SET)."""
        return self._value

    def get_parameter_value(self) -> ParameterValue:
        """The value as an ``rcl_interfaces/ParameterValue`` message."""
        message = ParameterValue(type=int(self._type_))
        if self._type_ in _VALUE_FIELDS:
            setattr(message, _VALUE_FIELDS[self._type_], self._value)
        return message

    def __repr__(self) -> str:
        return f"Parameter(name={self._name!r}, type_={self._type_}, value={self._value!r})"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Parameter):
            return NotImplemented
        return (self._name, self._type_, self._value) == (other._name, other._type_, other._value)


def parameter_value_to_python(value: ParameterValue) -> Any:
    """The Python value a ``ParameterValue`` message holds (None when not set)."""
    kind = ParameterType(value.type)
    return None if kind is ParameterType.NOT_SET else getattr(value, _VALUE_FIELDS[kind])
