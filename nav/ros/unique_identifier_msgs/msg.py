"""``unique_identifier_msgs.msg``: the 16-byte UUID that names an action goal."""

from __future__ import annotations

import numpy as np

from baobab.nav.rosmsg import Message

__all__ = ["UUID"]


class UUID(Message):
    """``unique_identifier_msgs/UUID``: ``uuid`` is 16 bytes (a ``uint8`` array)."""

    _type_name = "unique_identifier_msgs/msg/UUID"
    _fields_and_field_types = {"uuid": "uint8[16]"}
    uuid: np.ndarray
