"""ROS 2 message classes that behave as rclpy's generated ones: typed, slotted, keyword-built.

A message class lists its fields as rosidl does, in ``_fields_and_field_types`` (``{'x':
'double', 'poses': 'sequence<geometry_msgs/PoseStamped>', 'covariance': 'double[36]'}``);
:class:`MessageMeta` turns each into a slot and a property whose setter checks the value as
the generated code does, raising ``AssertionError`` with rclpy's wording:

* ``double``/``float`` take a Python ``float`` only (``msg.x = 1`` fails, as in rclpy);
* integer types take an ``int`` within the type's range; ``boolean`` a ``bool``; ``string``
  a ``str``;
* a nested field takes an instance of its message class;
* ``sequence<T>`` and ``T[N]``: numeric ones are stored as ``array.array`` (sequences) or a
  ``numpy`` array (fixed size), others as lists; any sequence of valid items is accepted.

The constructor takes keyword arguments only and refuses unknown ones. Messages compare by
value, print as ``geometry_msgs.msg.Point(x=0.0, y=0.0, z=0.0)`` and copy with :mod:`copy`.

A field may be *deferred* (:func:`defer_field`): it holds a recipe, built and checked on its
first read, so a large value nobody reads (the poses of a planned path) is never made; a copy
of the message shares the recipe, and :func:`deferred_source` says what the recipe is made from
while it has not been built.
"""

from __future__ import annotations

import math
from array import array
from collections.abc import Callable, Sequence, Set
from typing import Any, ClassVar, Self

import numpy as np

MESSAGE_TYPES: dict[str, type[Message]] = {}
"""Every message class by its ROS type name, ``"geometry_msgs/msg/Point"``."""

_FLOAT32_MAX = 3.402823466e38
_FLOAT64_MAX = 1.7976931348623157e308
_INTEGERS = {
    "int8": (-(2**7), 2**7 - 1, "b"),
    "uint8": (0, 2**8 - 1, "B"),
    "int16": (-(2**15), 2**15 - 1, "h"),
    "uint16": (0, 2**16 - 1, "H"),
    "int32": (-(2**31), 2**31 - 1, "i"),
    "uint32": (0, 2**32 - 1, "I"),
    "int64": (-(2**63), 2**63 - 1, "q"),
    "uint64": (0, 2**64 - 1, "Q"),
    "octet": (0, 2**8 - 1, "B"),
}
_FLOATS = {"float": (_FLOAT32_MAX, "f", np.float32), "double": (_FLOAT64_MAX, "d", np.float64)}

Check = Callable[[str, Any], Any]
"""Validates a value for the named field and returns what the field stores."""


def _fail(message: str) -> None:
    raise AssertionError(message)


def _scalar_check(kind: str) -> tuple[Check, Callable[[], Any]] | None:
    """The check and default of a scalar field type, or None if ``kind`` is not one."""
    if kind in _FLOATS:
        bound = _FLOATS[kind][0]
        wording = "a double" if kind == "double" else "a float"

        def check_float(name: str, value: Any) -> float:
            if not isinstance(value, float):
                _fail(f"The '{name}' field must be of type 'float'")
            if (value < -bound or value > bound) and not math.isinf(value):
                _fail(f"The '{name}' field must be {wording} in [{-bound}, {bound}]")
            return value

        return check_float, float
    if kind in _INTEGERS:
        low, high, _ = _INTEGERS[kind]

        def check_int(name: str, value: Any) -> int:
            if not isinstance(value, int) or isinstance(value, bool):
                _fail(f"The '{name}' field must be of type 'int'")
            if not low <= value <= high:
                _fail(f"The '{name}' field must be an integer in [{low}, {high}]")
            return int(value)

        return check_int, int
    if kind == "boolean":

        def check_bool(name: str, value: Any) -> bool:
            if not isinstance(value, bool):
                _fail(f"The '{name}' field must be of type 'bool'")
            return value

        return check_bool, bool
    if kind == "string":

        def check_str(name: str, value: Any) -> str:
            if not isinstance(value, str):
                _fail(f"The '{name}' field must be of type 'str'")
            return value

        return check_str, str
    return None


def _nested_check(kind: str) -> tuple[Check, Callable[[], Any]]:
    package, _, name = kind.partition("/")
    type_name = f"{package}/msg/{name}"

    def message_class() -> type[Message]:
        try:
            return MESSAGE_TYPES[type_name]
        except KeyError:
            raise TypeError(f"unknown message type {type_name!r}") from None

    def check_nested(field: str, value: Any) -> Message:
        cls = message_class()
        if not isinstance(value, cls):
            _fail(f"The '{field}' field must be a sub message of type '{cls.__name__}'")
        return value

    return check_nested, lambda: message_class()()


def _is_sequence(value: Any) -> bool:
    return isinstance(value, Sequence | Set | np.ndarray | array) and not isinstance(
        value, str | bytes
    )


def _sequence_check(item_kind: str, size: int | None) -> tuple[Check, Callable[[], Any]]:
    """Check and default of ``sequence<item_kind>`` (``size`` None) or ``item_kind[size]``."""
    scalar = _scalar_check(item_kind)
    item_check, item_default = scalar if scalar is not None else _nested_check(item_kind)
    shown_item = {"double": "float", "string": "str", "boolean": "bool"}.get(
        item_kind, "int" if item_kind in _INTEGERS else item_kind.rpartition("/")[2]
    )

    def checked_items(name: str, value: Any) -> list[Any]:
        if not _is_sequence(value):
            _fail(
                f"The '{name}' field must be a set or sequence and each value of type "
                f"'{shown_item}'"
            )
        if size is not None and len(value) != size:
            _fail(f"The '{name}' field must be a set or sequence with length {size}")
        items = value.tolist() if isinstance(value, np.ndarray) else list(value)
        for item in items:
            try:
                item_check(name, item)
            except AssertionError:
                _fail(
                    f"The '{name}' field must be a set or sequence and each value of type "
                    f"'{shown_item}'"
                )
        return items

    numeric = _FLOATS.get(item_kind) or _INTEGERS.get(item_kind)
    if numeric is not None and size is not None:
        dtype = _FLOATS[item_kind][2] if item_kind in _FLOATS else np.dtype(numeric[2])

        def check_fixed(name: str, value: Any) -> np.ndarray:
            if isinstance(value, np.ndarray):
                if value.dtype != dtype:
                    _fail(
                        f"The '{name}' numpy.ndarray() must have the dtype of '{np.dtype(dtype)}'"
                    )
                if value.size != size:
                    _fail(f"The '{name}' numpy.ndarray() must have a size of {size}")
                return value
            return np.array(checked_items(name, value), dtype=dtype)

        return check_fixed, lambda: np.zeros(size, dtype=dtype)
    if numeric is not None:
        code: str = _FLOATS[item_kind][1] if item_kind in _FLOATS else _INTEGERS[item_kind][2]

        def check_array(name: str, value: Any) -> array[Any]:
            if isinstance(value, array):
                if value.typecode != code:
                    _fail(f"The '{name}' array.array() must have the type code of '{code}'")
                return value
            if isinstance(value, np.ndarray) and value.dtype.char == code:
                return array(code, value.tobytes())
            return array(code, checked_items(name, value))

        return check_array, lambda: array(code)
    if size is not None:
        return (lambda name, value: checked_items(name, value)), lambda: [
            item_default() for _ in range(size)
        ]
    return (lambda name, value: checked_items(name, value)), list


def field_check(kind: str) -> tuple[Check, Callable[[], Any]]:
    """The setter check and the default factory of a rosidl field type string.

    Raises:
        TypeError: ``kind`` is not a type this module models.
    """
    if kind.startswith("sequence<") and kind.endswith(">"):
        inner = kind[len("sequence<") : -1].partition(",")[0]
        return _sequence_check(inner, None)
    if kind.endswith("]") and "[" in kind:
        inner, _, count = kind[:-1].partition("[")
        if count.isdigit():
            return _sequence_check(inner, int(count))
        raise TypeError(f"unsupported field type {kind!r}")
    scalar = _scalar_check(kind)
    if scalar is not None:
        return scalar
    if kind.count("/") == 1:
        return _nested_check(kind)
    raise TypeError(f"unsupported field type {kind!r}")


def _constant(value: Any) -> Callable[[], Any]:
    return lambda: value


class Deferred:
    """A field value made on the field's first read: ``build()``, from ``source``.

    ``build`` must make a new value on each call from ``source`` alone (which must not change),
    so that copies of a message may share the recipe.
    """

    __slots__ = ("build", "source")

    def __init__(self, build: Callable[[], Any], source: Any) -> None:
        self.build = build
        self.source = source


def defer_field(message: Message, field: str, build: Callable[[], Any], source: Any) -> None:
    """Let ``message.field`` be ``build()``, made and checked when it is first read.

    Raises:
        AttributeError: ``message`` has no such field.
    """
    if field not in message._factories:
        raise AttributeError(f"{type(message).__name__} has no field {field!r}")
    object.__setattr__(message, f"_{field}", Deferred(build, source))


def deferred_source(message: Message, field: str) -> Any | None:
    """What ``message.field`` will be built from, or None once it is built or set."""
    value = object.__getattribute__(message, f"_{field}")
    return value.source if type(value) is Deferred else None


def _field_property(name: str, check: Check) -> property:
    slot = f"_{name}"

    def getter(self: Message) -> Any:
        value = getattr(self, slot)
        if type(value) is Deferred:
            value = check(name, value.build())
            object.__setattr__(self, slot, value)
        return value

    def setter(self: Message, value: Any) -> None:
        object.__setattr__(self, slot, check(name, value))

    return property(getter, setter)


class MessageMeta(type):
    """Builds a message class's slots, typed properties and registry entry (module docstring)."""

    def __new__(mcls, name: str, bases: tuple[type, ...], namespace: dict[str, Any]) -> type:
        fields: dict[str, str] = namespace.get("_fields_and_field_types", {})
        namespace["__slots__"] = tuple(f"_{field}" for field in fields)
        cls = super().__new__(mcls, name, bases, namespace)
        if not fields and "_type_name" not in namespace:
            return cls  # the Message base itself
        defaults: dict[str, Any] = namespace.get("_defaults", {})
        factories: dict[str, Callable[[], Any]] = {}
        for field, kind in fields.items():
            check, default = field_check(kind)
            setattr(cls, field, _field_property(field, check))
            if field in defaults:
                factories[field] = _constant(defaults[field])
            else:
                factories[field] = default
        cls._factories = factories  # type: ignore[attr-defined]
        MESSAGE_TYPES[namespace["_type_name"]] = cls  # type: ignore[assignment]
        return cls


class Message(metaclass=MessageMeta):
    """Base of every message class; see the module docstring."""

    _type_name: ClassVar[str]
    """The ROS type name, ``"geometry_msgs/msg/Point"``."""
    _fields_and_field_types: ClassVar[dict[str, str]] = {}
    _defaults: ClassVar[dict[str, Any]] = {}
    _factories: ClassVar[dict[str, Callable[[], Any]]]

    def __init__(self, **kwargs: Any) -> None:
        factories = self._factories
        if not kwargs.keys() <= factories.keys():
            unknown = sorted(kwargs.keys() - factories.keys())
            _fail(f"Invalid arguments passed to constructor: {', '.join(unknown)}")
        for field, factory in factories.items():
            if field in kwargs:
                setattr(self, field, kwargs[field])
            else:
                object.__setattr__(self, f"_{field}", factory())

    @classmethod
    def unchecked(cls, **fields: Any) -> Self:
        """A message of every field in ``fields``, each already a value of its field's type.

        The setters' checks are skipped: for code that builds many messages from values it
        made itself (a path's poses).

        Raises:
            TypeError: ``fields`` does not name every field of the message, and no other.
        """
        if fields.keys() != cls._factories.keys():
            wanted = list(cls._factories)
            raise TypeError(f"{cls.__name__}.unchecked needs exactly the fields {wanted}")
        message = object.__new__(cls)
        for field, value in fields.items():
            object.__setattr__(message, f"_{field}", value)
        return message

    @classmethod
    def get_fields_and_field_types(cls) -> dict[str, str]:
        """The field names and rosidl types, in declaration order (rclpy's classmethod)."""
        return dict(cls._fields_and_field_types)

    def __repr__(self) -> str:
        package, kind, name = self._type_name.split("/")  # kind: msg, srv or action
        shown = ", ".join(f"{field}={getattr(self, field)!r}" for field in self._factories)
        return f"{package}.{kind}.{name}({shown})"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, self.__class__):
            return False
        for field in self._factories:
            mine, theirs = getattr(self, field), getattr(other, field)
            if isinstance(mine, np.ndarray):
                if not np.array_equal(mine, theirs):
                    return False
            elif mine != theirs:
                return False
        return True

    __hash__ = None  # type: ignore[assignment]

    def __deepcopy__(self, memo: dict[int, Any]) -> Message:
        """A copy sharing nothing mutable with this message (fields are already checked)."""
        new = object.__new__(type(self))
        for field in self._factories:
            slot = f"_{field}"
            object.__setattr__(new, slot, _copied(object.__getattribute__(self, slot)))
        return new

    def __getstate__(self) -> dict[str, Any]:
        return {field: getattr(self, field) for field in self._factories}

    def __setstate__(self, state: dict[str, Any]) -> None:
        for field, value in state.items():
            object.__setattr__(self, f"_{field}", value)


def _copied(value: Any) -> Any:
    if type(value) is Deferred:
        return value  # made anew from its unchanging source on each read
    if isinstance(value, Message):
        return value.__deepcopy__({})
    if isinstance(value, list):
        return [_copied(item) for item in value]
    if isinstance(value, array):
        return array(value.typecode, value)
    if isinstance(value, np.ndarray):
        return value.copy()
    return value


class MessageFieldError(ValueError):
    """Values that do not fit a message (:func:`fill_message`): says which field and why."""


def fill_message(message: Message, values: Any, path: str = "") -> Message:
    """Set ``message``'s fields from plain values (a YAML mapping), as ``ros2 topic pub`` does:
    nested mappings fill nested messages, and a number fills a float field (``x: 1``).

    Raises:
        MessageFieldError: an unknown field, or a value its field does not take.
    """
    if values is None:
        return message
    if not isinstance(values, dict):
        raise MessageFieldError(f"{path or 'the message'}: expected a mapping of field values")
    fields = message.get_fields_and_field_types()
    for name, value in values.items():
        where = f"{path}.{name}" if path else str(name)
        if name not in fields:
            known = ", ".join(fields) or "none"
            raise MessageFieldError(
                f"{where}: {type(message).__name__} has no such field (fields: {known})"
            )
        kind = fields[name]
        current = getattr(message, name)
        try:
            if isinstance(current, Message):
                fill_message(current, value, where)
                continue
            if (
                kind in ("double", "float")
                and isinstance(value, int)
                and not isinstance(value, bool)
            ):
                value = float(value)
            elif kind.startswith("sequence<") and "/" in kind and isinstance(value, list):
                item_class = message_class(kind[len("sequence<") : -1].partition(",")[0])
                value = [
                    fill_message(item_class(), item, f"{where}[{i}]")
                    for i, item in enumerate(value)
                ]
            elif isinstance(value, list) and any(word in kind for word in ("double", "float")):
                value = [
                    float(item) if isinstance(item, int) and not isinstance(item, bool) else item
                    for item in value
                ]
            setattr(message, name, value)
        except AssertionError as exc:
            raise MessageFieldError(f"{where}: {exc}") from None
    return message


def message_class(type_name: str) -> type[Message]:
    """The message class of ``"pkg/msg/Name"`` or ``"pkg/Name"``.

    Raises:
        KeyError: no such message type is modelled.
    """
    package, _, name = type_name.replace("/msg/", "/").partition("/")
    return MESSAGE_TYPES[f"{package}/msg/{name}"]


def to_plain(value: Any) -> Any:
    """A message (or field value) as plain dicts, lists and numbers, for YAML and JSON."""
    if isinstance(value, Message):
        return {field: to_plain(getattr(value, field)) for field in value._factories}
    if isinstance(value, np.ndarray | array):
        return value.tolist()
    if isinstance(value, list):
        return [to_plain(item) for item in value]
    return value
