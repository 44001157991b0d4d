"""``baobab campaign``: seeded sweeps on local processes or a Dask cluster, results, replay.

The quick fixture mission (tests/missions/campaign/dash.yaml) drives go-to-goal to north_spot
(reached after about 6.6 s of sim time) or into wall_east on its way to goal_behind_wall (the
tree times out after 8 s: FAILED), so a grid over ``goal`` gives known failures.
"""

from __future__ import annotations

import contextlib
import fcntl
import io
import json
import math
import os
import shlex
import signal
import sqlite3
import subprocess
import sys
from pathlib import Path
from typing import Any

import jsonschema
import numpy as np
import pytest
import yaml

from baobab.missions.campaigns.dispatch import replay_target
from baobab.missions.campaigns.executors import execute_run
from baobab.missions.campaigns.results import (
    WALL_CLOCK_COLUMNS,
    CampaignSummary,
    read_rows,
    wilson_interval,
)
from baobab.missions.campaigns.spec import build_spec
from baobab.missions.campaigns.variant import load_run_mission, variant_of
from baobab.missions.campaigns.vary import CampaignError, variable_keys
from baobab.missions.cli.command_line import main
from baobab.missions.language.bundled_missions import resolve_mission
from baobab.missions.language.errors import MissionError
from baobab.missions.language.json_schema import mission_json_schema
from baobab.missions.language.loader import load_mission
from baobab.missions.language.models import SpawnObstacleEvent

DASH = Path(__file__).parent / "missions" / "campaign" / "dash.yaml"
CAMPAIGN = [
    "campaign",
    str(DASH),
    "--grid",
    "goal=north_spot,goal_behind_wall",
    "--runs",
    "4",
    "--vary",
    "start.x=uniform(-0.1,0.1)",
    "--vary",
    "noise.lidar_std=uniform(0,0.02)",
    "--seed",
    "11",
    "--json",
]
"""8 runs: 4 to north_spot (succeed), then 4 into the wall (fail)."""
BAOBAB = [
    sys.executable,
    "-c",
    "import sys; from baobab.missions.cli.command_line import main; sys.exit(main())",
]


def _campaign(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, dict[str, Any]]:
    code = main([*CAMPAIGN, *argv])
    return code, json.loads(capsys.readouterr().out)


def _comparable(rows: list[dict[str, Any]], folder: Path) -> list[dict[str, Any]]:
    """Rows without wall-clock columns, the campaign folder in replay commands neutral."""
    return [
        {
            key: value.replace(str(folder), "<campaign>") if key == "replay" else value
            for key, value in row.items()
            if key not in WALL_CLOCK_COLUMNS
        }
        for row in rows
    ]


@pytest.fixture(scope="module")
def local_campaign(
    tmp_path_factory: pytest.TempPathFactory,
) -> tuple[int, dict[str, Any], Path]:
    """The 8-run campaign on 2 local workers, run once per session even under xdist."""
    root = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        root = root.parent  # shared by this session's xdist workers
    folder = root / "campaign-local"
    with (root / "campaign-local.lock").open("w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (folder / "summary.json").exists():
            out = io.StringIO()
            capture = pytest.MonkeyPatch()
            capture.setattr(sys, "stdout", out)
            try:
                main([*CAMPAIGN, "--workers", "2", "--out", str(folder)])
            finally:
                capture.undo()
            assert json.loads(out.getvalue()) == json.loads((folder / "summary.json").read_text())
    summary = json.loads((folder / "summary.json").read_text())
    return summary["exit_code"], summary, folder


def test_wilson_interval_matches_published_values() -> None:
    # Newcombe (1998), Stat. Med. 17:857, Table I, method 3 (score interval, no correction).
    published = {
        (81, 263): (0.2553, 0.3662),
        (15, 148): (0.0624, 0.1605),
        (0, 20): (0.0, 0.1611),
        (1, 29): (0.0061, 0.1718),
        (29, 29): (0.8830, 1.0),
    }
    for (successes, trials), expected in published.items():
        assert wilson_interval(successes, trials) == pytest.approx(expected, abs=5e-5)
    assert wilson_interval(0, 0) == (0.0, 1.0)
    with pytest.raises(ValueError):
        wilson_interval(3, 2)


def test_plan_is_seeded_per_run_and_grids_combine_as_a_product() -> None:
    text = DASH.read_text()
    mission = load_mission(DASH, {}, text=text)
    vary = ["start.yaw=normal(0,0.1)", "start.x=grid(-0.1,0.1,3)"]
    grid = ["goal=north_spot,goal_behind_wall"]
    spec = build_spec(mission, DASH, text, {}, vary, grid, 2, 7)
    assert (spec.cells, spec.total_runs) == (6, 12)
    tasks = list(spec.tasks())
    # Cells in order, the last axis fastest, each repeated --runs times.
    cells = [(t.values["start.x"], t.values["goal"]) for t in tasks[::2]]
    assert cells == [
        (-0.1, "north_spot"),
        (-0.1, "goal_behind_wall"),
        (0.0, "north_spot"),
        (0.0, "goal_behind_wall"),
        (0.1, "north_spot"),
        (0.1, "goal_behind_wall"),
    ]
    assert [t.overrides for t in tasks[:2]] == [{"goal": "north_spot"}] * 2
    # Each run's seed is the first child of SeedSequence(campaign seed, spawn_key=(run,)).
    for task in tasks:
        child = np.random.SeedSequence(7, spawn_key=(task.index,)).spawn(2)[0]
        assert task.seed == int(child.generate_state(1, np.uint32)[0])
    assert len({t.seed for t in tasks}) == len(tasks)
    assert len({t.values["start.yaw"] for t in tasks}) == len(tasks)
    # Run i does not depend on how many runs there are, nor on a second planning.
    longer = build_spec(mission, DASH, text, {}, vary, grid, 3, 7)
    assert longer.task(0) == spec.task(0)
    again = build_spec(mission, DASH, text, {}, vary, grid, 2, 7)
    assert list(again.tasks()) == tasks
    other_seed = build_spec(mission, DASH, text, {}, vary, grid, 2, 8)
    assert other_seed.task(0).seed != tasks[0].seed
    with pytest.raises(CampaignError, match="give --runs"):
        build_spec(mission, DASH, text, {}, ["start.x=uniform(0,1)"], [], None, 0)


CRATE = """\
# yaml-language-server: $schema=mission.schema.json
mission: crate
world: walls
robot: turtlebot3
start: {x: 0.6, y: 0.0, yaw: 0.8}
params:
  goal: {type: str, default: goal_open}
tree:
  go_to_goal: ${goal}
events:
  - {at: 1.0, spawn_obstacle: {name: crate, x: -1.5, y: 0.5}}
  - {at: 2.0, move_obstacle: {name: crate, x: -1.5, y: 0.8}}
timeout: 5
"""


def _crate(tmp_path: Path) -> tuple[Path, str]:
    path = tmp_path / "crate.yaml"
    path.write_text(CRATE)
    return path, CRATE


def test_variations_of_start_noise_and_events_make_the_run_mission(tmp_path: Path) -> None:
    path, text = _crate(tmp_path)
    mission = load_mission(path, {}, text=text)
    keys = set(variable_keys(mission))
    assert keys == {
        "goal",
        "robot",
        "start.x",
        "start.y",
        "start.yaw",
        "noise.lidar_std",
        "events.0.at",
        "events.0.spawn_obstacle.x",
        "events.0.spawn_obstacle.y",
        "events.0.spawn_obstacle.yaw",
        "events.1.at",
        "events.1.move_obstacle.x",
        "events.1.move_obstacle.y",
        "events.1.move_obstacle.yaw",
    }
    vary = [
        "events.0.spawn_obstacle.x=uniform(-1.6,-1.4)",
        "noise.lidar_std=choice(0.01,0.02)",
        "start.yaw=normal(0,0.2)",
        "params.goal=choice(goal_open,goal_behind_north_wall)",
    ]
    spec = build_spec(mission, path, text, {}, vary, ["start.y=-0.1,0.1"], 2, 3)
    for task in spec.tasks():
        variant = variant_of(task)
        assert variant is not None and variant.startswith(text.splitlines()[0] + "\n")
        run = load_run_mission(task, variant)
        spawn = run.events[0]
        assert isinstance(spawn, SpawnObstacleEvent)
        assert spawn.spawn_obstacle.x == task.values["events.0.spawn_obstacle.x"]
        assert run.noise.lidar_std == task.values["noise.lidar_std"]
        assert run.start is not None
        assert (run.start.x, run.start.y) == pytest.approx((0.6, task.values["start.y"]))
        assert run.start.yaw == pytest.approx(0.8 + task.values["start.yaw"])
        assert run.params["goal"] == task.values["goal"] == task.overrides["goal"]
    unvaried = build_spec(mission, path, text, {"goal": "goal_open"}, [], [], 1, 0).task(0)
    assert variant_of(unvaried) is None
    assert load_run_mission(unvaried, None).params == {"goal": "goal_open"}


def test_start_pushed_into_a_wall_is_an_invalid_run_that_replays(tmp_path: Path) -> None:
    path, text = _crate(tmp_path)
    mission = load_mission(path, {}, text=text)
    # start.x + 0.6 puts the robot at (1.2, 0), inside wall_east.
    spec = build_spec(mission, path, text, {}, [], ["start.x=0.6"], 1, 0)
    task = spec.task(0)
    outcome = execute_run(task)
    row = outcome.row
    assert (row["result"], row["error_name"], row["intended"]) == (
        "INVALID",
        "INVALID_MISSION",
        False,
    )
    assert row["error_msg"].startswith("replay/run-0000.yaml:")
    assert "wall_east" in row["error_msg"]
    assert outcome.variant_text is not None
    folder = tmp_path / "campaign"
    target = replay_target(spec, str(path), folder)
    written = target.write_variant(task, outcome.variant_text)
    assert shlex.split(target.command(task, variant=True))[:3] == ["baobab", "run", str(written)]
    with pytest.raises(MissionError) as replayed:
        load_mission(written, task.overrides)
    assert replayed.value.message in row["error_msg"]


@pytest.mark.parametrize(
    "first_line",
    ["# yaml-language-server: $schema=../mission.schema.json\n", "# Licence: MIT\n", ""],
    ids=["schema elsewhere", "licence comment", "no comment"],
)
def test_a_replay_file_names_a_schema_that_exists_beside_it(
    tmp_path: Path, first_line: str
) -> None:
    text = first_line + CRATE.split("\n", 1)[1]
    path = tmp_path / "missions" / "crate.yaml"
    path.parent.mkdir()
    path.write_text(text)
    spec = build_spec(load_mission(path), path, text, {}, [], ["start.y=-0.1,0.1"], 1, 0)
    target = replay_target(spec, str(path), tmp_path / "campaign")
    for task in spec.tasks():
        variant = variant_of(task)
        assert variant is not None
        written = target.write_variant(task, variant)
        comment = written.read_text().splitlines()[0]
        assert comment.startswith("# yaml-language-server: $schema=")
        schema = json.loads((written.parent / comment.split("=", 1)[1]).read_text())
        assert schema == json.loads(json.dumps(mission_json_schema()))
        jsonschema.validate(yaml.safe_load(written.read_text()), schema)
        assert load_mission(written).start is not None


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--vary", "start.x"], "expected KEY=VALUE"),
        (["--vary", "start.x=uniform(1)"], "uniform(a,b) takes 2 numbers, got 1"),
        (["--vary", "start.x=unifrom(0,1)"], "did you mean 'uniform'?"),
        (["--vary", "start.x=uniform(1,0)"], "needs a < b"),
        (["--vary", "start.x=normal(0,abc)"], "'abc' is not a number"),
        (["--vary", "start.x=grid(0,1,2.5)"], "whole number >= 2"),
        (["--vary", "start.xx=uniform(0,1)"], "unknown key 'start.xx'; did you mean 'start.x'?"),
        (["--vary", "gaol=choice(goal_open)"], "unknown key 'gaol'; did you mean 'goal'?"),
        (["--vary", "goal=uniform(0,1)"], "'goal' is a str parameter"),
        (["--vary", "goal=choice(goal_open,kitchen)"], "not one of the choices"),
        (["--vary", "events.0.at=uniform(0,1)"], "unknown key 'events.0.at'"),
        (["--grid", "goal=north_spot,north_spot"], "listed twice"),
        (["--grid", "start.x=0,wide"], "expected a finite number"),
        (["--vary", "goal=choice(north_spot)", "--set", "goal=north_spot"], "both set"),
        (
            ["--vary", "start.x=uniform(0,1)", "--workers", "2", "--scheduler", "tcp://h:1"],
            "not both",
        ),
        (["--vary", "start.x=uniform(0,1)"], "give --runs"),
    ],
)
def test_bad_variations_exit_2_with_one_line(
    argv: list[str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    runs = [] if "give --runs" in message else ["--runs", "2"]
    code = main(["campaign", str(DASH), *runs, *argv, "--out", str(tmp_path / "c")])
    captured = capsys.readouterr()
    assert code == 2
    assert captured.out == ""
    assert captured.err.startswith("baobab campaign: ")
    assert captured.err.count("\n") == 1
    assert message in captured.err
    assert not (tmp_path / "c").exists()


def test_scheduler_without_dask_is_one_line_with_the_pip_command(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed -> ImportError
    argv = ["campaign", str(DASH), "--runs", "2", "--scheduler", "tcp://127.0.0.1:1"]
    code = main([*argv, "--out", str(tmp_path / "c")])
    err = capsys.readouterr().err
    assert code == 2
    assert err == (
        "baobab campaign: --scheduler needs dask.distributed, which is not installed: "
        'pip install "baobab[campaign]"\n'
    )
    assert not (tmp_path / "c").exists()


def test_campaign_summary_rows_and_plot(local_campaign: tuple[int, dict[str, Any], Path]) -> None:
    code, summary, folder = local_campaign
    rows = read_rows(folder / "results.sqlite")
    assert code == 1  # some runs failed
    assert [row["run"] for row in rows] == list(range(8))
    assert [row["result"] for row in rows] == ["SUCCEEDED"] * 4 + ["FAILED"] * 4
    assert [row["intended"] for row in rows] == [True] * 4 + [False] * 4
    assert {row["error_name"] for row in rows[4:]} == {"TREE_FAILED"}
    assert all(row["params"]["goal"] == "goal_behind_wall" for row in rows[4:])
    assert all(-0.1 <= row["params"]["start.x"] < 0.1 for row in rows)
    assert all(len(row["trace_digest"]) == 64 for row in rows)
    assert all(row["expectations_passed"] == 3 for row in rows[:4])
    assert all(row["metrics"]["path_length"] == row["path_length"] for row in rows)
    assert summary["runs"] == summary["planned"] == 8
    assert summary["success_rate"] == 0.5
    assert summary["success_ci95"] == pytest.approx(wilson_interval(4, 8), abs=1e-6)
    assert summary["interrupted"] is False
    sim_times = [row["sim_time"] for row in rows]
    assert summary["sim_time"]["p50"] == pytest.approx(float(np.percentile(sim_times, 50)))
    assert summary["sim_time"]["p95"] == pytest.approx(8.0, abs=0.01)
    assert summary["results"] == str(folder / "results.sqlite")
    assert summary["failure_groups"] == [
        {"group": "9900 TREE_FAILED", "count": 4, "runs": [4, 5, 6, 7]}
    ]
    assert [f["run"] for f in summary["failures"]] == [4, 5, 6, 7]
    assert all(f["replay"].startswith("baobab run ") for f in summary["failures"])
    assert (folder / "outcomes.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in (folder / "replay").iterdir()) == [
        "mission.schema.json",  # what the replay files' editor comment names
        *(f"run-{i:04d}.yaml" for i in range(8)),
    ]
    summarised = CampaignSummary("campaign_dash", 8, rows).as_json()
    assert summarised["failures"] == summary["failures"]


def test_failing_run_replays_exactly(
    local_campaign: tuple[int, dict[str, Any], Path],
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    _, summary, folder = local_campaign
    failure = summary["failures"][1]
    row = read_rows(folder / "results.sqlite")[failure["run"]]
    words = shlex.split(failure["replay"])
    assert words[:3] == ["baobab", "run", str(folder / "replay" / "run-0005.yaml")]
    assert words[3:] == ["--seed", str(row["seed"]), "--set", "goal=goal_behind_wall"]
    code = main([*words[1:], "--json", "--out", str(tmp_path / "replayed")])
    replayed = json.loads(capsys.readouterr().out)
    assert code == 1
    assert replayed["result"] == row["result"] == "FAILED"
    assert replayed["error_code"] == row["error_code"]
    assert replayed["trace_digest"] == row["trace_digest"]
    assert replayed["sim_time"] == row["sim_time"]


def test_dask_cluster_gives_the_same_rows_as_local_workers(
    local_campaign: tuple[int, dict[str, Any], Path],
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    from distributed import LocalCluster

    _, local_summary, local_folder = local_campaign
    folder = tmp_path / "dask"
    with LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=":0",
    ) as cluster:
        code, summary = _campaign(
            capsys, "--scheduler", cluster.scheduler_address, "--out", str(folder)
        )
    assert code == 1
    assert summary["executor"].startswith("Dask cluster at tcp://127.0.0.1:")
    local_rows = _comparable(read_rows(local_folder / "results.sqlite"), local_folder)
    dask_rows = _comparable(read_rows(folder / "results.sqlite"), folder)
    assert len(dask_rows) == 8
    assert dask_rows == local_rows
    for name in ("runs", "success_rate", "success_ci95", "sim_time", "path_length"):
        assert summary[name] == local_summary[name]


def _row_count(results: Path) -> int:
    if not results.exists():
        return 0
    try:
        with contextlib.closing(sqlite3.connect(f"file:{results}?mode=ro", uri=True)) as db:
            return int(db.execute("SELECT COUNT(*) FROM runs").fetchone()[0])
    except sqlite3.OperationalError:  # not created yet, or being created
        return 0


def test_sigint_stops_dispatch_keeps_finished_rows_and_exits_130(tmp_path: Path) -> None:
    folder = tmp_path / "interrupted"
    argv = ["campaign", str(DASH), "--runs", "40", "--set", "goal=north_spot"]
    process = subprocess.Popen(
        [*BAOBAB, *argv, "--workers", "2", "--json", "--out", str(folder)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    results = folder / "results.sqlite"
    try:
        for _ in range(3000):  # bounded: at most 3000 polls of 0.1 s
            if _row_count(results) > 0:
                break
            try:
                process.wait(timeout=0.1)
            except subprocess.TimeoutExpired:
                continue
            break
        assert process.poll() is None, "the campaign ended before it could be interrupted"
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=300)
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    assert process.returncode == 130, err
    summary = json.loads(out)
    rows = read_rows(results)
    assert 1 <= len(rows) < 40
    # Runs are dispatched in order and those in flight at the SIGINT finish: no gaps.
    assert [row["run"] for row in rows] == list(range(len(rows)))
    assert all(row["result"] == "SUCCEEDED" for row in rows)
    # Only --set values vary: the replay command names the mission file itself.
    assert rows[0]["replay"] == shlex.join(
        ["baobab", "run", str(DASH), "--seed", str(rows[0]["seed"]), "--set", "goal=north_spot"]
    )
    assert not (folder / "replay").exists()
    assert summary["interrupted"] is True
    assert (summary["runs"], summary["planned"]) == (len(rows), 40)
    assert summary["success_rate"] == 1.0
    low, high = summary["success_ci95"]
    assert math.isclose(high, 1.0) and low == pytest.approx(
        wilson_interval(len(rows), len(rows))[0]
    )
    assert "Traceback" not in err


def test_the_forkserver_loads_numbas_compiler_once_for_every_worker(tmp_path: Path) -> None:
    # Each local run is a process forked from the forkserver: what the forkserver imported
    # (the preload list) every run starts with, numba's registries and the dispatcher too.
    from baobab.missions.campaigns.executors import preload_modules

    mission = load_mission(resolve_mission("walls_go_to_goal"))
    modules = preload_modules(mission)
    script = (
        "import importlib, json, sys\n"
        f"for name in {modules!r}:\n"
        "    importlib.import_module(name)\n"
        "from baobab.sim import native_control\n"
        "print(json.dumps([native_control._installed_callback.cache_info().currsize,\n"
        "                  'numba.np.arraymath' in sys.modules]))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, check=True
    )
    assert json.loads(done.stdout) == [1, True]
