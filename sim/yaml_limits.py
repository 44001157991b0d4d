"""A quick pass over a YAML text with libyaml's event parser, before anything is built.

Composing a document into nodes and then into located Python data costs tens of microseconds
per value, so refusing a 200,000-value document that way took seconds. libyaml's event stream
is cheaper and can stop early: :func:`scan_limits` counts values the way the loader does
(mapping keys are not values), tracks how deeply they nest, and reports the first limit
crossed, with its position, after at most ``max_values`` values. libyaml's parser keeps its
own stack, so any nesting depth is safe here (its composer recurses on the C stack).

An alias counts as one value here; the loader still counts what it expands to, so the count
is a lower bound: a limit crossed here is crossed in the loader too.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import yaml

from baobab.sim.text_positions import TextPositions

_NODE_EVENTS = (
    yaml.ScalarEvent,
    yaml.AliasEvent,
    yaml.SequenceStartEvent,
    yaml.MappingStartEvent,
)
_START_EVENTS = (yaml.SequenceStartEvent, yaml.MappingStartEvent)
_END_EVENTS = (yaml.SequenceEndEvent, yaml.MappingEndEvent)
_LAST_EVENTS = (yaml.DocumentEndEvent, yaml.StreamEndEvent)


@dataclass(frozen=True)
class ScanProblem:
    """The first limit a text crosses, or its first syntax error: 1-based line and column."""

    line: int
    column: int
    message: str


@dataclass(frozen=True)
class ScanResult:
    """What a complete scan of the first document found."""

    values: int
    depth: int


def libyaml_available() -> bool:
    """True when PyYAML was built with libyaml (the scan needs its C parser)."""
    return bool(getattr(yaml, "__with_libyaml__", False))


def events_at_most(text: str, limit: int) -> bool:
    """True when the whole of ``text`` parses into at most ``limit`` events.

    libyaml counts them without making a Python object per event (~1 us each, a fifth of
    :func:`scan_limits`), but cannot stop early or say where: a quick pass for texts that are
    long but not huge. Every value is at least one event, so this bounds the value count.
    """
    from yaml._yaml import CParser  # present whenever libyaml_available() is True

    parser = CParser(text)
    try:
        return bool(parser.raw_parse() <= limit)
    except yaml.YAMLError:
        return False  # the full scan will say where
    finally:
        parser.dispose()


def scan_limits(text: str, max_values: int, max_depth: int) -> ScanProblem | ScanResult:
    """Count the values of the first document in ``text`` and measure its nesting.

    Args:
        text: YAML text (PyYAML's reader has already accepted its characters).
        max_values: more values than this is a problem (the root counts as one).
        max_depth: a value nested deeper than this is a problem (the root is at depth 0).

    Returns:
        The first problem in document order (too many values, too deep, or a syntax error
        as libyaml words it), or the counts when there is none.
    """
    from yaml._yaml import CParser  # present whenever libyaml_available() is True

    positions = TextPositions(text)
    parser = CParser(text)
    try:
        return _scan_events(parser.get_event, max_values, max_depth, positions)
    except yaml.MarkedYAMLError as exc:
        if LIBYAML_DEPTH_LIMIT not in str(exc.problem):
            return _syntax_problem(exc, positions)
    finally:
        parser.dispose()
    # libyaml's scanner reads ahead over tightly packed brackets (``[[[[...``) and stops at its
    # own nesting limit (1000 levels) before the parser reports the level that crossed ours.
    # PyYAML's pure-Python parser has no such limit and also keeps its own stack.
    events = yaml.parse(text, Loader=yaml.SafeLoader)
    try:
        return _scan_events(lambda: next(events, None), max_values, max_depth, positions)
    except yaml.MarkedYAMLError as exc:
        return _syntax_problem(exc, positions)


LIBYAML_DEPTH_LIMIT = "maximum nesting depth"
"""Words of libyaml's own error when collections nest past its limit (seen with libyaml 0.2.6)."""


def _scan_events(
    next_event: Callable[[], yaml.Event | None],
    max_values: int,
    max_depth: int,
    positions: TextPositions,
) -> ScanProblem | ScanResult:
    """The scan of :func:`scan_limits` over a parser's events (raises its syntax errors)."""
    values = 0
    depth = 0
    keys_open = 0  # collections open inside a mapping key (their contents are not values)
    frames: list[list[int]] = []  # per open collection: [is_mapping, children so far, is_key]
    while True:
        event = next_event()
        if isinstance(event, _NODE_EVENTS):
            top = frames[-1] if frames else None
            is_key = keys_open > 0 or (top is not None and top[0] == 1 and top[1] % 2 == 0)
            if not is_key:
                values += 1
                level = len(frames)
                if values > max_values:
                    return _problem(event, f"more than {max_values} values", positions)
                if level > max_depth:
                    return _problem(event, f"nesting deeper than {max_depth} levels", positions)
                depth = max(depth, level)
            if isinstance(event, _START_EVENTS):
                frames.append([int(isinstance(event, yaml.MappingStartEvent)), 0, int(is_key)])
                keys_open += is_key
            elif top is not None:
                top[1] += 1
        elif isinstance(event, _END_EVENTS):
            keys_open -= frames.pop()[2]
            if frames:
                frames[-1][1] += 1
        elif event is None or isinstance(event, _LAST_EVENTS):
            return ScanResult(values, depth)


def _syntax_problem(exc: yaml.MarkedYAMLError, positions: TextPositions) -> ScanProblem:
    mark = exc.problem_mark or exc.context_mark
    line, column = positions.of_mark(mark) if mark else (1, 1)
    return ScanProblem(line, column, f"YAML syntax error: {exc.problem or exc.context}")


def _problem(event: yaml.Event, message: str, positions: TextPositions) -> ScanProblem:
    mark = event.start_mark
    if mark is None:
        return ScanProblem(1, 1, message)
    return ScanProblem(*positions.of_mark(mark), message)
