"""The registry and the JSON Schema built from it: complete, single, and in step with the loader."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import jsonschema
import pytest
import yaml

from baobab.behaviours.builtin import default_registry
from baobab.behaviours.common_nodes import WaitParams
from baobab.behaviours.registry import (
    BehaviourType,
    NodeKind,
    Registry,
    RegistryError,
)
from baobab.missions.language.json_schema import mission_json_schema
from baobab.missions.language.loader import load_mission
from baobab.missions.language.models import TOP_LEVEL_KEYS

FIXTURES = Path(__file__).parent / "missions"
MISSIONS = sorted(FIXTURES.glob("*.yaml"))
CHECKED_IN_SCHEMA = FIXTURES / "mission.schema.json"


@pytest.fixture(scope="module")
def validator() -> jsonschema.Draft202012Validator:
    """One validator per module: checking the schema against the meta-schema takes seconds."""
    schema = mission_json_schema()
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def _fixture(name: str) -> dict[str, Any]:
    data = yaml.safe_load((FIXTURES / name).read_text())
    assert isinstance(data, dict)
    return data


def test_a_type_can_be_registered_only_once() -> None:
    registry = Registry()
    entry = BehaviourType("pause", NodeKind.ACTION, WaitParams, "pause", lambda r: None)  # type: ignore[arg-type,return-value]
    registry.register(entry)
    with pytest.raises(RegistryError, match="'pause' is already registered"):
        registry.register(entry)
    with pytest.raises(RegistryError, match="lower_case identifier"):
        registry.register(
            BehaviourType("Pause", NodeKind.ACTION, WaitParams, "pause", entry.factory)
        )
    with pytest.raises(RegistryError, match="shorthand 'seconds' is not a parameter"):
        registry.register(
            BehaviourType(
                "halt", NodeKind.ACTION, WaitParams, "pause", entry.factory, shorthand="seconds"
            )
        )


def test_default_registry_has_the_design_vocabulary() -> None:
    names = set(default_registry().names())
    assert names >= {
        "sequence", "selector", "parallel", "retry", "timeout", "repeat", "invert",
        "force_success", "force_failure", "subtree", "navigate_to_pose",
        "navigate_through_poses", "follow_waypoints", "follow_path", "spin", "back_up",
        "drive_on_heading", "wait", "clear_costmaps", "assisted_teleop", "go_to_goal", "bug2",
        "move_to", "gripper", "is_at", "elapsed",
    }  # fmt: skip
    for behaviour in default_registry():
        assert behaviour.description and "\n" not in behaviour.description
        assert behaviour.params.model_config.get("extra") == "forbid"


def test_every_registered_type_is_used_by_a_fixture_mission() -> None:
    used: set[str] = set()
    for path in MISSIONS:
        mission = load_mission(path)
        used |= {node.type for node in mission.tree.walk()}
    assert used == set(default_registry().names())


def test_the_schema_is_valid_and_covers_every_type_and_top_level_key(
    validator: jsonschema.Draft202012Validator,
) -> None:
    schema = validator.schema
    variants = schema["$defs"]["Node"]["anyOf"]
    assert [next(iter(v["properties"])) for v in variants] == default_registry().names()
    assert list(schema["properties"]) == list(TOP_LEVEL_KEYS)
    assert schema["required"] == ["mission", "robot", "tree"]


@pytest.mark.parametrize("path", MISSIONS, ids=[path.name for path in MISSIONS])
def test_every_fixture_mission_validates(
    validator: jsonschema.Draft202012Validator, path: Path
) -> None:
    errors = [e.message for e in validator.iter_errors(yaml.safe_load(path.read_text()))]
    assert errors == []


def _set(data: dict[str, Any], path: tuple[str | int, ...], value: Any) -> dict[str, Any]:
    target: Any = data
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    return data


@pytest.mark.parametrize(
    ("path", "value"),
    [
        (("tree",), {"sequence": [{"navigate_to_pos": "kitchen"}]}),
        (("tree",), {"wait": {"duration": "soon"}}),
        (("tree",), {"wait": {"duraton": 5}}),
        (("tree",), {"wait": 1, "spin": 1}),
        (("tree",), {"sequence": []}),
        (("tree",), {"gripper": "ajar"}),
        (("tree",), {"retry": {"num_failures": 0, "child": {"wait": 1}}}),
        (("robot",), "turtlebot"),
        (("timeout",), -1),
        (("seed",), "seven"),
        (("events",), [{"at": 1, "teleport": {}}]),
        (("expect",), {"max_sim_tme": 10}),
        (("expect",), {"result": "DONE"}),
        (("params", "table", "type"), "integer"),
    ],
)
def test_the_schema_rejects_malformed_missions(
    validator: jsonschema.Draft202012Validator, path: tuple[str | int, ...], value: Any
) -> None:
    data = _set(_fixture("delivery.yaml"), path, value)
    assert list(validator.iter_errors(data)), f"accepted {path} = {value!r}"


def test_the_schema_accepts_parameter_references_in_typed_places(
    validator: jsonschema.Draft202012Validator,
) -> None:
    data = _fixture("delivery.yaml")
    data["tree"] = {
        "sequence": [
            {"wait": "${dwell}"},
            {"retry": {"num_failures": "${table}", "child": {"navigate_to_pose": "t_${table}"}}},
        ]
    }
    data["timeout"] = "${dwell}"
    assert list(validator.iter_errors(data)) == []
    data["timeout"] = "${not a name}"
    assert list(validator.iter_errors(data))


def test_the_checked_in_schema_is_current() -> None:
    checked_in = json.loads(CHECKED_IN_SCHEMA.read_text())
    assert checked_in == mission_json_schema(), (
        "regenerate it: baobab schema -o tests/missions/mission.schema.json"
    )
