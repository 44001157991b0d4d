"""Keepout and speed zones in runs: the metrics, the expectations, the recording and the plot,
and the bundled office_patrol mission over a map with both masks."""

from __future__ import annotations

import json
import math
import runpy
import shutil
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from map_files import image_cells, room_pixels, write_map
from matplotlib.figure import Figure
from test_run_recording import read_mcap

from baobab.missions.cli.command_line import main
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.missions.run.expectations import RunEnd, evaluate
from baobab.missions.run.plot_data import MobilePlot
from baobab.missions.run.plotting import _mobile
from baobab.missions.run.runner import run_mission
from baobab.missions.run.zone_probe import ZoneProbe
from baobab.robots.turtlebot3 import BURGER, build_turtlebot3_sim
from baobab.sim.map_geometry import signed_distance_to_cells
from baobab.sim.world import Pose2D, World, load_world

ROOM = (120, 60)
"""A 6 m x 3 m room on a map (0.05 m cells)."""
KEEPOUT = (3.0, 1.2, 4.0, 1.8)
"""The keepout zone (m): a 1 m x 0.6 m block on the room's centre line."""
SLOW = (1.5, 0.0, 2.5, 3.0)
"""The slow zone (m): a band across the room, 50 % of the top speed."""
OFFICE = Path(str(resources.files("baobab.missions"))) / "office_patrol.yaml"


def _room(folder: Path) -> Path:
    """The room map and its masks in ``folder``; returns the world file standing on them."""
    write_map(folder, room_pixels(*ROOM), name="room")
    keepout = np.full((ROOM[1], ROOM[0]), 254, dtype=np.uint8)
    keepout[image_cells(KEEPOUT, ROOM[1])] = 0
    write_map(folder, keepout, name="keepout")
    speed = np.full((ROOM[1], ROOM[0]), 255, dtype=np.uint8)
    speed[image_cells(SLOW, ROOM[1])] = 128  # scale mode: 50 % taken off
    write_map(folder, speed, name="speed", mode="scale", occupied_thresh=1.0, free_thresh=0.0)
    path = folder / "world.yaml"
    path.write_text(
        "name: room\nmap: ./room.yaml\nfilters: {keepout: ./keepout.yaml, speed: ./speed.yaml}\n"
    )
    return path


def _drive(world: World, start: Pose2D, speed: float, seconds: float) -> tuple[ZoneProbe, list]:
    """Drive straight at ``speed`` (m/s, base commands, no navigation); the probe and the
    (x, y, forward speed) it sampled, read beside it at the same times."""
    sim, robot = build_turtlebot3_sim(world, start)
    probe = ZoneProbe(sim, robot.base, world, BURGER.footprint_radius, 0.22)
    seen: list[tuple[float, float, float]] = []

    def look(_now: float) -> None:
        pose = robot.base.pose()
        seen.append((pose.x, pose.y, robot.base.body_velocity()[0]))

    sim.every(0.05, look, name="test samples")
    robot.base.command(speed, 0.0)
    sim.step_for(seconds)
    return probe, seen


def test_keepout_clearance_is_the_least_exact_distance_of_the_samples(tmp_path: Path) -> None:
    world = load_world(_room(tmp_path))
    zone = world.masks.keepout
    assert zone is not None
    cells = zone.data == 100

    def exact(samples: list) -> float:
        return min(signed_distance_to_cells(cells, zone.origin, 0.05, x, y) for x, y, _ in samples)

    passing, seen = _drive(world, Pose2D(x=0.6, y=1.0), 0.2, 20.0)  # 0.2 m south of the zone
    clearance = passing.keepout_clearance()
    assert clearance == pytest.approx(exact(seen) - BURGER.footprint_radius, abs=1e-12)
    assert 0.05 < clearance < 0.1
    into, seen = _drive(world, Pose2D(x=0.6, y=1.5), 0.2, 15.0)  # along the zone's centre line
    assert into.keepout_clearance() == pytest.approx(exact(seen) - BURGER.footprint_radius)
    deepest = -0.3 - BURGER.footprint_radius  # the zone's centre line is 0.3 m inside
    assert into.keepout_clearance() == pytest.approx(deepest, abs=1e-9)


def test_speed_excess_counts_where_the_whole_footprint_is_under_a_limit(tmp_path: Path) -> None:
    world = load_world(_room(tmp_path))
    fast, seen = _drive(world, Pose2D(x=0.6, y=0.8), 0.2, 12.0)
    inside = [v for x, _, v in seen if SLOW[0] + 0.2 < x < SLOW[2] - 0.2]
    assert inside and fast.speed_limit_excess() == pytest.approx(max(inside) - 0.11, abs=0.002)
    slow, _ = _drive(world, Pose2D(x=0.6, y=0.8), 0.1, 25.0)
    assert slow.speed_limit_excess() == 0.0
    assert slow.samples_under_limit > 100


def _filter_mission(folder: Path, expect: str, tree: str = "wait: 0.1") -> Path:
    world = _room(folder)
    path = folder / "m.yaml"
    path.write_text(
        f"mission: zones\nworld: ./{world.name}\nrobot: turtlebot3\n"
        f"start: {{x: 0.6, y: 1.5}}\ntree: {{{tree}}}\nexpect:\n{expect}"
    )
    return path


def test_the_zone_expectations_judge_the_zone_metrics(tmp_path: Path) -> None:
    mission = load_mission(
        _filter_mission(tmp_path, "  no_keepout_entry: true\n  within_speed_limits: true\n")
    )
    end = RunEnd("SUCCEEDED", 0, "NONE", 10.0)

    def judge(**metrics: Any) -> list[bool]:
        return [r.passed for r in evaluate(mission.expect, end, metrics, mission)]

    assert judge(min_keepout_clearance=0.2, speed_limit_excess=0.004) == [True, True]
    assert judge(min_keepout_clearance=-0.01, speed_limit_excess=0.02) == [False, False]
    entered = evaluate(mission.expect, end, {"min_keepout_clearance": -0.03}, mission)[0]
    assert entered.detail == "the footprint reached 0.030 m into a keepout zone"


@pytest.mark.parametrize(
    ("expect", "message"),
    [
        ("  no_keepout_entry: true\n", "expectation 'no_keepout_entry' needs a keepout filter"),
        ("  metrics: {speed_limit_excess: {max: 0.0}}\n", "metric 'speed_limit_excess' needs"),
    ],
)
def test_zone_expectations_need_the_mask(tmp_path: Path, expect: str, message: str) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(
        f"mission: zones\nworld: walls\nrobot: turtlebot3\ntree: {{wait: 0.1}}\nexpect:\n{expect}"
    )
    with pytest.raises(MissionError, match=message) as caught:
        load_mission(path)
    assert caught.value.line == 6


def test_a_run_on_a_map_records_the_map_the_masks_and_the_speed_limits(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    tree = "navigate_to_pose: {goal: {x: 5.2, y: 1.0}}"
    path = _filter_mission(tmp_path, "  result: SUCCEEDED\n  no_keepout_entry: true\n", tree)
    mcap = tmp_path / "run.mcap"
    code = main(["run", str(path), "--out", str(tmp_path / "out"), "--record", str(mcap)])
    capsys.readouterr()
    assert code == 0
    schemas, messages = read_mcap(mcap)
    world = load_world(tmp_path / "world.yaml")
    for topic, grid in (
        ("/map", world.grid),
        ("/keepout_filter_mask", world.masks.keepout),
        ("/speed_filter_mask", world.masks.speed),
    ):
        assert grid is not None
        assert schemas[topic] == "foxglove.Grid"
        _, message = messages[topic][0]
        values = np.frombuffer(message.data, dtype=np.int8).reshape(grid.data.shape)
        assert np.array_equal(values, grid.data)
        assert message.fields[0].name == "occupancy"
        assert (message.pose.position.x, message.cell_size.x) == (0.0, 0.05)
    limits = [json.loads(m) if isinstance(m, bytes) else m for _, m in messages["/speed_limit"]]
    assert {"percentage": True, "speed_limit": 50.0} in limits
    assert limits[-1] == {"percentage": True, "speed_limit": 0.0}  # out of the zone: no limit


def test_the_plot_draws_the_map_image_and_the_zones(tmp_path: Path) -> None:
    tree = "navigate_to_pose: {goal: {x: 5.2, y: 1.0}}"
    record = run_mission(load_mission(_filter_mission(tmp_path, "  result: SUCCEEDED\n", tree)))
    plot = record.plot
    assert isinstance(plot, MobilePlot)
    keepout, slow = plot.zones
    assert keepout.label == "keepout zone" and keepout.cells[30, 70]
    assert slow.label == "speed limit 0.11 m/s" and slow.cells.sum() == 20 * ROOM[1]
    axes = Figure().add_subplot()
    _mobile(axes, plot)
    shaded = [image for image in axes.images if image.get_extent() == [0.0, 6.0, 0.0, 3.0]]
    map_image = np.asarray(shaded[0].get_array())
    assert map_image[0, 10] == 0.0 and map_image[10, 10] == 1.0  # a wall black, floor white
    labels = {patch.get_label() for patch in axes.patches}
    assert {"keepout zone", "speed limit 0.11 m/s"} <= labels


def _poses(lines: list[str]) -> list[dict[str, Any]]:
    """The trace's pose records (10 Hz): x, y (m), forward speed v (m/s)."""
    return [record for record in map(json.loads, lines) if record["type"] == "pose"]


def test_office_patrol_slows_in_the_corridor_and_keeps_out_of_the_zone() -> None:
    record = run_mission(load_mission(OFFICE))
    result = record.result_object()
    assert record.exit_code == 0, result["expectations"]
    judged = {e["name"]: e for e in result["expectations"]}
    assert judged["no_keepout_entry"]["passed"] and judged["within_speed_limits"]["passed"]
    metrics = result["metrics"]
    assert metrics["min_keepout_clearance"] > 0.1
    states = _poses(record.trace.lines)
    # 0.3 m inside the slow zone (4.25..11.75 x 5.0..6.5 m): the limit holds there.
    corridor = [s["v"] for s in states if 4.55 < s["x"] < 11.45 and 5.3 < s["y"] < 6.2]
    assert len(corridor) > 50  # the patrol drives through the slow zone ...
    assert 0.09 < max(corridor) <= 0.11 + 0.01  # ... at its limit, 50 % of 0.22 m/s
    assert max(s["v"] for s in states) > 0.2


def test_office_patrol_would_cross_the_keepout_zone_without_its_mask(tmp_path: Path) -> None:
    shutil.copytree(OFFICE.parent / "office", tmp_path / "office")
    text = OFFICE.read_text().replace("  keepout: ./office/keepout.yaml\n", "")
    text = text.replace("  no_keepout_entry: true\n", "")
    (tmp_path / "office_patrol.yaml").write_text(text)
    without = load_mission(tmp_path / "office_patrol.yaml")
    assert without.world is not None and without.world.masks.keepout is None
    from baobab.nav.server import build_navigation

    sim, robot = build_turtlebot3_sim(without.world, without.locations["kitchen"].pose2d())
    server = build_navigation(sim, robot.base, robot.lidar, without.world)
    path = server.compute_path(None, without.locations["printer"].pose2d())
    x0, y0, x1, y1 = 8.6, 0.65, 11.0, 3.8  # draw_office.KEEPOUT_ZONE
    assert any(x0 < x < x1 and y0 < y < y1 for x, y in path.xy)
    assert math.hypot(*np.subtract(path.xy[-1], (4.8, 3.2))) < 0.05


def test_the_office_map_files_are_what_its_script_draws(tmp_path: Path) -> None:
    folder = OFFICE.parent / "office"
    script = runpy.run_path(str(folder / "draw_office.py"))
    script["main"](tmp_path)
    drawn = sorted(path.name for path in tmp_path.iterdir())
    assert drawn == sorted(p.name for p in folder.iterdir() if p.suffix in (".pgm", ".yaml"))
    for name in drawn:
        assert (tmp_path / name).read_bytes() == (folder / name).read_bytes(), name
