"""The located YAML loader: data, marks and every rejection with its line and column."""

from __future__ import annotations

from pathlib import Path

import pytest

from baobab.sim.errors import SourceError
from baobab.sim.yaml_source import MAX_ALIASES, MAX_DEPTH, load_located_yaml


def _load(tmp_path: Path, text: str | bytes) -> object:
    path = tmp_path / "doc.yaml"
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text)
    return load_located_yaml(path)


def test_marks_point_at_keys_and_items(tmp_path: Path) -> None:
    path = tmp_path / "doc.yaml"
    path.write_text("a: 1\nb:\n  - x: 2\n  - 3\n")
    document = load_located_yaml(path)
    assert document.data == {"a": 1, "b": [{"x": 2}, 3]}
    assert document.locate(("a",)) == (1, 1)
    assert document.locate(("b", 0, "x")) == (3, 5)
    assert document.locate(("b", 1)) == (4, 5)
    assert document.locate(("b", 1, "missing")) == (4, 5)


@pytest.mark.parametrize(
    ("text", "where", "fragment"),
    [
        ("a: 1\na: 2\n", "2:1", "duplicate key 'a'"),
        ("a: [1, 2\n", "2:1", "YAML syntax error"),
        ("a: .nan\n", "1:4", "non-finite"),
        ("a: -.inf\n", "1:4", "non-finite"),
        ("a: 1.0e+400\n", "1:4", "non-finite"),
        ("", "1:1", "empty"),
        ("? [1, 2]\n: 3\n", "1:3", "plain value"),
        ("a: 123456789012345678901\n", "1:4", "too large"),
        ("base: &b {x: 1}\nother:\n  <<: *b\n", "3:3", "merge keys"),
        ("a: 1\n---\nb: 2\n", "2:1", "YAML syntax error"),
    ],
)
def test_rejections_are_located(tmp_path: Path, text: str, where: str, fragment: str) -> None:
    with pytest.raises(SourceError) as caught:
        _load(tmp_path, text)
    message = str(caught.value)
    assert message.startswith(f"{tmp_path / 'doc.yaml'}:{where}: "), message
    assert fragment in message
    assert "\n" not in message


def test_alias_bomb_is_refused(tmp_path: Path) -> None:
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x]"]
    for level in range(1, 9):
        previous = f"*a{level - 1}"
        lines.append(f"a{level}: &a{level} [{', '.join([previous] * 9)}]")
    with pytest.raises(SourceError, match=f"more than {MAX_ALIASES} aliases"):
        _load(tmp_path, "\n".join(lines) + "\n")


def test_deep_nesting_is_refused(tmp_path: Path) -> None:
    text = "a: " + "[" * (MAX_DEPTH + 5) + "]" * (MAX_DEPTH + 5) + "\n"
    with pytest.raises(SourceError, match="nesting deeper"):
        _load(tmp_path, text)


def test_binary_and_non_utf8_files_are_refused(tmp_path: Path) -> None:
    with pytest.raises(SourceError, match="binary"):
        _load(tmp_path, b"a: 1\x00\x01")
    with pytest.raises(SourceError, match=r":2:4: not valid UTF-8"):
        _load(tmp_path, b"a: 1\nb: \xff\xfe\n")


def test_missing_file_and_directory(tmp_path: Path) -> None:
    with pytest.raises(SourceError, match="no such file"):
        load_located_yaml(tmp_path / "absent.yaml")
    with pytest.raises(SourceError, match="is a directory"):
        load_located_yaml(tmp_path)


def test_python_tags_are_never_executed(tmp_path: Path) -> None:
    with pytest.raises(SourceError):
        _load(tmp_path, "a: !!python/object/apply:os.system ['true']\n")
