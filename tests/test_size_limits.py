"""Sizes have stated limits, checked by ``validate`` before anything is allocated or expanded.

Worlds: floor sides, coordinates, costmap cells, obstacles and named poses; missions: events
and the expanded tree; campaigns: runs, with a grid axis checked before its values are made.
Each refusal names its limit (``MAX_...``, listed in the README); the values just inside each
limit are accepted.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from baobab.missions.campaigns import vary as campaign_vary
from baobab.missions.campaigns.spec import MAX_RUNS
from baobab.missions.cli.command_line import main
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.missions.language.models import MAX_EVENTS
from baobab.missions.language.tree_parser import MAX_TREE_NODES
from baobab.nav import BasicNavigator
from baobab.nav.layers import CostmapSizeError, StaticLayer
from baobab.sim.errors import WorldError
from baobab.sim.world import (
    COSTMAP_CELL_SIZE,
    MAX_COSTMAP_CELLS,
    MAX_NAMED_POSES,
    MAX_OBSTACLES,
    World,
    load_world,
)

HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
DASH = Path(__file__).parent / "missions" / "campaign" / "dash.yaml"


def _world_file(tmp_path: Path, floor: str, boxes: int = 0, locations: int = 0) -> Path:
    lines = ["name: big", f"floor: {floor}", "boxes:" if boxes else "boxes: []"]
    lines += [
        f"  - {{name: b{i}, center: [{-1.9 + 0.01 * (i % 300):.2f}, {1.0 + 0.003 * (i // 300)}],"
        " size: [0.005, 0.002]}"
        for i in range(boxes)
    ]
    lines += ["spawns:", "  default: {x: 0, y: 0}"]
    lines += ["locations:" if locations else "locations: {}"]
    lines += [f"  l{i}: {{x: 0.5, y: 0.5}}" for i in range(locations)]
    path = tmp_path / "w.yaml"
    path.write_text("\n".join(lines) + "\n")
    return path


def _refusal(path: Path) -> WorldError:
    with pytest.raises(WorldError) as raised:
        load_world(path)
    return raised.value


def test_a_floor_at_the_cell_limit_loads_and_one_over_it_is_refused(tmp_path: Path) -> None:
    side = COSTMAP_CELL_SIZE * 3162  # 3162 x 3162 cells: just under 10 million
    assert load_world(_world_file(tmp_path, f"{{size: [{side:.2f}, {side:.2f}]}}")).floor
    over = COSTMAP_CELL_SIZE * 3163
    error = _refusal(_world_file(tmp_path, f"{{size: [{over:.2f}, {over:.2f}]}}"))
    assert (error.line, error.column) == (2, 9)
    assert error.message == (
        "floor.size: the floor is 158.15 m x 158.15 m: 10,004,569 cells of the navigation "
        f"costmap at 0.05 m; the limit is {MAX_COSTMAP_CELLS:,} cells (MAX_COSTMAP_CELLS)"
    )


def test_a_long_thin_floor_is_within_the_limits(tmp_path: Path) -> None:
    assert load_world(_world_file(tmp_path, "{size: [1000, 10]}")).bounds == (-500, -5, 500, 5)


def test_obstacles_and_named_poses_have_limits(tmp_path: Path) -> None:
    floor = "{size: [4, 4]}"
    assert len(load_world(_world_file(tmp_path, floor, boxes=MAX_OBSTACLES)).boxes) == 1000
    error = _refusal(_world_file(tmp_path, floor, boxes=MAX_OBSTACLES + 1))
    assert (error.line, error.message) == (
        3,
        "boxes: 1001 obstacles (boxes and cylinders); the limit is 1000 (MAX_OBSTACLES)",
    )
    assert len(load_world(_world_file(tmp_path, floor, locations=MAX_NAMED_POSES - 1)).locations)
    error = _refusal(_world_file(tmp_path, floor, locations=MAX_NAMED_POSES))
    assert error.message == (
        "locations: 1001 spawns and locations; the limit is 1000 (MAX_NAMED_POSES)"
    )


def test_a_10_km_world_is_refused_before_a_navigator_allocates_a_costmap(tmp_path: Path) -> None:
    path = _world_file(tmp_path, "{size: [10000, 10000]}")
    with pytest.raises(WorldError, match="the limit is 1000 m a side"):
        BasicNavigator(world=str(path))


def test_the_costmap_refuses_a_finer_resolution_than_the_world_was_checked_at() -> None:
    world = World.model_validate(
        {"name": "w", "floor": {"size": [100, 100]}, "spawns": {"default": {"x": 0, "y": 0}}}
    )
    assert StaticLayer(world, COSTMAP_CELL_SIZE).size_x == 2002
    with pytest.raises(CostmapSizeError, match=r"100,000,000 cells; the limit is 10,000,000"):
        StaticLayer(world, 0.01)


def test_more_events_than_the_limit_are_refused_at_the_first_one_over(tmp_path: Path) -> None:
    events = "".join(f"  - {{at: {i}, cancel: true}}\n" for i in range(MAX_EVENTS + 1))
    body = "mission: m\nworld: walls\nrobot: turtlebot3\ntree: {wait: 1}\ntimeout: 2000\n"
    path = tmp_path / "m.yaml"
    path.write_text(HEADER + body + "events:\n" + events)
    with pytest.raises(MissionError) as raised:
        load_mission(path)
    assert (raised.value.line, raised.value.message) == (
        8 + MAX_EVENTS,
        f"{MAX_EVENTS + 1} events; the limit is {MAX_EVENTS} (MAX_EVENTS)",
    )
    path.write_text(HEADER + body + "events:\n" + events.rsplit("  - ", 1)[0])
    assert len(load_mission(path).events) == MAX_EVENTS


def test_subtrees_that_multiply_past_the_tree_limit_are_refused(tmp_path: Path) -> None:
    # Thirty levels of three calls each would expand to 3**30 nodes.
    lines = [HEADER + "mission: m\nworld: walls\nrobot: turtlebot3\ntree: {subtree: {name: s0}}"]
    lines.append("subtrees:")
    for level in range(30):
        call = f"{{subtree: {{name: s{level + 1}}}}}" if level < 29 else "{wait: 1}"
        lines.append(f"  s{level}: {{tree: {{sequence: [{call}, {call}, {call}]}}}}")
    path = tmp_path / "m.yaml"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(MissionError) as raised:
        load_mission(path)
    assert raised.value.message == (
        f"the expanded tree has more than {MAX_TREE_NODES} nodes (MAX_TREE_NODES)"
    )


@pytest.fixture
def linspace_sizes(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The sizes of the grids campaign_vary makes (np.linspace's ``num``)."""
    sizes: list[int] = []
    linspace = np.linspace

    def recording_linspace(low: float, high: float, num: int) -> np.ndarray:
        sizes.append(int(num))
        return linspace(low, high, num)

    monkeypatch.setattr(campaign_vary.np, "linspace", recording_linspace)
    return sizes


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (
            ["--vary", "start.x=grid(0,0.1,100000000)"],
            "--vary start.x=grid(0,0.1,100000000): 100000000 grid values; at most 100000 fit "
            "in one campaign with the other grid axes and --runs (MAX_RUNS)",
        ),
        (
            [
                "--runs",
                "10",
                "--vary",
                "start.x=grid(0,0.1,1000)",
                "--vary",
                "start.y=grid(0,0.1,20)",
            ],
            "--vary start.y=grid(0,0.1,20): 20 grid values; at most 10 fit",
        ),
        (
            ["--runs", "1000", "--grid", "start.yaw=" + ",".join(str(i) for i in range(101))],
            "101 grid values; at most 100 fit",
        ),
        (["--runs", str(MAX_RUNS + 1)], f"--runs {MAX_RUNS + 1}: at most {MAX_RUNS} runs"),
    ],
)
def test_campaign_grids_are_counted_before_they_are_made(
    argv: list[str],
    message: str,
    linspace_sizes: list[int],
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    code = main(["campaign", str(DASH), *argv, "--out", str(tmp_path / "c")])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and message in err, err
    assert all(size <= MAX_RUNS for size in linspace_sizes), linspace_sizes
    assert not (tmp_path / "c").exists()
