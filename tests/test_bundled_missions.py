"""The missions shipped in ``missions/``: valid, judged, editor-ready, and one run end to end."""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path

import pytest

from baobab.behaviours.navigation_nodes import NavigateThroughPosesParams
from baobab.behaviours.ports import Capabilities
from baobab.missions.language.bundled_missions import resolve_mission
from baobab.missions.language.compiler import compile_mission
from baobab.missions.language.json_schema import mission_json_schema
from baobab.missions.language.loader import load_mission
from baobab.missions.run.plot_data import MobilePlot
from baobab.missions.run.runner import run_mission

FOLDER = Path(str(resources.files("baobab.missions")))
BUNDLED = sorted(FOLDER.glob("*.yaml"))


def test_the_expected_missions_are_bundled() -> None:
    assert {path.stem for path in BUNDLED} >= {
        "walls_go_to_goal",
        "walls_bug2",
        "cafe_delivery",
        "farm_rows",
        "waypoint_patrol",
        "waypoint_patrol_cancel",
        "town_nav_to_pose",
        "office_patrol",
    }


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_each_bundled_mission_is_valid_and_judged(path: Path) -> None:
    assert path.read_text().splitlines()[0] == (
        "# yaml-language-server: $schema=mission.schema.json"
    )
    mission = load_mission(path)
    assert mission.name == path.stem
    assert mission.expect is not None and mission.expect.result is not None
    assert resolve_mission(path.stem) == path
    offline = Capabilities(clock=lambda: 0.0)
    compiled = compile_mission(mission, offline, require_ports=False)
    assert compiled.goal_leaves()


def test_the_shipped_schema_is_the_current_one() -> None:
    shipped = json.loads((FOLDER / "mission.schema.json").read_text())
    assert shipped == json.loads(json.dumps(mission_json_schema()))


def test_farm_rows_drives_through_the_seed_poses() -> None:
    mission = load_mission(FOLDER / "farm_rows.yaml")
    (leaf,) = [n for n in mission.tree.walk() if n.type == "navigate_through_poses"]
    assert isinstance(leaf.params, NavigateThroughPosesParams)
    poses = leaf.params.poses
    assert len(poses) == 41
    assert (poses[0].x, poses[0].y) == (-5.0, -4.2)
    assert (poses[-1].x, poses[-1].y) == (13.0, 4.2)


def test_cafe_delivery_to_table_1_and_back() -> None:
    mission = load_mission(FOLDER / "cafe_delivery.yaml", {"table": "1", "pickup": "1"})
    record = run_mission(mission)
    result = record.result_object()
    assert record.exit_code == 0, result["expectations"]
    assert result["result"] == "SUCCEEDED"
    metrics = result["metrics"]
    assert metrics["visited"][0] == "kitchen" and metrics["visited"][-1] == "kitchen"
    assert "table_1" in metrics["visited"]
    assert metrics["planned_path_length"] > 15.0
    assert metrics["path_length"] < 1.3 * metrics["planned_path_length"]
    assert isinstance(record.plot, MobilePlot) and record.plot.costmap is not None


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_each_bundled_mission_runs_as_intended(path: Path) -> None:
    record = run_mission(load_mission(path))
    result = record.result_object()
    failed = [e for e in result["expectations"] if not e["passed"]]
    assert record.exit_code == 0, failed
    assert result["expectations"] and not failed
