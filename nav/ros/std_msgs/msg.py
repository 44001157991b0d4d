"""``std_msgs.msg``: the header and the plain one-field messages scripts commonly use."""

from __future__ import annotations

from dataclasses import dataclass

from baobab.nav.msgs import Header

__all__ = ["Bool", "Empty", "Float32", "Float64", "Header", "Int32", "Int64", "String"]


@dataclass(slots=True, kw_only=True)
class Empty:
    """``std_msgs/Empty``."""


@dataclass(slots=True, kw_only=True)
class Bool:
    """``std_msgs/Bool``."""

    data: bool = False


@dataclass(slots=True, kw_only=True)
class String:
    """``std_msgs/String``."""

    data: str = ""


@dataclass(slots=True, kw_only=True)
class Int32:
    """``std_msgs/Int32``."""

    data: int = 0


@dataclass(slots=True, kw_only=True)
class Int64:
    """``std_msgs/Int64``."""

    data: int = 0


@dataclass(slots=True, kw_only=True)
class Float32:
    """``std_msgs/Float32``."""

    data: float = 0.0


@dataclass(slots=True, kw_only=True)
class Float64:
    """``std_msgs/Float64``."""

    data: float = 0.0
