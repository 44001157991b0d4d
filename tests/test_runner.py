"""``baobab run`` end to end on real physics: results, run folders, digests, events, exits."""

from __future__ import annotations

import json
import math
import os
import queue
import signal
import subprocess
import sys
import threading
from pathlib import Path
from typing import Any

import pytest

from baobab.missions.cli.command_line import main
from baobab.missions.language.loader import load_mission
from baobab.missions.run.events import TimedEvents
from baobab.missions.run.rig import MobileRig
from baobab.missions.run.run_folder import PLOT_FILE, RESULT_FILE, TRACE_FILE
from baobab.missions.run.runner import run_mission

BAOBAB = str(Path(sys.executable).parent / "baobab")
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
RESULT_KEYS = {
    "mission", "result", "error_code", "error_msg", "sim_time", "wall_time", "metrics",
    "expectations", "trace_digest",
}  # fmt: skip


def _mission(tmp_path: Path, body: str, name: str = "m.yaml") -> Path:
    path = tmp_path / name
    path.write_text(HEADER + body, encoding="utf-8")
    return path


def _cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _json_run(
    capsys: pytest.CaptureFixture[str], mission: str | Path, out: Path, *extra: str
) -> tuple[int, dict[str, Any], str]:
    code, stdout, stderr = _cli(capsys, "run", str(mission), "--json", "--out", str(out), *extra)
    return code, json.loads(stdout), stderr


def _expectation(result: dict[str, Any], name: str) -> dict[str, Any]:
    return next(e for e in result["expectations"] if e["name"] == name)


def _assert_complete_folder(folder: Path) -> None:
    assert sorted(p.name for p in folder.iterdir()) == sorted([RESULT_FILE, TRACE_FILE, PLOT_FILE])
    assert (folder / PLOT_FILE).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    leftovers = [p.name for p in folder.parent.iterdir() if p.name.startswith(".")]
    assert leftovers == []


WALK = """
mission: walk
world: walls
robot: turtlebot3
seed: 4
tree:
  go_to_goal: goal_open
timeout: 60
"""


# --- the bundled missions -------------------------------------------------------------------


@pytest.mark.parametrize("name", ["walls_go_to_goal", "walls_bug2"])
def test_bundled_walls_missions_succeed_as_expected(
    name: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    code, result, _ = _json_run(capsys, name, out)
    assert code == 0
    assert set(result) >= RESULT_KEYS
    assert (result["mission"], result["result"], result["error_code"]) == (name, "SUCCEEDED", 0)
    assert result["expectations"] and all(e["passed"] for e in result["expectations"])
    assert result["metrics"]["contacts"] == 0
    assert result["metrics"]["min_clearance"] > 0.05
    assert json.loads((out / RESULT_FILE).read_text()) == result
    trace = [json.loads(line) for line in (out / TRACE_FILE).read_text().splitlines()]
    assert trace[0]["type"] == "start" and trace[-1]["type"] == "end"
    assert all("t" in record for record in trace)
    poses = [record["t"] for record in trace if record["type"] == "pose"]
    assert poses[:3] == [0.0, 0.1, 0.2]
    _assert_complete_folder(out)


def test_walls_go_to_goal_stops_within_five_centimetres(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, result, _ = _json_run(capsys, "walls_go_to_goal", tmp_path / "run")
    final = result["metrics"]["final_pose"]
    assert code == 0
    assert math.hypot(final["x"] - 2.0, final["y"] - 2.0) < 0.05
    assert _expectation(result, "final_pose_near")["measured"] < 0.05
    assert result["metrics"]["visited"] == ["goal_open"]
    assert 2.8 < result["metrics"]["path_length"] < 3.0


def test_subprocess_json_is_the_only_stdout_and_digests_agree(tmp_path: Path) -> None:
    mission = load_mission(Path(__file__).parents[1] / "missions" / "walls_go_to_goal.yaml")
    in_process = run_mission(mission).trace_digest
    again = run_mission(mission).trace_digest
    assert in_process == again
    processes = [
        subprocess.Popen(
            [BAOBAB, "run", "walls_go_to_goal", "--json", "--out", str(tmp_path / f"run{i}")],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for i in range(2)
    ]
    digests = []
    for process in processes:
        stdout, stderr = process.communicate(timeout=300)
        assert process.returncode == 0, stderr
        assert stdout.count("\n") == 1 and stdout.endswith("}\n")
        result = json.loads(stdout)
        assert set(result) >= RESULT_KEYS
        assert result["result"] == "SUCCEEDED"
        assert "go_to_goal goal_open" in stderr  # progress went to stderr
        digests.append(result["trace_digest"])
    assert digests == [in_process, in_process]


# --- events, timeouts, expectations -----------------------------------------------------------


def test_a_cancel_event_cancels_the_running_goal(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    events = "events:\n  - {at: 5.0, cancel: true}\n"
    expected = _mission(tmp_path, WALK + events + "expect:\n  result: CANCELED\n", "a.yaml")
    code, result, _ = _json_run(capsys, expected, tmp_path / "a")
    assert code == 0
    assert (result["result"], result["error_code"]) == ("CANCELED", 0)
    assert result["sim_time"] == 5.0
    assert "cancel event at 5 s" in result["error_msg"]
    outcomes = [
        json.loads(line)
        for line in (tmp_path / "a" / TRACE_FILE).read_text().splitlines()
        if '"type":"outcome"' in line
    ]
    assert [(o["node"], o["status"], o["t"]) for o in outcomes] == [
        ("go_to_goal goal_open", "CANCELED", 5.0)
    ]
    without_expect = _mission(tmp_path, WALK + events, "b.yaml")
    assert _json_run(capsys, without_expect, tmp_path / "b")[0] == 1
    wrong = _mission(tmp_path, WALK + events + "expect:\n  result: SUCCEEDED\n", "c.yaml")
    code, result, _ = _json_run(capsys, wrong, tmp_path / "c")
    assert code == 1
    assert _expectation(result, "result") == {
        "name": "result",
        "expected": "SUCCEEDED",
        "measured": "CANCELED",
        "passed": False,
        "detail": "ended CANCELED",
    }


def test_an_impossible_expectation_exits_1_and_says_why(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    expect = "expect:\n  max_sim_time: 5\n  metrics:\n    path_length: {max: 1.0}\n"
    path = _mission(tmp_path, WALK + expect)
    code, result, _ = _json_run(capsys, path, tmp_path / "run")
    assert code == 1
    assert result["result"] == "SUCCEEDED"
    too_slow = _expectation(result, "max_sim_time")
    assert (too_slow["expected"], too_slow["passed"]) == (5.0, False)
    assert too_slow["measured"] > 10.0
    too_long = _expectation(result, "metrics.path_length")
    assert too_long["expected"] == {"max": 1.0} and not too_long["passed"]
    assert too_long["measured"] > 2.5
    code, out, _ = _cli(capsys, "run", str(path), "--out", str(tmp_path / "plain"))
    assert code == 1
    assert "expect max_sim_time" in out and "[FAILED]" in out


def test_the_mission_timeout_ends_failed_without_hanging(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    body = "mission: idle\nworld: walls\nrobot: turtlebot3\ntree:\n  wait: 1000\ntimeout: 3.05\n"
    code, result, _ = _json_run(capsys, _mission(tmp_path, body), tmp_path / "run")
    assert code == 1
    assert result["result"] == "FAILED"
    assert (result["error_name"], result["error_code"]) == ("MISSION_TIMEOUT", 9901)
    assert result["sim_time"] == 3.05
    assert "3.05 s of sim time" in result["error_msg"] and "wait 1000 s" in result["error_msg"]


def test_a_spawned_obstacle_blocks_the_robot_and_the_controller_reports_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    body = WALK + (
        "events:\n  - {at: 1.0, spawn_obstacle: {name: crate, x: 1.0, y: 1.0}}\n"
        "expect:\n  result: FAILED\n  error_code: FAILED_TO_MAKE_PROGRESS\n  no_contact: false\n"
    )
    code, result, _ = _json_run(capsys, _mission(tmp_path, body), tmp_path / "run")
    assert code == 0, result["expectations"]
    assert result["error_code"] == 801
    assert result["metrics"]["contact_objects"] == ["movable_0"]
    assert result["metrics"]["final_pose"]["x"] < 0.95


def test_a_spawned_obstacle_is_seen_by_the_lidar_and_follows_a_move(tmp_path: Path) -> None:
    body = (
        "mission: boxes\nworld: walls\nrobot: turtlebot3\ntree:\n  wait: 10\nevents:\n"
        "  - {at: 0.5, spawn_obstacle: {name: crate, x: 0.0, y: -1.0, size: [0.4, 0.3, 0.5]}}\n"
        "  - {at: 1.0, move_obstacle: {name: crate, x: 0.0, y: -2.0}}\n"
    )
    mission = load_mission(_mission(tmp_path, body))
    rig = MobileRig(mission, seed=0)
    events = TimedEvents(mission.events, rig.obstacles, rig.teleop)
    lidar = rig.robot.lidar
    south = 270  # beam index: 1 degree per beam, counter-clockwise from ahead
    before = lidar.scan()
    assert before.ranges[south] == pytest.approx(before.sensor_pose.y + 3.0, abs=0.005)  # wall
    rig.sim.step_for(0.5)
    assert [r["event"] for r in events.apply_due(rig.sim.time)] == ["spawn_obstacle"]
    scan = lidar.scan()
    face = -1.0 + 0.15  # the crate's north face (m)
    assert scan.ranges[south] == pytest.approx(scan.sensor_pose.y - face, abs=0.005)
    rig.sim.step_for(0.5)
    events.apply_due(rig.sim.time)
    assert lidar.scan().ranges[south] == pytest.approx(scan.sensor_pose.y + 2.0 - 0.15, abs=0.01)
    assert rig.robot.base.min_clearance() > 0.5


def test_teleop_events_reach_assisted_teleop_and_navigation_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    body = (
        "mission: nudge\nworld: walls\nrobot: turtlebot3\ntree:\n  sequence:\n"
        "    - force_success: {assisted_teleop: 4}\n    - navigate_to_pose: goal_open\n"
        "events:\n  - {at: 1.0, duration: 2.0, teleop: {linear: 0.15, angular: 0.0}}\n"
        "expect:\n  result: SUCCEEDED\n  final_pose_near: {location: goal_open}\n"
        "  max_path_length_ratio: 1.2\n"
    )
    code, result, _ = _json_run(capsys, _mission(tmp_path, body), tmp_path / "run")
    assert code == 0, result["expectations"]
    poses = {
        record["t"]: record
        for line in (tmp_path / "run" / TRACE_FILE).read_text().splitlines()
        if (record := json.loads(line))["type"] == "pose"
    }
    assert poses[1.0]["x"] == 0.0
    assert 0.25 < poses[4.0]["x"] < 0.35 and poses[4.0]["v"] == 0.0  # 2 s at 0.15 m/s
    assert result["metrics"]["planned_path_length"] > 2.0


# --- invalid input, interruption, baselines -------------------------------------------------


def test_invalid_input_exits_2_with_one_located_line_and_no_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    broken = _mission(tmp_path, WALK.replace("go_to_goal:", "go_to_gaol:"))
    code, out, err = _cli(capsys, "run", str(broken))
    assert (code, out) == (2, "")
    assert err.count("\n") == 1
    assert err.startswith(f"{broken}:8:3: unknown behaviour 'go_to_gaol'")
    unknown_metric = _mission(
        tmp_path, WALK + "expect:\n  metrics:\n    speed: {max: 1}\n", "metric.yaml"
    )
    code, _, err = _cli(capsys, "run", str(unknown_metric))
    assert code == 2
    assert err.startswith(f"{unknown_metric}:12:5: unknown metric 'speed'")
    for argv, message in [
        (["no_such_mission"], "no mission file 'no_such_mission'"),
        (["walls_bug2", "--set", "speed=3"], "unknown parameter 'speed'"),
        (["walls_bug2", "--record", "no/x.mcap"], "the folder no does not exist"),
        (["walls_bug2", "--seed", "-1"], "--seed must be >= 0"),
    ]:
        code, out, err = _cli(capsys, "run", *argv)
        assert (code, out) == (2, ""), argv
        assert err.count("\n") == 1 and message in err, err
    (tmp_path / "full").mkdir()
    (tmp_path / "full" / "x").write_text("")
    code, _, err = _cli(capsys, "run", "walls_bug2", "--out", str(tmp_path / "full"))
    assert code == 2 and "not empty" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["full", "m.yaml", "metric.yaml"]


def test_viewer_without_a_display_warns_and_runs_headless(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    body = "mission: pause\nworld: walls\nrobot: turtlebot3\ntree:\n  wait: 0.5\n"
    code, result, err = _json_run(capsys, _mission(tmp_path, body), tmp_path / "run", "--viewer")
    assert (code, result["result"], result["sim_time"]) == (0, "SUCCEEDED", 0.5)
    assert "baobab run: --viewer: no display" in err and "running headless" in err


def test_a_reader_that_stops_early_gets_no_traceback_and_the_run_goes_on(tmp_path: Path) -> None:
    # `baobab run MISSION | head -2`: the progress stream closes while the mission runs.
    out = tmp_path / "run"
    process = subprocess.Popen(
        [BAOBAB, "run", str(_mission(tmp_path, WALK)), "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert process.stdout is not None and process.stderr is not None
    assert process.stdout.readline().startswith("running ")
    process.stdout.close()
    err = process.stderr.read()
    assert process.wait(timeout=300) == 0
    assert "Traceback" not in err and "BrokenPipeError" not in err
    assert json.loads((out / RESULT_FILE).read_text())["result"] == "SUCCEEDED"
    _assert_complete_folder(out)


def test_sigint_cancels_the_run_and_still_writes_the_folder(tmp_path: Path) -> None:
    body = WALK.replace("go_to_goal: goal_open", "wait: 50") + "expect:\n  result: SUCCEEDED\n"
    path = _mission(tmp_path, body)
    out = tmp_path / "run"
    process = subprocess.Popen(
        [BAOBAB, "run", str(path), "--json", "--realtime", "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert process.stderr is not None
    lines: queue.Queue[str] = queue.Queue()
    reader = threading.Thread(target=lambda: [lines.put(line) for line in process.stderr or []])
    reader.start()
    while not lines.get(timeout=300).startswith("t="):
        pass
    process.send_signal(signal.SIGINT)
    assert process.wait(timeout=300) == 130
    assert process.stdout is not None
    stdout = process.stdout.read()
    reader.join()
    result = json.loads(stdout)
    assert (result["result"], result["error_msg"]) == ("CANCELED", "interrupted (SIGINT)")
    assert result["sim_time"] < 50.0
    assert json.loads((out / RESULT_FILE).read_text())["result"] == "CANCELED"
    _assert_complete_folder(out)


def test_a_baseline_is_created_then_guards_against_regressions(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    mission = _mission(tmp_path, WALK)
    baseline = tmp_path / "baseline.json"
    code, result, err = _json_run(capsys, mission, tmp_path / "a", "--baseline", str(baseline))
    assert code == 0 and "baseline created" in err
    assert result["baseline"]["status"] == "created"
    stored = json.loads(baseline.read_text())
    assert stored["metrics"]["sim_time"] == result["metrics"]["sim_time"]
    code, result, _ = _json_run(capsys, mission, tmp_path / "b", "--baseline", str(baseline))
    assert code == 0
    names = [e["name"] for e in result["expectations"]]
    assert names == ["baseline.sim_time", "baseline.path_length", "baseline.number_of_recoveries"]
    stored["metrics"]["sim_time"] = 10.0  # the run takes ~14.7 s: beyond 10 * 1.1 + 0.5
    baseline.write_text(json.dumps(stored))
    code, result, _ = _json_run(capsys, mission, tmp_path / "c", "--baseline", str(baseline))
    assert code == 1
    slower = _expectation(result, "baseline.sim_time")
    assert slower["passed"] is False and slower["expected"]["max"] == pytest.approx(11.5)
    assert _expectation(result, "baseline.path_length")["passed"] is True
    baseline.write_text('{"baobab_baseline": 1,\n "mission": }')
    code, out, err = _cli(capsys, "run", str(mission), "--baseline", str(baseline))
    assert (code, out) == (2, "")
    assert err.startswith(f"{baseline}:2:13: not valid JSON")


def test_runs_default_to_a_timestamped_folder_under_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    code, out, _ = _cli(capsys, "run", str(_mission(tmp_path, WALK)))
    assert code == 0
    (folder,) = (tmp_path / "runs").iterdir()
    assert folder.name.startswith("walk-") and folder.name.endswith("Z")
    _assert_complete_folder(folder)
    assert "result" in out and "SUCCEEDED" in out and f"runs{os.sep}walk-" in out


def test_the_panda_picks_and_places_through_the_arm_port() -> None:
    mission = load_mission(Path(__file__).parent / "missions" / "pick.yaml")
    record = run_mission(mission)
    result = record.result_object()
    assert record.exit_code == 0, result["expectations"]
    assert [e["name"] for e in result["expectations"]] == [
        "result",
        "object_lifted",
        "object_placed",
    ]
    metrics = result["metrics"]
    assert metrics["cube_max_lift"] > 0.14  # the lift parameter is 0.15 m
    assert metrics["placement_error"] < 0.03
    tcp = [json.loads(line) for line in record.trace.lines if '"type":"pose"' in line][-1]
    assert set(tcp) >= {"tcp", "quat", "gripper", "cube"}


def test_a_mobile_run_without_navigation_imports_neither_panda_nor_nav(tmp_path: Path) -> None:
    path = _mission(tmp_path, "mission: pause\nworld: walls\nrobot: turtlebot3\ntree:\n  wait: 1\n")
    script = (
        "import sys\nfrom baobab.missions.cli.command_line import main\n"
        f"code = main(['run', {str(path)!r}, '--out', {str(tmp_path / 'run')!r}])\n"
        "heavy = [m for m in sys.modules if m.split('.')[0] == 'pinocchio'"
        " or m.startswith(('baobab.robots.panda', 'baobab.nav'))]\n"
        "print('HEAVY', code, heavy)\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[-1] == "HEAVY 0 []"


def test_a_cold_kernel_cache_is_announced(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from baobab.missions.cli.run_command import kernels_cached
    from baobab.robots.catalog import ROBOTS

    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    assert not kernels_cached(ROBOTS["turtlebot3"])
    index = tmp_path / "diff_drive_0123" / "base_kernel.base_kernel-170.py311.nbi"
    index.parent.mkdir()
    index.touch()
    assert kernels_cached(ROBOTS["turtlebot3"])
    assert kernels_cached(ROBOTS["turtlebot4"])
    assert not kernels_cached(ROBOTS["panda"])
