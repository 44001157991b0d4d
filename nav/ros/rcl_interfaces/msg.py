"""``rcl_interfaces.msg``: parameter descriptors, types, ranges and set results."""

from __future__ import annotations

from baobab.nav.rosmsg import Message

__all__ = [
    "FloatingPointRange",
    "IntegerRange",
    "ParameterDescriptor",
    "ParameterType",
    "ParameterValue",
    "SetParametersResult",
]


class ParameterType(Message):
    """``rcl_interfaces/ParameterType``: the type codes of a parameter value."""

    _type_name = "rcl_interfaces/msg/ParameterType"
    PARAMETER_NOT_SET = 0
    PARAMETER_BOOL = 1
    PARAMETER_INTEGER = 2
    PARAMETER_DOUBLE = 3
    PARAMETER_STRING = 4
    PARAMETER_BYTE_ARRAY = 5
    PARAMETER_BOOL_ARRAY = 6
    PARAMETER_INTEGER_ARRAY = 7
    PARAMETER_DOUBLE_ARRAY = 8
    PARAMETER_STRING_ARRAY = 9


class FloatingPointRange(Message):
    """``rcl_interfaces/FloatingPointRange``: ``from_value`` to ``to_value`` by ``step``
    (0: any)."""

    _type_name = "rcl_interfaces/msg/FloatingPointRange"
    _fields_and_field_types = {"from_value": "double", "to_value": "double", "step": "double"}
    from_value: float
    to_value: float
    step: float


class IntegerRange(Message):
    """``rcl_interfaces/IntegerRange``: ``from_value`` to ``to_value`` by ``step`` (0: any)."""

    _type_name = "rcl_interfaces/msg/IntegerRange"
    _fields_and_field_types = {"from_value": "int64", "to_value": "int64", "step": "uint64"}
    from_value: int
    to_value: int
    step: int


class ParameterDescriptor(Message):
    """``rcl_interfaces/ParameterDescriptor``: what a parameter is and which values it takes."""

    _type_name = "rcl_interfaces/msg/ParameterDescriptor"
    _fields_and_field_types = {
        "name": "string",
        "type": "uint8",
        "description": "string",
        "additional_constraints": "string",
        "read_only": "boolean",
        "dynamic_typing": "boolean",
        "floating_point_range": "sequence<rcl_interfaces/FloatingPointRange, 1>",
        "integer_range": "sequence<rcl_interfaces/IntegerRange, 1>",
    }
    name: str
    type: int
    description: str
    additional_constraints: str
    read_only: bool
    dynamic_typing: bool
    floating_point_range: list[FloatingPointRange]
    integer_range: list[IntegerRange]


class SetParametersResult(Message):
    """``rcl_interfaces/SetParametersResult``: whether a set succeeded, and why not."""

    _type_name = "rcl_interfaces/msg/SetParametersResult"
    _fields_and_field_types = {"successful": "boolean", "reason": "string"}
    successful: bool
    reason: str


class ParameterValue(Message):
    """``rcl_interfaces/ParameterValue``: one field per type, ``type`` says which holds."""

    _type_name = "rcl_interfaces/msg/ParameterValue"
    _fields_and_field_types = {
        "type": "uint8",
        "bool_value": "boolean",
        "integer_value": "int64",
        "double_value": "double",
        "string_value": "string",
        "byte_array_value": "sequence<octet>",
        "bool_array_value": "sequence<boolean>",
        "integer_array_value": "sequence<int64>",
        "double_array_value": "sequence<double>",
        "string_array_value": "sequence<string>",
    }
    type: int
    bool_value: bool
    integer_value: int
    double_value: float
    string_value: str
    byte_array_value: list[bytes]
    bool_array_value: list[bool]
    integer_array_value: list[int]
    double_array_value: list[float]
    string_array_value: list[str]
