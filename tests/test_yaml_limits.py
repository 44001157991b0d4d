"""The quick libyaml pass that refuses huge or deep documents before anything is built.

It must count values exactly as the loader does (mapping keys are not values), so the refusal
names the same line and column; the timings live in bench/bench_bad_inputs.py.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from baobab.sim import yaml_source
from baobab.sim.errors import SourceError
from baobab.sim.yaml_limits import ScanProblem, ScanResult, events_at_most, scan_limits
from baobab.sim.yaml_source import load_located_yaml


def test_keys_are_not_values_and_the_root_is_one() -> None:
    text = "a: 1\nb: [2, 3]\nc: {d: 4, e: [5]}\n"
    # root, 1, [2, 3], 2, 3, {d, e}, 4, [5], 5
    assert scan_limits(text, 100, 10) == ScanResult(values=9, depth=3)


def test_the_first_value_over_the_limit_is_named() -> None:
    text = "a: 1\nb: [2, 3, 4]\n"
    # values in order: root, 1, [...], 2, 3, 4; the sixth is '4' at line 2, column 11
    assert scan_limits(text, 5, 10) == ScanProblem(2, 11, "more than 5 values")


def test_keys_that_are_collections_hold_no_values() -> None:
    text = "? [1, 2, 3]\n: x\n"
    assert scan_limits(text, 100, 10) == ScanResult(values=2, depth=1)


def test_depth_is_measured_without_recursion() -> None:
    text = "a: " + "[" * 5000 + "]" * 5000 + "\n"
    found = scan_limits(text, 100_000, 64)
    assert found == ScanProblem(1, 4 + 64, "nesting deeper than 64 levels")


def test_a_syntax_error_is_located() -> None:
    found = scan_limits("a: [1, 2\nb: 3\n", 100, 10)
    assert isinstance(found, ScanProblem) and found.message.startswith("YAML syntax error")
    assert (found.line, found.column) == (2, 2)


def test_events_bound_the_values() -> None:
    text = "a: [" + "0, " * 99 + "0]\n"
    # 102 values (the root, the list, 100 items); 109 events (+ stream, document, ends, key)
    assert scan_limits(text, 1000, 10) == ScanResult(values=102, depth=2)
    assert events_at_most(text, 109) and not events_at_most(text, 108)
    assert not events_at_most("a: [1\n", 1000)  # unknown: the full scan will say where


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "doc.yaml"
    path.write_text(text)
    return path


def test_the_loader_and_the_scan_blame_the_same_value(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(yaml_source, "MAX_NODES", 300)
    body = "x: 1\n" + "".join(f"k{i}: [{i}, {i}]\n" for i in range(120))
    scanned = write(tmp_path, body)  # longer than MAX_NODES characters: scanned first
    with pytest.raises(SourceError) as by_scan:
        load_located_yaml(scanned)
    monkeypatch.setattr(yaml_source, "scan_limits", lambda *_: ScanResult(0, 0))
    with pytest.raises(SourceError) as by_walk:
        load_located_yaml(scanned)  # the builder's own count
    assert str(by_scan.value) == str(by_walk.value)
    assert by_scan.value.message == "more than 300 values"


def test_a_deeply_nested_text_is_refused_where_it_gets_too_deep(tmp_path: Path) -> None:
    path = write(tmp_path, "a: 1\nb: " + "[" * 3000 + "]" * 3000 + "\n")
    with pytest.raises(SourceError, match="nesting deeper than 64 levels") as refused:
        load_located_yaml(path)
    assert (refused.value.line, refused.value.column) == (2, 4 + 64)


def test_errors_late_in_a_long_text_are_reported_without_a_second_pass(tmp_path: Path) -> None:
    values = "a: [" + "0, " * 4000 + "0]\n"
    for tail, fragment in (
        ("a: 2\n", "duplicate key 'a' (first defined at line 1)"),
        ("b: [1\n", "YAML syntax error"),
        ("\tc: 1\n", "YAML syntax error"),
    ):
        with pytest.raises(SourceError, match=fragment.replace("(", r"\(").replace(")", r"\)")):
            load_located_yaml(write(tmp_path, values + tail))
