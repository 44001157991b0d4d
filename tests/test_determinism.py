"""Determinism: the same mission, parameters and seed give the same trace digest.

What is checked, and how it is kept affordable:

- every bundled mission, run whole with its defaults and seed, gives the digest pinned in
  ``tests/golden_digests.json``: the same bits on every machine and after every change that
  is not meant to change a run. A change that moves a digest on purpose updates the file with
  ``python -m tests.update_golden`` and says why in its commit;
- every bundled mission runs twice in this process with the same seed and the same digest.
  The long missions take minutes of sim time (farm_rows about 490 s, waypoint_patrol about
  340 s), so every mission's ``timeout`` is cut to :data:`PREFIX_TIME` s of sim time for both
  runs: the trace of a run cut short is a prefix of the full run's (plus the timeout's end
  record), and both runs are cut alike, so equal digests mean equal prefixes;
- one comparison across processes, on the shortest lidar-driven mission with sensor noise on
  and a different ``PYTHONHASHSEED`` in the child process (``tests/test_runner.py`` also
  compares ``baobab run`` processes on walls_go_to_goal);
- the seed matters exactly where randomness enters: with ``noise: {lidar_std: ...}`` another
  seed changes the motion, without noise it does not; the Panda's cube is placed by the seed.

Digests always differ between seeds because the trace's first record names the seed, so the
seed checks compare the motion records instead.
"""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys
from importlib import resources
from pathlib import Path

import pytest

from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import Mission, load_mission
from baobab.missions.run.rig import MobileRig
from baobab.missions.run.runner import RunRecord, run_mission

BUNDLED = sorted(Path(str(resources.files("baobab.missions"))).glob("*.yaml"))
GOLDEN = Path(__file__).with_name("golden_digests.json")
UPDATE = "python -m tests.update_golden"
PREFIX_TIME = 20.0
"""Sim time (s) each bundled mission runs for in the repeat check."""
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"

NOISY_BUG2 = """
mission: noisy_bug2
world: walls
robot: turtlebot3
start: {x: 0.0, y: 0.0, yaw: 0.0}
seed: 5
params:
  sigma: {type: float, default: 0.01, min: 0}
tree:
  bug2: goal_behind_wall
noise: {lidar_std: "${sigma}"}
timeout: 20
"""
"""Bug2 steers by its lidar, so range noise changes its path."""


def _cut(mission: Mission, timeout: float = PREFIX_TIME) -> Mission:
    return dataclasses.replace(mission, timeout=min(mission.timeout, timeout))


def _motion(record: RunRecord) -> list[str]:
    """The trace's pose records: where the robot (and the objects) went, tick by tick."""
    return [line for line in record.trace.lines if '"type":"pose"' in line]


def _noisy(tmp_path: Path, sigma: float | None = None) -> Mission:
    path = tmp_path / "noisy_bug2.yaml"
    path.write_text(HEADER + NOISY_BUG2, encoding="utf-8")
    return load_mission(path, None if sigma is None else {"sigma": str(sigma)})


def _golden() -> dict[str, str]:
    digests: dict[str, str] = json.loads(GOLDEN.read_text(encoding="utf-8"))
    return digests


def test_the_golden_file_pins_exactly_the_bundled_missions() -> None:
    assert sorted(_golden()) == [path.stem for path in BUNDLED], f"run {UPDATE}"


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_every_bundled_mission_gives_its_golden_digest(path: Path) -> None:
    digest = run_mission(load_mission(path)).trace_digest
    assert digest == _golden().get(path.stem), (
        f"{path.stem}'s trace moved: if that is intended, run {UPDATE} and review the diff"
    )


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_every_bundled_mission_repeats_its_trace_in_one_process(path: Path) -> None:
    mission = _cut(load_mission(path))
    first, second = run_mission(mission), run_mission(mission)
    assert first.trace.lines[-1] == second.trace.lines[-1]
    assert first.trace_digest == second.trace_digest
    assert len(_motion(first)) > 50  # the runs went somewhere: 10 pose records per second


def test_a_noisy_run_repeats_across_processes(tmp_path: Path) -> None:
    mission = _noisy(tmp_path)
    here = run_mission(mission).trace_digest
    script = (
        "import sys\n"
        "from baobab.missions.language.loader import load_mission\n"
        "from baobab.missions.run.runner import run_mission\n"
        "print(run_mission(load_mission(sys.argv[1])).trace_digest)\n"
    )
    env = {**os.environ, "PYTHONHASHSEED": "12345"}
    child = subprocess.run(
        [sys.executable, "-c", script, str(mission.path)],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
        check=False,
    )
    assert child.returncode == 0, child.stderr
    assert child.stdout.strip() == here


def test_with_noise_the_seed_changes_the_motion_and_repeats_it(tmp_path: Path) -> None:
    mission = _noisy(tmp_path)
    assert mission.noise.lidar_std == 0.01
    first, again, other = (run_mission(mission, seed=seed) for seed in (5, 5, 6))
    assert first.trace_digest == again.trace_digest
    assert _motion(first) != _motion(other)
    last = json.loads(_motion(first)[-1])
    assert abs(last["x"]) + abs(last["y"]) > 0.5  # it drove, noise or not


def test_without_noise_the_seed_does_not_change_a_mobile_robots_motion(tmp_path: Path) -> None:
    mission = _noisy(tmp_path, sigma=0.0)
    assert mission.noise.lidar_std == 0.0
    one, other = run_mission(mission, seed=5), run_mission(mission, seed=6)
    assert one.trace_digest != other.trace_digest  # the start record names the seed
    assert _motion(one) == _motion(other)


def test_the_noise_reaches_the_lidar(tmp_path: Path) -> None:
    rig = MobileRig(_noisy(tmp_path, sigma=0.02), seed=1)
    assert rig.robot.lidar.noise_std == 0.02
    scans = [rig.robot.lidar.scan().ranges for _ in range(2)]
    hits = [i for i, r in enumerate(scans[0]) if r < 3.0]
    assert hits and any(scans[0][i] != scans[1][i] for i in hits)


def test_the_panda_cube_is_placed_by_the_seed() -> None:
    mission = _cut(load_mission(BUNDLED[0].parent / "panda_pick.yaml"), 0.5)
    one, again, other = (run_mission(mission, seed=seed) for seed in (0, 0, 1))
    assert _motion(one) == _motion(again)
    cubes = [json.loads(_motion(record)[0])["cube"] for record in (one, other)]
    assert cubes[0] != cubes[1]


def test_noise_needs_a_robot_with_a_lidar(tmp_path: Path) -> None:
    path = tmp_path / "arm.yaml"
    path.write_text(
        HEADER + "mission: arm\nrobot: panda\ntree:\n  gripper: open\nnoise: {lidar_std: 0.01}\n",
        encoding="utf-8",
    )
    with pytest.raises(MissionError, match=r"arm.yaml:6:\d+: lidar_std needs a robot with a lidar"):
        load_mission(path)


def test_negative_noise_is_refused_with_its_location(tmp_path: Path) -> None:
    path = tmp_path / "noisy.yaml"
    path.write_text(HEADER + NOISY_BUG2.replace('"${sigma}"', "-0.1"), encoding="utf-8")
    with pytest.raises(MissionError, match=r"noisy.yaml:\d+:\d+: .*lidar_std"):
        load_mission(path)
