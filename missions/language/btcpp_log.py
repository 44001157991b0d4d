"""Groot2 replay logs: BehaviorTree.CPP's ``FileLogger2`` ``.btlog`` format, written from Python.

Layout (all little-endian, as ``bt_file_logger_v2.cpp`` writes it)::

    b"BTCPP4-FileLogger2" | u8 protocol (1) | i32 xml length | tree XML (UTF-8)
    | i64 first timestamp (microseconds since the epoch)
    | 9-byte records: u48 offset (microseconds from the first timestamp) | u16 uid | u8 status

The tree XML is BehaviorTree.CPP v4 XML whose nodes carry ``_uid`` attributes (depth-first
pre-order from 1, continuing through subtrees) and ``_fullpath``, plus a ``<TreeNodesModel>``.
This module does not build that XML: the tree exporter does; it writes the file around it, and
reads the tree's shape from it to order the records of one instant as a tick makes them.
"""

from __future__ import annotations

import enum
import io
import itertools
import math
import struct
import xml.etree.ElementTree as ET
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import BinaryIO

from baobab.sim.closable import Closable
from baobab.sim.output_file import OutputFile
from baobab.sim.recording_sinks import RecordingError

MAGIC = b"BTCPP4-FileLogger2"
PROTOCOL = 1
_MAX_OFFSET_US = 2**48 - 1


class BtStatus(enum.IntEnum):
    """BehaviorTree.CPP node statuses as Groot2 reads them."""

    IDLE = 0
    RUNNING = 1
    SUCCESS = 2
    FAILURE = 3
    SKIPPED = 4


PY_TREES_STATUS = {
    "INVALID": BtStatus.IDLE,
    "RUNNING": BtStatus.RUNNING,
    "SUCCESS": BtStatus.SUCCESS,
    "FAILURE": BtStatus.FAILURE,
}
"""py_trees ``Status`` names (``status.name``) -> BehaviorTree.CPP statuses."""


class BtLogWriter(Closable):
    """Write a ``.btlog`` that Groot2's log viewer replays.

    Args:
        path: the file; its suffix must be ``.btlog`` (Groot2 recognises files by it).
        tree_xml: BehaviorTree.CPP v4 XML with ``_uid`` on every node.
        start_time_us: the first timestamp (microseconds since the epoch); sim time ``t``
            is written at ``start_time_us + t * 1e6``.
        on_failure: told once why the log stopped when the disk refuses a write (the file is
            then dropped, nothing stays under its name); without it, :meth:`close` raises.

    Raises:
        RecordingError: for another suffix, tree XML that does not parse, or a file that
            cannot be opened.
    """

    def __init__(
        self,
        path: str | Path,
        tree_xml: str,
        *,
        start_time_us: int = 0,
        on_failure: Callable[[str], None] | None = None,
    ) -> None:
        self.path = Path(path)
        self._on_failure = on_failure
        if self.path.suffix != ".btlog":
            raise RecordingError(f"{self.path}: a Groot2 log needs the suffix .btlog")
        try:
            self._places = tick_places(tree_xml)
        except ET.ParseError as error:
            raise RecordingError(f"{self.path}: the tree XML does not parse: {error}") from error
        try:
            self._output = OutputFile(self.path, on_failure)  # disk full: stops, run goes on
        except OSError as error:
            raise RecordingError(f"{self.path}: cannot write the tree log: {error}") from error
        self._file: BinaryIO | None = io.BufferedWriter(self._output)
        xml = tree_xml.encode("utf-8")
        self._file.write(MAGIC + struct.pack("<Bi", PROTOCOL, len(xml)) + xml)
        self._file.write(struct.pack("<q", start_time_us))
        self._statuses: dict[int, BtStatus] = {}
        self._last_offset = 0
        self.records_written = 0

    def transition(self, t: float, uid: int, status: BtStatus) -> None:
        """Record that node ``uid`` entered ``status`` at sim time ``t`` (s)."""
        if self._file is None:
            raise RecordingError(f"{self.path}: the tree log is closed")
        offset = round(t * 1e6) if math.isfinite(t) else -1
        if not self._last_offset <= offset <= _MAX_OFFSET_US:
            raise RecordingError(f"{self.path}: transition time {t} s is out of order or range")
        if not 0 < uid < 2**16:
            raise RecordingError(f"{self.path}: node uid {uid} is outside 1..65535")
        self._file.write(offset.to_bytes(6, "little") + struct.pack("<HB", uid, int(status)))
        self._statuses[uid] = BtStatus(status)
        self._last_offset = offset
        self.records_written += 1

    def update(self, t: float, statuses: Mapping[int, BtStatus]) -> int:
        """Record every node whose status changed since the last call; returns how many.

        Call it after each tree tick with the status of every node (uid -> status); nodes
        never seen before count as changed unless they are IDLE. The records of one call come
        in the order BehaviorTree.CPP's ``FileLogger2`` writes them during a tick: a node that
        starts RUNNING before everything below it (a control node is RUNNING before it ticks
        its children), any other change after everything below it (a child finishes, or is
        halted, before its parent does); siblings in tick order.
        """
        changes = [
            (uid, status)
            for uid, status in statuses.items()
            if self._statuses.get(uid, BtStatus.IDLE) != status
        ]
        changes.sort(key=lambda change: self._place(*change))
        for uid, status in changes:
            self.transition(t, uid, status)
        return len(changes)

    def _place(self, uid: int, status: BtStatus) -> tuple[float, int]:
        """Sort key of a change at one instant; nodes not in the tree XML come last."""
        entered, left = self._places.get(uid, (math.inf, math.inf))
        return (entered if status == BtStatus.RUNNING else left), uid

    def close(self) -> None:
        """Finish the file (idempotent).

        Raises:
            RecordingError: writing failed on the way (disk full) and nobody was told.
        """
        if self._file is not None:
            self._file.close()
            self._file = None
            if self._output.failure is not None and self._on_failure is None:
                reason = self._output.failure
                raise RecordingError(f"{self.path}: cannot write the tree log: {reason}")


def tick_places(tree_xml: str) -> dict[int, tuple[float, float]]:
    """Each node's place in a tick: uid -> (when it is entered, when it is left).

    Both count steps of one depth-first walk of the tree XML from the main tree, into each
    ``<SubTree>`` instance (the ``<BehaviorTree>`` with the same ``_fullpath``), so a node is
    entered before and left after every node below it.

    Raises:
        xml.etree.ElementTree.ParseError: ``tree_xml`` is not XML.
    """
    root = ET.fromstring(tree_xml)
    trees = root.findall("BehaviorTree")
    instances = {tree.get("_fullpath"): tree for tree in trees}
    main_id = root.get("main_tree_to_execute")
    main = next((tree for tree in trees if tree.get("ID") == main_id), trees[0] if trees else root)
    places: dict[int, tuple[float, float]] = {}
    steps = itertools.count()

    def walk(element: ET.Element) -> None:
        for child in element:
            entered = next(steps)
            if child.tag == "SubTree":
                instance = instances.get(child.get("_fullpath"))
                if instance is not None:
                    walk(instance)
            else:
                walk(child)
            uid = child.get("_uid")
            if uid is not None and uid.isdigit():
                places[int(uid)] = (entered, next(steps))

    walk(main)
    return places
