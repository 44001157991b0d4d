"""Tick a py_trees tree once, by direct calls instead of py_trees' chain of generators.

py_trees ticks a tree through generators so that a visitor can see every node as it is
ticked: each node's ``tick()`` yields itself, and every ancestor passes the yield on. A tree
with no visitors (the mission tree in
:meth:`~baobab.missions.run.tick_loop.RunLoop._tick_tree`, py_trees' sequences inside the Nav2
trees through :func:`baobab.nav.bt.tick_child`) only wants the tick, so :func:`tick_once` walks
the same nodes with plain calls. baobab's own Nav2 nodes (those marked ``ticks_directly``,
:class:`baobab.nav.bt.Direct`) tick by their ``step()``. For the node kinds it
knows (a leaf, a decorator, a sequence, a selector, each with py_trees' own ``tick``) it does
what that ``tick`` does, in the same order: ``initialise``, the children, ``update``,
``stop``/``terminate``, the status. py_trees' debug log lines are not written. Any other
node (a parallel, a node that overrides ``tick``) is ticked by its own generator, so the
result is the generator tick's, call for call (``tests/test_direct_tick.py`` compares the two
on seeded random trees).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from typing import Any

import py_trees

Behaviour = py_trees.behaviour.Behaviour
Status = py_trees.common.Status
RUNNING, SUCCESS, FAILURE, INVALID = Status.RUNNING, Status.SUCCESS, Status.FAILURE, Status.INVALID
_STATUSES = tuple(Status)
"""What ``update`` may return (py_trees checks ``new_status in list(Status)``)."""

Ticker = Callable[[Any], None]
"""Ticks one node of the class it was chosen for."""


def tick_once(node: Behaviour) -> None:
    """Tick ``node`` and its subtree once, as ``node.tick_once()`` does."""
    _ticker(type(node))(node)


def _finish(node: Behaviour, new_status: Status) -> None:
    """The end of py_trees' ``Behaviour.tick`` and ``Decorator.tick``, after ``update``."""
    if new_status not in _STATUSES:
        node.logger.error(
            "A behaviour returned an invalid status, setting to INVALID "
            f"[{new_status}][{node.name}]"
        )
        new_status = INVALID
    if new_status != RUNNING:
        node.stop(new_status)
    node.status = new_status


def _tick_leaf(node: Behaviour) -> None:
    """py_trees' ``Behaviour.tick``."""
    if node.status != RUNNING:
        node.initialise()
    _finish(node, node.update())


def _tick_decorator(node: py_trees.decorators.Decorator) -> None:
    """py_trees' ``Decorator.tick``: the decorated child is ticked before ``update``."""
    if node.status != RUNNING:
        node.initialise()
    child = node.decorated
    _ticker(type(child))(child)
    _finish(node, node.update())


def _tick_sequence(node: py_trees.composites.Sequence) -> None:
    """py_trees' ``Sequence.tick`` (with or without memory)."""
    children = node.children
    index = 0
    if node.status != RUNNING:
        node.current_child = children[0] if children else None
        for child in children:
            if child.status != INVALID:
                child.stop(INVALID)
        node.initialise()
    elif node.memory and node.current_child is not None:
        index = children.index(node.current_child)
    else:
        node.current_child = children[0] if children else None
    if not children:
        node.current_child = None
        node.stop(SUCCESS)
        return
    for child in itertools.islice(children, index, None):
        _ticker(type(child))(child)
        status = child.status
        if status != SUCCESS:
            if not node.memory:  # invalidate the rest: stop dangling runners
                for later in itertools.islice(children, index + 1, None):
                    if later.status != INVALID:
                        later.stop(INVALID)
            if status != RUNNING:
                node.stop(status)
            else:
                node.status = status
            return
        if index + 1 < len(children):
            node.current_child = children[index + 1]
            index += 1
    node.stop(SUCCESS)


def _tick_selector(node: py_trees.composites.Selector) -> None:
    """py_trees' ``Selector.tick`` (with or without memory)."""
    children = node.children
    if node.status != RUNNING:
        node.current_child = children[0] if children else None
        node.initialise()
    if not children:
        node.current_child = None
        node.stop(FAILURE)
        return
    if node.memory:
        assert node.current_child is not None  # set above: the selector has children
        index = children.index(node.current_child)
        for child in itertools.islice(children, None, index):
            if child.status != INVALID:
                child.stop(INVALID)
    else:
        index = 0
    previous = node.current_child
    for child in itertools.islice(children, index, None):
        _ticker(type(child))(child)
        status = child.status
        if status in (RUNNING, SUCCESS):
            node.current_child = child
            if previous is None or previous != child:
                # a higher priority took over: invalidate every lower one
                passed = False
                for other in children:
                    if passed and other.status != INVALID:
                        other.stop(INVALID)
                    passed = True if other == child else passed
            if status == SUCCESS:
                node.stop(status)
            else:
                node.status = status
            return
    node.stop(FAILURE)
    node.current_child = children[-1] if children else None


def _tick_direct(node: Any) -> None:
    """A :class:`baobab.nav.bt.Direct` node: its ``step()`` is its whole tick."""
    node.step()


def _tick_by_generator(node: Behaviour) -> None:
    """The node's own tick (a parallel, or a node that overrides ``tick``)."""
    for _ in node.tick():
        pass


_DIRECT: tuple[tuple[Callable[..., object], Ticker], ...] = (
    (py_trees.behaviour.Behaviour.tick, _tick_leaf),
    (py_trees.decorators.Decorator.tick, _tick_decorator),
    (py_trees.composites.Sequence.tick, _tick_sequence),
    (py_trees.composites.Selector.tick, _tick_selector),
)
_TICKERS: dict[type, Ticker] = {}
"""The ticker of each node class seen so far."""


def _ticker(kind: type) -> Ticker:
    """How nodes of class ``kind`` are ticked: by ``step()`` when the class ticks directly,
    by plain calls when their ``tick`` is one of py_trees' four above, else by their own
    generator."""
    ticker = _TICKERS.get(kind)
    if ticker is None:
        own = getattr(kind, "tick", None)
        ticker = next((direct for tick, direct in _DIRECT if own is tick), _tick_by_generator)
        if getattr(kind, "ticks_directly", False):
            ticker = _tick_direct
        _TICKERS[kind] = ticker
    return ticker
