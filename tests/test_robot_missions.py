"""Missions and robots: every bundled mobile mission on every bundled mobile robot it fits,
the robots a mission declares, ``--robot``, and campaigns over robots.

The Burger's runs of the bundled missions are ``test_bundled_missions.py``'s and
``test_determinism.py``'s; here run the other robots, and the TurtleBot 4 on the farm against
the Burger: at least as fast as their top speeds say.
"""

from __future__ import annotations

import json
import sqlite3
from importlib import resources
from pathlib import Path

import pytest

from baobab.missions.cli.command_line import main
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.missions.run.runner import run_mission
from baobab.robots.catalog import DEFAULT_MOBILE_ROBOT, MOBILE_ROBOTS, ROBOTS

FOLDER = Path(str(resources.files("baobab.missions")))
FARM = FOLDER / "farm_rows.yaml"


def _mobile_missions() -> list[Path]:
    return [path for path in sorted(FOLDER.glob("*.yaml")) if load_mission(path).robot.mobile]


def _pairs() -> list[tuple[Path, str]]:
    """(mission, robot) for every bundled mobile mission and every other mobile robot it fits;
    the TurtleBot 4's farm run is the speed test's."""
    pairs = []
    for path in _mobile_missions():
        fits = load_mission(path).supported_robots or MOBILE_ROBOTS
        for robot in fits:
            if robot != DEFAULT_MOBILE_ROBOT and (path, robot) != (FARM, "turtlebot4"):
                pairs.append((path, robot))
    return pairs


def test_each_bundled_mobile_mission_fits_every_mobile_robot_or_says_which() -> None:
    for path in _mobile_missions():
        mission = load_mission(path)
        fits = mission.supported_robots or MOBILE_ROBOTS
        assert mission.robot.name in fits
        assert set(fits) <= set(MOBILE_ROBOTS)
        for robot in set(MOBILE_ROBOTS) - set(fits):
            with pytest.raises(MissionError) as caught:
                load_mission(path, robot=robot)
            assert "robots:" in str(caught.value) and ", ".join(fits) in str(caught.value)


@pytest.mark.parametrize(
    ("path", "robot"), _pairs(), ids=lambda value: value.stem if isinstance(value, Path) else value
)
def test_each_mobile_mission_meets_its_expectations_on_each_robot_it_fits(
    path: Path, robot: str
) -> None:
    record = run_mission(load_mission(path, robot=robot))
    assert record.mission.robot.name == robot
    failed = [(e.name, e.expected, e.measured) for e in record.expectations if not e.passed]
    assert record.intended, failed


def test_the_turtlebot4_drives_the_farm_faster_as_its_top_speed_says() -> None:
    burger = run_mission(load_mission(FARM))
    tb4 = run_mission(load_mission(FARM, robot="turtlebot4"))
    failed = [(e.name, e.measured) for e in tb4.expectations if not e.passed]
    assert tb4.intended, failed  # the 41 poses in order, no contact, the final pose
    assert tb4.metrics["contacts"] == 0 and tb4.metrics["contact_objects"] == []
    assert {e.name for e in tb4.expectations} >= {"visited_in_order", "no_contact"}
    v_max = ROBOTS["turtlebot4"].max_linear_speed
    burger_time, tb4_time = burger.metrics["sim_time"], tb4.metrics["sim_time"]
    assert isinstance(burger_time, float) and isinstance(tb4_time, float)
    assert tb4_time <= 0.22 / v_max * burger_time * 1.15, (tb4_time, burger_time)


def _run(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_run_robot_overrides_the_missions_robot_where_it_fits(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["run", "walls_go_to_goal", "--robot", "turtlebot4", "--json"]
    code, out, _ = _run([*argv, "--out", str(tmp_path / "tb4")], capsys)
    result = json.loads(out)
    assert code == 0 and result["robot"] == "turtlebot4", result["expectations"]
    refused = [
        "run",
        "assisted_teleop",
        "--robot",
        "turtlebot3_waffle",
        "--out",
        str(tmp_path / "w"),
    ]
    code, _, err = _run(refused, capsys)
    assert code == 2 and not (tmp_path / "w").exists()
    assert "assisted_teleop.yaml:" in err
    assert "fits only turtlebot3, turtlebot4 (robots:)" in err
    code, _, err = _run(
        ["validate", str(FOLDER / "cafe_delivery.yaml"), "--robot", "panda"], capsys
    )
    assert code == 2 and "cafe_delivery.yaml:" in err
    code, _, err = _run(["validate", str(FOLDER / "cafe_delivery.yaml"), "--robot", "tb9"], capsys)
    assert code == 2 and "unknown robot 'tb9'" in err


def test_a_campaign_varies_the_robot(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    argv = [
        "campaign",
        "walls_go_to_goal",
        "--runs",
        "4",
        "--vary",
        "robot=choice(turtlebot3,turtlebot4)",
        "--workers",
        "1",
        "--json",
        "--out",
        str(tmp_path / "campaign"),
    ]
    code, out, _ = _run(argv, capsys)
    summary = json.loads(out)
    assert code == 0 and summary["success_rate"] == 1.0, summary
    with sqlite3.connect(summary["results"]) as results:
        rows = results.execute("SELECT run, params FROM runs ORDER BY run").fetchall()
    robots = [json.loads(params)["robot"] for _, params in rows]
    assert set(robots) == {"turtlebot3", "turtlebot4"}, robots
    for (run, _), robot in zip(rows, robots, strict=True):
        variant = tmp_path / "campaign" / "replay" / f"run-{run:04d}.yaml"
        assert f"robot: {robot}" in variant.read_text(encoding="utf-8").splitlines()
    refused = [
        "campaign",
        "assisted_teleop",
        "--runs",
        "2",
        "--vary",
        "robot=choice(turtlebot3_waffle)",
    ]
    code, _, err = _run([*refused, "--out", str(tmp_path / "refused")], capsys)
    assert code == 2 and "fits turtlebot3, turtlebot4, not 'turtlebot3_waffle'" in err
