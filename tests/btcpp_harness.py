"""BehaviorTree.CPP (``behaviortreepy``) as the tests use it: dummy nodes, ticking, reading.

The helpers load exported XML with a dummy for every node of its ``TreeNodesModel``, tick it to
completion, list the port values each node reads (following ``<SubTree>`` remapping) and read
``.btlog`` files.
"""

from __future__ import annotations

import struct
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import behaviortreepy as bt

MAX_TICKS = 500
TICK_WAIT_MS = 2


def btcpp_tree(xml: str) -> bt.Tree:
    """``xml`` loaded by BehaviorTree.CPP, every node of its ``TreeNodesModel`` a dummy.

    Actions are RUNNING for one tick, then succeed; conditions succeed; decorators pass their
    child's status on. behaviortreepy registers Python nodes without ports (their
    ``providedPorts()`` is empty), so each custom node's port attributes are checked against
    its model here and then taken off; the built-in nodes keep theirs, for BT.CPP to check.
    """
    root = ET.fromstring(xml)
    (model,) = root.findall("TreeNodesModel")
    factory = bt.BehaviorTreeFactory()
    custom: dict[str, set[str]] = {}
    for entry in model:
        node_id = entry.get("ID", "")
        if entry.tag == "SubTree":
            continue
        custom[node_id] = {port.get("name", "") for port in entry.findall("input_port")}
        if entry.tag == "Action":
            factory.register_simple_stateful_action(node_id, _running, _succeed, lambda node: None)
        elif entry.tag == "Condition":
            factory.register_simple_condition(node_id, _succeed)
        else:
            assert entry.tag == "Decorator", entry.tag
            factory.register_simple_decorator(node_id, lambda status, node: status)
    for element in root.iter():
        if element.tag in custom:
            ports = set(element.attrib) - {"name"}
            assert ports <= custom[element.tag], (element.tag, ports - custom[element.tag])
            for port in ports:
                del element.attrib[port]
    return factory.create_tree_from_text(ET.tostring(root, encoding="unicode"))


def _running(node: bt.TreeNode) -> bt.NodeStatus:
    return bt.NodeStatus.RUNNING


def _succeed(node: bt.TreeNode) -> bt.NodeStatus:
    return bt.NodeStatus.SUCCESS


def tick_to_completion(tree: bt.Tree) -> bt.NodeStatus:
    """Tick until the tree finishes (at most :data:`MAX_TICKS` ticks)."""
    for _ in range(MAX_TICKS):
        status = tree.tick_once()
        if status != bt.NodeStatus.RUNNING:
            return status
        tree.sleep(TICK_WAIT_MS)  # returns early when a Sleep or Timeout node wakes the tree
    raise AssertionError(f"still RUNNING after {MAX_TICKS} ticks")


def resolved(xml: str) -> list[tuple[str, dict[str, str]]]:
    """Every element of the tree BT.CPP builds from ``xml``, with the port values it reads.

    Walks from the main tree into each ``<SubTree>``, following blackboard references through
    the call's attributes and its model's defaults (BT.CPP's remapping), so each value is the
    one that reaches the node. Each element is its tag and its attributes but the name.
    """
    root = ET.fromstring(xml)
    trees = {tree.get("ID"): tree for tree in root.findall("BehaviorTree")}
    (model,) = root.findall("TreeNodesModel")
    defaults = {
        entry.get("ID"): {port.get("name"): port.get("default") for port in entry}
        for entry in model
        if entry.tag == "SubTree"
    }
    found: list[tuple[str, dict[str, str]]] = []

    def value(text: str, board: dict[str, str]) -> str:
        return board[text[1:-1]] if text.startswith("{") and text.endswith("}") else text

    def walk(element: ET.Element, board: dict[str, str]) -> None:
        for child in element:
            attributes = {k: value(v, board) for k, v in child.attrib.items() if k != "name"}
            found.append((child.tag, attributes))
            if child.tag == "SubTree":
                tree_id = attributes["ID"]
                inner = {k: v for k, v in defaults.get(tree_id, {}).items() if v is not None}
                inner.update({k: v for k, v in attributes.items() if k != "ID"})
                walk(trees[tree_id], inner)
            else:
                walk(child, board)

    walk(trees[root.get("main_tree_to_execute")], {})
    return found


def instances(log_xml: str) -> list[tuple[str, dict[str, str]]]:
    """The elements of a ``.btlog`` tree XML (subtree instances expanded), as :func:`resolved`."""
    root = ET.fromstring(log_xml)
    trees = {tree.get("_fullpath"): tree for tree in root.findall("BehaviorTree")}
    found: list[tuple[str, dict[str, str]]] = []

    def walk(element: ET.Element) -> None:
        for child in element:
            hidden = {"name", "_uid", "_fullpath"}
            found.append((child.tag, {k: v for k, v in child.attrib.items() if k not in hidden}))
            walk(trees[child.get("_fullpath")] if child.tag == "SubTree" else child)

    walk(trees[""])
    return found


def read_msec(xml: str) -> list[int]:
    """Every ``msec`` that BT.CPP's Sleep and Timeout nodes read, in tick order."""
    return [int(ports["msec"]) for tag, ports in resolved(xml) if tag in ("Sleep", "Timeout")]


def read_btlog(path: Path) -> tuple[str, list[tuple[int, int, int]]]:
    """The tree XML and the (offset us, uid, status) records of a ``.btlog``."""
    raw = path.read_bytes()
    (length,) = struct.unpack_from("<i", raw, 19)
    body = raw[31 + length :]
    records = [
        (int.from_bytes(body[i : i + 6], "little"), *struct.unpack_from("<HB", body, i + 6))
        for i in range(0, len(body), 9)
    ]
    return raw[23 : 23 + length].decode(), records


LOG_WRITER_TIMEOUT_S = 30.0


def finished_btlog(tree: bt.Tree, path: Path) -> bt.NodeStatus:
    """Tick ``tree`` to completion under a ``FileLogger`` writing ``path``; its final status.

    BT.CPP 4.8's ``FileLogger2`` writes from a thread of its own and drops what that thread has
    not yet taken from its queue when the logger is destroyed, so a loaded machine loses the
    last records. This waits (at most :data:`LOG_WRITER_TIMEOUT_S` wall-clock seconds) until
    the root's (uid 1) final status is on disk; the queue is written in order, so everything
    before it is too. Under load the same thread sometimes writes a batch twice: read the log
    with :func:`read_btlog_once`.
    """
    logger = bt.FileLogger(tree, str(path))
    status = tick_to_completion(tree)
    final = 2 if status == bt.NodeStatus.SUCCESS else 3
    deadline = time.monotonic() + LOG_WRITER_TIMEOUT_S
    while True:
        logger.flush()
        if path.stat().st_size > 31:
            _, records = read_btlog(path)
            if (1, final) in {(uid, status) for _, uid, status in records}:
                break
        if time.monotonic() > deadline:
            raise AssertionError(f"BT.CPP's logger did not write the final status to {path}")
        time.sleep(0.001)
    del logger
    return status


def read_btlog_once(path: Path) -> tuple[str, list[tuple[int, int, int]]]:
    """:func:`read_btlog` up to the root's (uid 1) first final status: one run of the tree."""
    xml, records = read_btlog(path)
    end = next(i for i, (_, uid, status) in enumerate(records) if uid == 1 and status in (2, 3))
    return xml, records[: end + 1]
