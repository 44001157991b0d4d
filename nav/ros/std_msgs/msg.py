"""``std_msgs.msg``: the header and the plain one-field messages."""

from __future__ import annotations

from baobab.nav.msgs import Header
from baobab.nav.rosmsg import Message

__all__ = [
    "Bool",
    "ColorRGBA",
    "Empty",
    "Float32",
    "Float64",
    "Header",
    "Int8",
    "Int16",
    "Int32",
    "Int64",
    "String",
    "UInt8",
    "UInt16",
    "UInt32",
    "UInt64",
]


class Empty(Message):
    """``std_msgs/Empty``."""

    _type_name = "std_msgs/msg/Empty"


class Bool(Message):
    """``std_msgs/Bool``."""

    _type_name = "std_msgs/msg/Bool"
    _fields_and_field_types = {"data": "boolean"}
    data: bool


class String(Message):
    """``std_msgs/String``."""

    _type_name = "std_msgs/msg/String"
    _fields_and_field_types = {"data": "string"}
    data: str


class Int8(Message):
    """``std_msgs/Int8``."""

    _type_name = "std_msgs/msg/Int8"
    _fields_and_field_types = {"data": "int8"}
    data: int


class UInt8(Message):
    """``std_msgs/UInt8``."""

    _type_name = "std_msgs/msg/UInt8"
    _fields_and_field_types = {"data": "uint8"}
    data: int


class Int16(Message):
    """``std_msgs/Int16``."""

    _type_name = "std_msgs/msg/Int16"
    _fields_and_field_types = {"data": "int16"}
    data: int


class UInt16(Message):
    """``std_msgs/UInt16``."""

    _type_name = "std_msgs/msg/UInt16"
    _fields_and_field_types = {"data": "uint16"}
    data: int


class Int32(Message):
    """``std_msgs/Int32``."""

    _type_name = "std_msgs/msg/Int32"
    _fields_and_field_types = {"data": "int32"}
    data: int


class UInt32(Message):
    """``std_msgs/UInt32``."""

    _type_name = "std_msgs/msg/UInt32"
    _fields_and_field_types = {"data": "uint32"}
    data: int


class Int64(Message):
    """``std_msgs/Int64``."""

    _type_name = "std_msgs/msg/Int64"
    _fields_and_field_types = {"data": "int64"}
    data: int


class UInt64(Message):
    """``std_msgs/UInt64``."""

    _type_name = "std_msgs/msg/UInt64"
    _fields_and_field_types = {"data": "uint64"}
    data: int


class Float32(Message):
    """``std_msgs/Float32``."""

    _type_name = "std_msgs/msg/Float32"
    _fields_and_field_types = {"data": "float"}
    data: float


class Float64(Message):
    """``std_msgs/Float64``."""

    _type_name = "std_msgs/msg/Float64"
    _fields_and_field_types = {"data": "double"}
    data: float


class ColorRGBA(Message):
    """``std_msgs/ColorRGBA`` (each channel 0..1)."""

    _type_name = "std_msgs/msg/ColorRGBA"
    _fields_and_field_types = {"r": "float", "g": "float", "b": "float", "a": "float"}
    r: float
    g: float
    b: float
    a: float
