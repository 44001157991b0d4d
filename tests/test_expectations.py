"""The ``expect:`` vocabulary, evaluated against hand-made run endings and metrics."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import Mission, load_mission
from baobab.missions.run.expectations import (
    ExpectationResult,
    RunEnd,
    all_passed,
    check_metric_names,
    evaluate,
)
from baobab.missions.run.metrics import MetricRegistry

HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
MOBILE = """
mission: judged
world: walls
robot: turtlebot3
locations:
  dock: {x: 1.0, y: -2.0, yaw_deg: 90}
tree:
  go_to_goal: goal_open
expect:
"""
ARM = """
mission: judged_arm
robot: panda
locations:
  place: {position: [0.45, 0.3, 0.525]}
tree:
  gripper: open
expect:
"""
SUCCEEDED = RunEnd("SUCCEEDED", 0, "NONE", 20.0)


def _mission(tmp_path: Path, body: str, expect: str) -> Mission:
    path = tmp_path / "m.yaml"
    indented = "".join(f"  {line}\n" for line in expect.strip().splitlines())
    path.write_text(HEADER + body + indented)
    return load_mission(path)


def _mobile_metrics(**changes: Any) -> dict[str, Any]:
    metrics: dict[str, Any] = {
        "sim_time": 20.0,
        "path_length": 3.0,
        "straight_line_distance": 2.5,
        "min_clearance": 0.2,
        "contacts": 0,
        "contact_objects": [],
        "final_pose": {"x": 2.01, "y": 1.98, "yaw": 0.5},
        "visited": ["default", "goal_open", "dock", "goal_open"],
        "number_of_recoveries": 1,
        "planned_path_length": None,
    }
    metrics.update(changes)
    return metrics


def _judge(
    tmp_path: Path, expect: str, metrics: dict[str, Any], end: RunEnd = SUCCEEDED
) -> dict[str, ExpectationResult]:
    mission = _mission(tmp_path, MOBILE, expect)
    return {result.name: result for result in evaluate(mission.expect, end, metrics, mission)}


def test_no_expect_block_means_no_expectations(tmp_path: Path) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(HEADER + MOBILE.replace("expect:\n", ""))
    mission = load_mission(path)
    assert evaluate(mission.expect, SUCCEEDED, _mobile_metrics(), mission) == []
    assert all_passed([])


def test_result_error_code_and_sim_time(tmp_path: Path) -> None:
    failed = RunEnd("FAILED", 801, "FAILED_TO_MAKE_PROGRESS", 40.0)
    by_name = _judge(
        tmp_path,
        "result: FAILED\nerror_code: FAILED_TO_MAKE_PROGRESS\nmax_sim_time: 45",
        _mobile_metrics(),
        failed,
    )
    assert [r.passed for r in by_name.values()] == [True, True, True]
    assert by_name["error_code"].measured == "FAILED_TO_MAKE_PROGRESS"
    by_number = _judge(
        tmp_path, "result: FAILED\nerror_code: 800\nmax_sim_time: 30", _mobile_metrics(), failed
    )
    assert (by_number["error_code"].measured, by_number["error_code"].passed) == (801, False)
    assert (by_number["max_sim_time"].measured, by_number["max_sim_time"].passed) == (40.0, False)
    assert by_number["result"].as_dict() == {
        "name": "result",
        "expected": "FAILED",
        "measured": "FAILED",
        "passed": True,
        "detail": "ended FAILED",
    }


def test_final_pose_near_a_location_or_a_pose_with_heading(tmp_path: Path) -> None:
    near = _judge(
        tmp_path, "final_pose_near: {location: goal_open, xy_tolerance: 0.05}", _mobile_metrics()
    )["final_pose_near"]
    assert near.passed and near.measured == pytest.approx(math.hypot(0.01, 0.02))
    assert near.expected == {"location": "goal_open", "xy_tolerance": 0.05}
    too_far = _judge(tmp_path, "final_pose_near: {location: dock}", _mobile_metrics())
    assert not too_far["final_pose_near"].passed
    heading = "final_pose_near: {pose: {x: 2, y: 2, yaw_deg: 90}, yaw_tolerance: 0.1}"
    turned = _judge(tmp_path, heading, _mobile_metrics())["final_pose_near"]
    assert not turned.passed and "heading off by 1.071 rad" in turned.detail
    aligned = _mobile_metrics(final_pose={"x": 2.0, "y": 2.0, "yaw": math.pi / 2 + 0.05})
    assert _judge(tmp_path, heading, aligned)["final_pose_near"].passed


def test_visited_in_order_is_a_subsequence(tmp_path: Path) -> None:
    metrics = _mobile_metrics()
    assert _judge(tmp_path, "visited_in_order: [goal_open, dock]", metrics)[
        "visited_in_order"
    ].passed
    assert _judge(tmp_path, "visited_in_order: [dock, goal_open]", metrics)[
        "visited_in_order"
    ].passed
    backwards = _judge(tmp_path, "visited_in_order: [dock, goal_open, dock]", metrics)
    assert not backwards["visited_in_order"].passed
    assert backwards["visited_in_order"].measured == metrics["visited"]


def test_clearance_contact_recoveries(tmp_path: Path) -> None:
    expect = "min_clearance: 0.1\nno_contact: true\nmax_recoveries: 1"
    results = _judge(tmp_path, expect, _mobile_metrics())
    assert all(r.passed for r in results.values())
    worse = _mobile_metrics(min_clearance=0.05, contacts=3, contact_objects=["wall_east"])
    results = _judge(tmp_path, expect.replace("recoveries: 1", "recoveries: 0"), worse)
    assert [r.passed for r in results.values()] == [False, False, False]
    assert results["no_contact"].detail == "3 contact samples (wall_east)"
    nothing_near = _judge(tmp_path, "min_clearance: 0.1", _mobile_metrics(min_clearance=None))
    assert nothing_near["min_clearance"].passed and nothing_near["min_clearance"].measured is None
    wanted_contact = _judge(tmp_path, "no_contact: false", worse)["no_contact"]
    assert wanted_contact.passed


def test_path_length_ratio_prefers_the_planned_length(tmp_path: Path) -> None:
    straight = _judge(tmp_path, "max_path_length_ratio: 1.1", _mobile_metrics())
    assert straight["max_path_length_ratio"].measured == pytest.approx(1.2)
    assert not straight["max_path_length_ratio"].passed
    planned = _judge(
        tmp_path, "max_path_length_ratio: 1.1", _mobile_metrics(planned_path_length=2.9)
    )
    ratio = planned["max_path_length_ratio"]
    assert ratio.passed and ratio.measured == pytest.approx(3.0 / 2.9)
    assert "planned" in ratio.detail
    standing = _judge(
        tmp_path, "max_path_length_ratio: 1.1", _mobile_metrics(straight_line_distance=0.0)
    )
    assert not standing["max_path_length_ratio"].passed


def test_metric_bounds(tmp_path: Path) -> None:
    expect = "metrics:\n  path_length: {min: 1.0, max: 2.5}\n  contacts: {max: 0}"
    results = _judge(tmp_path, expect, _mobile_metrics())
    too_long = results["metrics.path_length"]
    assert (too_long.expected, too_long.measured, too_long.passed) == (
        {"min": 1.0, "max": 2.5},
        3.0,
        False,
    )
    assert results["metrics.contacts"].passed
    unknown = _judge(tmp_path, "metrics:\n  planned_path_length: {max: 5}", _mobile_metrics())
    assert not unknown["metrics.planned_path_length"].passed


def test_arm_expectations(tmp_path: Path) -> None:
    mission = _mission(
        tmp_path,
        ARM,
        "object_lifted: 0.1\nobject_placed: {target: place, tolerance: 0.02}",
    )
    metrics: dict[str, Any] = {"object_max_lift": 0.15, "cube_final_position": [0.46, 0.3, 0.525]}
    lifted, placed = evaluate(mission.expect, SUCCEEDED, metrics, mission)
    assert (lifted.name, lifted.measured, lifted.passed) == ("object_lifted", 0.15, True)
    assert placed.passed and placed.measured == pytest.approx(0.01)
    metrics["cube_final_position"] = [0.5, 0.3, 0.525]
    assert not evaluate(mission.expect, SUCCEEDED, metrics, mission)[1].passed


def test_metric_names_are_checked_when_the_mission_loads(tmp_path: Path) -> None:
    for body, name, message in [
        (MOBILE, "path_lenght", "unknown metric 'path_lenght' in runs of turtlebot3; did you mean"),
        (MOBILE, "final_pose", "metric 'final_pose' is not a number; bounds apply to: sim_time"),
        (ARM, "path_length", "unknown metric 'path_length' in runs of panda"),
    ]:
        with pytest.raises(MissionError, match=message) as raised:
            _mission(tmp_path, body, f"metrics:\n  {name}: {{max: 1}}")
        assert (raised.value.line, raised.value.column) == (12 if body is MOBILE else 11, 5)


def test_the_run_checks_metric_names_against_its_own_registry(tmp_path: Path) -> None:
    registry = MetricRegistry()
    registry.add("path_length", lambda: 0.0, unit="m")
    registry.add("final_pose", lambda: {}, number=False)
    known = _mission(tmp_path, MOBILE, "metrics:\n  path_length: {max: 1}")
    check_metric_names(known, registry.number_names(), registry.names())
    mission = _mission(tmp_path, MOBILE, "metrics:\n  sim_time: {max: 1}")
    with pytest.raises(MissionError, match="unknown metric 'sim_time'") as raised:
        check_metric_names(mission, registry.number_names(), registry.names())
    assert (raised.value.line, raised.value.column) == (12, 5)
