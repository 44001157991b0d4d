"""The ``baobab`` command line: validate, tree, schema, list, and the placeholders."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import jsonschema
import pydot
import pytest
import yaml

from baobab.behaviours.builtin import default_registry
from baobab.missions.cli.command_line import main

FIXTURES = Path(__file__).parent / "missions"
MISSIONS = sorted(FIXTURES.glob("*.yaml"))
DELIVERY = FIXTURES / "delivery.yaml"
BTCPP_BUILTINS = {
    "Sequence", "ReactiveSequence", "SequenceWithMemory", "Fallback", "ReactiveFallback",
    "Parallel", "ParallelAll", "Inverter", "RetryUntilSuccessful", "Repeat", "Timeout",
    "ForceSuccess", "ForceFailure", "AlwaysSuccess", "AlwaysFailure", "Sleep", "SubTree",
}  # fmt: skip
CATEGORIES = {"Action", "Condition", "Decorator", "Control"}


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _broken(tmp_path: Path) -> Path:
    """The delivery fixture with a misspelt behaviour on line 24, next to its world."""
    shutil.copytree(FIXTURES / "worlds", tmp_path / "worlds", dirs_exist_ok=True)
    path = tmp_path / "broken.yaml"
    path.write_text(
        DELIVERY.read_text().replace("navigate_to_pose: kitchen", "navigate_to: kitchen")
    )
    return path


def test_validate_accepts_the_fixtures(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(capsys, "validate", *map(str, MISSIONS))
    assert (code, err) == (0, "")
    assert out.splitlines() == [
        f"{FIXTURES / 'delivery.yaml'}: ok (delivery: turtlebot3 in diner.yaml, 8 nodes)",
        f"{FIXTURES / 'dock.yaml'}: ok (dock: turtlebot3 in lobby, 4 nodes)",
        f"{FIXTURES / 'follow.yaml'}: ok (follow: turtlebot3 in lobby, 4 nodes)",
        f"{FIXTURES / 'guarded.yaml'}: ok (guarded: turtlebot3 in walls, 5 nodes)",
        f"{FIXTURES / 'lanes_tour.yaml'}: ok (lanes_tour: turtlebot3 in lanes.yaml, 5 nodes)",
        f"{FIXTURES / 'patrol.yaml'}: ok (patrol: turtlebot3 in walls, 27 nodes)",
        f"{FIXTURES / 'pick.yaml'}: ok (pick_and_place: panda in panda_table, 11 nodes)",
        f"{FIXTURES / 'ros_listener.yaml'}: ok (ros_listener: turtlebot3 in walls, 3 nodes)",
    ]


def test_validate_reports_each_bad_file_on_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    broken = _broken(tmp_path)
    code, out, err = _run(capsys, "validate", str(broken), str(DELIVERY))
    assert code == 2
    assert err == (
        f"{broken}:24:7: unknown behaviour 'navigate_to'; did you mean 'navigate_to_pose'? "
        f"valid: {', '.join(sorted(default_registry().names()))}\n"
    )
    assert out == f"{DELIVERY}: ok (delivery: turtlebot3 in diner.yaml, 8 nodes)\n"


def test_validate_applies_set_and_reports_choices(capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = _run(capsys, "validate", str(DELIVERY), "--set", "table=9")
    assert code == 2
    assert err == f"{DELIVERY}:9:3: --set table=9: 9 is not one of the choices 1, 2, 3, 4, 5\n"
    assert _run(capsys, "validate", str(DELIVERY), "--set", "table=5")[0] == 0


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["validate", str(DELIVERY), "--set", "table"], "expected KEY=VALUE, got 'table'"),
        (["validate", str(DELIVERY), "--set", "table=1", "--set", "table=2"], "given twice"),
        (["validate"], "the following arguments are required: FILE"),
        (["tree", str(DELIVERY), "--format", "png"], "invalid choice: 'png'"),
        (["validate", "/no/such/mission.yaml"], "/no/such/mission.yaml:1:1: no such file"),
    ],
)
def test_usage_mistakes_exit_2_without_a_traceback(
    capsys: pytest.CaptureFixture[str], argv: list[str], fragment: str
) -> None:
    code, _, err = _run(capsys, *argv)
    assert code == 2
    assert fragment in err
    assert "Traceback" not in err


def test_the_installed_command_validates_in_a_subprocess(tmp_path: Path) -> None:
    command = Path(sys.executable).parent / "baobab"
    broken = _broken(tmp_path)
    done = subprocess.run(
        [str(command), "validate", str(DELIVERY), str(broken)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 2
    assert done.stdout.startswith(f"{DELIVERY}: ok")
    assert done.stderr.startswith(f"{broken}:24:7: unknown behaviour 'navigate_to'")
    assert len(done.stderr.splitlines()) == 1


def test_tree_prints_the_substituted_unicode_tree(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _run(capsys, "tree", str(DELIVERY), "--set", "table=5")
    assert code == 0
    assert out.splitlines() == [
        "{-} sequence",
        "    -^- subtree deliver(table=5, dwell=2.0)",
        "        {-} sequence",
        "            -^- retry x3",
        "                -^- timeout 120 s",
        "                    --> navigate_to_pose table_5",
        "            --> wait 2 s",
        "    --> navigate_to_pose kitchen",
    ]


@pytest.mark.filterwarnings("ignore:'setParseAction' deprecated")  # inside pydot's parser
def test_tree_dot_is_a_graphviz_graph(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _run(capsys, "tree", str(DELIVERY), "--format", "dot")
    assert code == 0
    graphs = pydot.graph_from_dot_data(out)
    assert graphs is not None
    (graph,) = graphs
    labels = {str(node.get("label")).strip('"') for node in graph.get_nodes()}
    assert {"navigate_to_pose kitchen", "navigate_to_pose table_3", "wait 2 s"} <= labels
    assert len(graph.get_edges()) == 7


@pytest.mark.parametrize("path", MISSIONS, ids=[path.name for path in MISSIONS])
def test_tree_btcpp_is_groot_ready_xml(capsys: pytest.CaptureFixture[str], path: Path) -> None:
    code, out, _ = _run(capsys, "tree", str(path), "--format", "btcpp")
    assert code == 0
    root = ET.fromstring(out)
    assert root.tag == "root" and root.get("BTCPP_format") == "4"
    trees = {tree.get("ID"): tree for tree in root.findall("BehaviorTree")}
    assert root.get("main_tree_to_execute") in trees
    assert all(len(list(tree)) == 1 for tree in trees.values())
    (model,) = root.findall("TreeNodesModel")
    declared = {(entry.tag, entry.get("ID")): entry for entry in model}
    assert all(tag in CATEGORIES | {"SubTree"} for tag, _ in declared)
    ports = {
        key[1]: {port.get("name") for port in entry.findall("input_port")}
        for key, entry in declared.items()
    }
    for tree in trees.values():
        for element in tree.iter():
            if element is tree:
                continue
            if element.tag == "SubTree":
                assert ("SubTree", element.get("ID")) in declared
                assert set(element.attrib) - {"ID"} <= ports[element.get("ID")]
                assert "name" not in element.attrib  # Groot2 crashes on named SubTrees
            elif element.tag not in BTCPP_BUILTINS:
                assert element.tag in ports, f"{element.tag} missing from TreeNodesModel"
                assert set(element.attrib) - {"name"} <= ports[element.tag]
    custom = {element.tag for tree in trees.values() for element in tree.iter()} - BTCPP_BUILTINS
    custom.discard("BehaviorTree")
    assert custom == {entry_id for (tag, entry_id) in declared if tag != "SubTree"}


def test_schema_validates_the_fixtures_and_rejects_a_malformed_mission(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    code, out, _ = _run(capsys, "schema")
    assert code == 0
    schema = json.loads(out)  # checked against the meta-schema in test_mission_schema.py
    validator = jsonschema.Draft202012Validator(schema)
    for path in MISSIONS:
        assert list(validator.iter_errors(yaml.safe_load(path.read_text()))) == [], path
    broken = yaml.safe_load(_broken(tmp_path).read_text())
    assert list(validator.iter_errors(broken))
    written = tmp_path / "schema.json"
    assert _run(capsys, "schema", "--output", str(written))[0] == 0
    assert json.loads(written.read_text()) == schema


def test_list_names_missions_worlds_robots_and_every_behaviour(
    capsys: pytest.CaptureFixture[str],
) -> None:
    code, out, _ = _run(capsys, "list")
    assert code == 0
    sections = [line for line in out.splitlines() if not line.startswith(" ")]
    assert sections == ["missions:", "worlds:", "robots:", "behaviours:"]
    assert "  walls" in out.splitlines()
    assert "  panda_table (scene)" in out.splitlines()
    listed = {line.split()[0] for line in out.split("behaviours:\n")[1].splitlines()}
    assert listed == set(default_registry().names())
    assert any(
        line.split()[:3] == ["bug2", "action", "[base_controllers]"] for line in out.splitlines()
    )
    code, out, _ = _run(capsys, "list", "--json")
    catalogue = json.loads(out)
    assert set(catalogue) == {"missions", "worlds", "scenes", "robots", "behaviours"}
    assert catalogue["robots"]["panda"]["capabilities"] == ["arm", "gripper", "ros_nodes"]
    waffle = catalogue["robots"]["turtlebot3_waffle"]
    assert len(waffle["footprint"]["polygon"]) == 4
    assert catalogue["robots"]["turtlebot4"]["lidar"]["range"] == [0.15, 12.0]
    assert catalogue["robots"]["turtlebot3"]["aliases"] == ["turtlebot3_burger"]
    assert catalogue["behaviours"]["move_to"]["capability"] == "arm"
    assert "walls" in catalogue["worlds"]
