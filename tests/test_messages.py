"""One line per error, values cut to a readable length, lines counted as editors count them.

argparse's usage errors are one line (``--help`` is unchanged); a path or value holding a line
break or a control character cannot split or garble the line; a huge value is cut; line
numbers count only ``\\n``, ``\\r\\n`` and ``\\r``; YAML 1.1's surprising scalars are refused
with the way to write them; a baseline nested past the JSON parser's limit is located.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from baobab.missions.cli.command_line import main
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.missions.testing.baseline import MAX_JSON_DEPTH, BaselineError, read_baseline
from baobab.sim.errors import MAX_MESSAGE_CHARS, SourceError, clip, one_line
from baobab.sim.text_positions import TextPositions
from baobab.sim.yaml11 import scalar_surprise
from baobab.sim.yaml_source import load_located_yaml

HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
MISSION = HEADER + "mission: m\nworld: walls\nrobot: turtlebot3\ntree: {wait: 1}\n"
BAOBAB = str(Path(sys.executable).with_name("baobab"))


@pytest.mark.parametrize(
    ("argv", "line"),
    [
        ([], "baobab: the following arguments are required: COMMAND (see baobab --help)"),
        (["rnu"], "baobab: argument COMMAND: invalid choice: 'rnu' (choose from"),
        (["run"], "baobab run: the following arguments are required: MISSION (see baobab run"),
        (["run", "m", "--port", "70000"], "baobab run: argument --port: a port is 0..65535, got"),
        (["tree", "m", "--format", "svg"], "baobab tree: argument --format: invalid choice: 'svg'"),
        (
            ["validate", "m", "--set", "novalue"],
            "argument --set: expected KEY=VALUE, got 'novalue'",
        ),
        (["validate", "m", "--frobnicate"], "baobab: unrecognized arguments: --frobnicate"),
        (["run", "m", "--fps", "0"], "baobab run: argument --fps: must be positive, got 0"),
    ],
)
def test_usage_errors_are_one_line_naming_the_help(
    argv: list[str], line: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.count("\n") == 1 and line in err, err
    assert err.rstrip().endswith("--help)")


def test_a_huge_unrecognized_argument_is_cut(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["validate", "m", "--x", "y" * 100_000]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and len(err) < MAX_MESSAGE_CHARS + 40
    assert "characters cut]" in err


def test_help_is_unchanged() -> None:
    done = subprocess.run([BAOBAB, "run", "--help"], capture_output=True, text=True, check=False)
    assert done.returncode == 0 and done.stderr == ""
    assert done.stdout.startswith("usage: baobab run [-h]")
    assert "seeing what happened:" in done.stdout


def test_one_line_escapes_breaks_controls_and_undecodable_bytes() -> None:
    text = "a\nb\rc\x1b[2J\u2028d\x85e\u202ef" + b"\xff".decode("utf-8", "surrogateescape")
    assert one_line(text) == "a\\nb\\rc\\x1b[2J\\u2028d\\x85e\\u202ef\\xff"
    assert one_line("tab\tand\u00a0space") == "tab\tand\u00a0space"
    cut = one_line("x" * 5000)
    assert len(cut) <= MAX_MESSAGE_CHARS and "[4040 characters cut]" in cut
    assert clip("y" * 1_500_000) == "y" * 57 + "... (1500000 characters)"


def test_a_path_with_a_line_break_stays_on_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    good = tmp_path / "good\nmission.yaml"
    good.write_text(MISSION)
    bad = tmp_path / "bad\r\nmission.yaml"
    bad.write_text(MISSION.replace("wait: 1", "wait: -1"))
    assert main(["validate", str(good), str(bad)]) == 2
    out, err = capsys.readouterr()
    assert out.splitlines() == [
        f"{tmp_path}/good\\nmission.yaml: ok (m: turtlebot3 in walls, 1 nodes)"
    ]
    assert err.splitlines() == [
        f"{tmp_path}/bad\\r\\nmission.yaml:5:8: wait.duration: Input should be greater than or "
        "equal to 0"
    ]
    assert str(SourceError("a\nb", 1, 1, "x")) == "a\\nb:1:1: x"


def test_a_1_5_mb_location_name_is_cut_in_the_message(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(MISSION.replace("{wait: 1}", "{navigate_to_pose: " + "a" * 1_500_000 + "}"))
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert err == (
        f"{path}:5:8: navigate_to_pose.goal: unknown location '{'a' * 57}... (1500000 "
        "characters)'; valid: default, goal_behind_north_wall, goal_behind_southwest_wall, "
        "goal_behind_wall, goal_open\n"
    )


def test_an_unknown_name_lists_at_most_forty_valid_ones(tmp_path: Path) -> None:
    locations = "".join(f"  spot_{i:03d}: {{x: 1, y: 1}}\n" for i in range(100))
    path = tmp_path / "m.yaml"
    path.write_text(
        MISSION.replace("{wait: 1}", "{navigate_to_pose: nowhere}") + "locations:\n" + locations
    )
    with pytest.raises(MissionError) as raised:
        load_mission(path)
    assert raised.value.message.endswith("spot_034, ... (65 more)")


@pytest.mark.parametrize(
    ("text", "line", "column"),
    [
        ("a\nb\nX", 3, 1),
        ("a\r\nb\r\nX", 3, 1),
        ("a\rb\rX", 3, 1),
        ("a\u2028b\x85c\u2029\nX", 2, 1),
        ("ab\n  cdX", 2, 5),
    ],
)
def test_positions_count_only_the_line_breaks_editors_count(
    text: str, line: int, column: int
) -> None:
    assert TextPositions(text).of_index(text.index("X")) == (line, column)


@given(
    breaks=st.lists(st.sampled_from(["\n", "\r\n", "\r"]), min_size=1, max_size=12),
    separators=st.lists(st.sampled_from(["\u2028", "\u2029", "\x85", "x"]), max_size=5),
)
def test_an_error_after_quoted_separators_is_on_the_editors_line(
    breaks: list[str], separators: list[str]
) -> None:
    # Each line holds a quoted string with YAML 1.1's extra line breaks; the last is an error.
    quoted = '"' + "".join(separators) + '"'
    lines = [f"k{i}: {quoted}" for i in range(len(breaks))]
    text = "".join(line + end for line, end in zip(lines, breaks, strict=True)) + "bad: [1,"
    with pytest.raises(SourceError) as raised:
        load_located_yaml("t.yaml", text=text)
    assert raised.value.line == len(breaks) + 1


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("off", "'off' reads as false in YAML 1.1; write false for a yes/no value, or quote it"),
        ("YES", "'YES' reads as true in YAML 1.1"),
        ("On", "'On' reads as true in YAML 1.1"),
        ("1:30", "'1:30' reads as the base-60 number 90 in YAML 1.1; write 90 if you mean"),
        ("1:30.5", "'1:30.5' reads as the base-60 number 90.5 in YAML 1.1"),
        ("-010", "'-010' reads as the octal number -8 in YAML 1.1; write -10 without the"),
    ],
)
def test_yaml11_scalars_are_refused_with_how_to_write_them(text: str, message: str) -> None:
    with pytest.raises(SourceError) as raised:
        load_located_yaml("t.yaml", text=f"key: {text}\n")
    assert (raised.value.line, raised.value.column) == (1, 6)
    assert raised.value.message.startswith(message)


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("'off'", "off"),
        ('"1:30"', "1:30"),
        ("true", True),
        ("False", False),
        ("90", 90),
        ("0", 0),
        ("0x1f", 31),
        ("1.5", 1.5),
        ("yes-please", "yes-please"),
    ],
)
def test_what_yaml_1_1_and_1_2_read_alike_is_accepted(text: str, value: object) -> None:
    assert load_located_yaml("t.yaml", text=f"key: {text}\n").data == {"key": value}
    assert scalar_surprise("tag:yaml.org,2002:str", text, text) is None


def _baseline(tmp_path: Path, text: str) -> BaselineError:
    path = tmp_path / "b.json"
    path.write_text(text)
    with pytest.raises(BaselineError) as raised:
        read_baseline(path, "m")
    return raised.value


def test_a_baseline_nested_past_the_json_parser_is_located(tmp_path: Path) -> None:
    # Brackets inside strings, escaped quotes included, do not nest.
    prefix = '{"note": "[[{\\"[", "deep":\n  '
    error = _baseline(tmp_path, prefix + "[" * 5000 + "]" * 5000 + "}")
    assert (error.line, error.column) == (2, 3 + MAX_JSON_DEPTH - 1)
    assert error.message == f"JSON nested deeper than {MAX_JSON_DEPTH} levels"


@pytest.mark.parametrize(
    ("text", "where", "message"),
    [
        ('{"metrics": 1' + "0" * 5000 + "}", "1:1", "not a usable JSON value: Exceeds the limit"),
        ('{"a":\n "\xff"}', "2:3", "not valid UTF-8 text"),
        ('{"a": 1,\n}', "2:1", "not valid JSON: Expecting property name"),
    ],
)
def test_broken_baselines_are_one_located_line(
    text: str, where: str, message: str, tmp_path: Path
) -> None:
    path = tmp_path / "b.json"
    path.write_bytes(text.encode("latin-1"))
    with pytest.raises(BaselineError) as raised:
        read_baseline(path, "m")
    assert f"{raised.value.line}:{raised.value.column}" == where
    assert raised.value.message.startswith(message)
