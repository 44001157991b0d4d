"""Property-based fuzzing of the mission and world loaders: only located errors escape.

The inputs are mutations of the bundled missions and worlds (lines deleted, duplicated or
re-indented, characters swapped, scalars and keys replaced by odd ones, truncations) and
random structures dumped with PyYAML. Whatever the text, the loader returns a mission or
raises the located error it documents, as one line; never any other exception.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from functools import cache
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from baobab.missions.language import loader
from baobab.missions.language.loader import SCHEMA_HEADER, load_mission
from baobab.missions.language.models import TOP_LEVEL_KEYS
from baobab.sim.errors import SourceError, WorldError
from baobab.sim.world import World, bundled_world_names, bundled_world_path, load_world

REPO = Path(__file__).parent.parent
FIXTURES = Path(__file__).parent / "missions"
MISSIONS = sorted((REPO / "missions").glob("*.yaml")) + sorted(FIXTURES.glob("*.yaml"))
MISSION_TEXTS = [(path, path.read_text(encoding="utf-8")) for path in MISSIONS]
WORLDS = [bundled_world_path(name) for name in bundled_world_names()]
WORLDS.append(FIXTURES / "worlds" / "diner.yaml")
WORLD_TEXTS = [path.read_text(encoding="utf-8") for path in WORLDS]
LOCATED = re.compile(r"^.+:\d+:\d+: \S")

ODD_SCALARS = [
    "", "~", "null", "0", "-1", "1e999", "-.inf", ".nan", "99999999999999999999", "0x1F",
    "true", "no", "'quoted'", '"unterminated', "[", "]", "{", "}", "[1, 2", "{a: 1}", "[]",
    "{}", "*alias", "&anchor x", "!!python/object/apply:os.system ['true']", "!tag x",
    "${x}", "${", "$${x}", "table_${table}", "2001-12-14", "!!binary aGk=", "|", ">",
    "- a", ": x", "? x", "\t", "é", "\\u0000", "@at", "`tick`", "%YAML 1.1", "---", "...",
    "<<: *a", "1:2", "0o17", "+12", "1_000", "3.", "1e3", "yes", "kitchen", "cafe",
    "turtlebot3", "panda", "walls", "../x.yaml", "/etc/passwd", "worlds/diner.yaml",
]  # fmt: skip
NAMES = sorted(TOP_LEVEL_KEYS) + [
    "sequence", "fallback", "wait", "retry", "navigate_to_pose", "subtree", "x", "y", "yaw",
    "yaw_deg", "at", "type", "default", "choices", "min", "max", "name", "args", "child",
    "children", "floor", "size", "boxes", "cylinders", "spawns", "default", "center", "radius",
    "colour", "result", "max_sim_time", "position", "orientation", "unknown_key", "",
]  # fmt: skip

DUMPER = getattr(yaml, "CSafeDumper", yaml.SafeDumper)
lines_to_text = "\n".join


@st.composite
def mutated(draw: st.DrawFn, texts: list[str]) -> str:
    """A bundled file with one to four random mutations."""
    lines = draw(st.sampled_from(texts)).split("\n")
    for _ in range(draw(st.integers(1, 4))):
        index = draw(st.integers(0, len(lines) - 1))
        line = lines[index]
        kind = draw(st.integers(0, 8))
        if kind == 0:
            del lines[index]
        elif kind == 1:
            lines.insert(index, line)
        elif kind == 2 and len(line) > 1:
            at = draw(st.integers(0, len(line) - 2))
            lines[index] = line[:at] + line[at + 1] + line[at] + line[at + 2 :]
        elif kind == 3 and ":" in line:
            head = line[: line.index(":") + 1]
            lines[index] = f"{head} {draw(st.sampled_from(ODD_SCALARS))}"
        elif kind == 4:
            indent = " " * draw(st.integers(0, 8))
            key, value = draw(st.sampled_from(NAMES)), draw(st.sampled_from(ODD_SCALARS))
            lines.insert(index, f"{indent}{key}: {value}")
        elif kind == 5:
            lines[index] = " " * draw(st.integers(0, 6)) + line.lstrip(" ")
        elif kind == 6:
            at = draw(st.integers(0, len(line)))
            lines[index] = line[:at] + draw(st.sampled_from(ODD_SCALARS)) + line[at:]
        elif kind == 7 and ":" in line:
            rest = line[line.index(":") :]
            indent = line[: len(line) - len(line.lstrip(" "))]
            lines[index] = indent + draw(st.sampled_from(NAMES)) + rest
        else:
            text = lines_to_text(lines)
            return text[: draw(st.integers(0, len(text)))]
    return lines_to_text(lines)


scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**20), 10**20),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from(ODD_SCALARS + NAMES),
    st.text(max_size=8),
)
structures = st.recursive(
    scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=3),
        st.dictionaries(st.sampled_from(NAMES), inner, max_size=3),
    ),
    max_leaves=8,
)


@st.composite
def generated_mission(draw: st.DrawFn) -> str:
    """A random mapping of top-level keys, dumped by PyYAML behind the schema header."""
    data = draw(st.dictionaries(st.sampled_from(sorted(TOP_LEVEL_KEYS)), structures, max_size=5))
    if draw(st.booleans()):
        data.update(mission="m", robot=draw(st.sampled_from(["turtlebot3", "panda"])))
        data.setdefault("world", draw(st.sampled_from(["walls", "cafe", "worlds/diner.yaml"])))
    return f"{SCHEMA_HEADER}mission.schema.json\n" + yaml.dump(data, Dumper=DUMPER, sort_keys=False)


def _assert_one_located_line(error: Exception) -> None:
    message = str(error)
    assert "\n" not in message, message
    assert LOCATED.match(message), message


@cache
def _bundled_world(name: str) -> World:
    return load_world(name)


def _load_world_reusing_bundled(name_or_path: str | Path) -> World:
    """``load_world``, but each bundled world (constant text) is parsed once per session.

    Parsing a world is most of a mission's load time; the world loader is fuzzed on its own
    below, and world files named by path are still read and parsed every time.
    """
    if isinstance(name_or_path, str):
        return _bundled_world(name_or_path)
    return load_world(name_or_path)


@pytest.fixture(scope="module", autouse=True)
def _reuse_bundled_worlds() -> Iterator[None]:
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(loader, "load_world", _load_world_reusing_bundled)
        yield


@settings(
    max_examples=2000,
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(st.one_of(mutated([text for _, text in MISSION_TEXTS]), generated_mission()))
def test_the_mission_loader_raises_only_located_errors(text: str) -> None:
    # Loaded as if it stood beside the fixtures, so world paths like worlds/diner.yaml resolve.
    path = FIXTURES / "fuzzed.yaml"
    try:
        mission = load_mission(path, text=text)
    except SourceError as error:  # a mission, world or robot file: each error is located
        _assert_one_located_line(error)
    else:
        assert mission.path == path


@pytest.fixture(scope="module")
def world_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("fuzz") / "world.yaml"


@settings(
    max_examples=500,
    derandomize=True,
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(text=mutated(WORLD_TEXTS))
def test_the_world_loader_raises_only_world_errors(world_file: Path, text: str) -> None:
    world_file.write_text(text, encoding="utf-8")
    try:
        world = load_world(world_file)
    except WorldError as error:
        _assert_one_located_line(error)
    else:
        assert "default" in world.spawns


def test_the_fuzzed_inputs_start_from_every_bundled_file() -> None:
    assert len(MISSION_TEXTS) >= 7
    assert {path.stem for path in WORLDS} >= {"cafe", "farm", "town", "walls", "diner"}
