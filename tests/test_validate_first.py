"""Whatever ``run`` would refuse, ``validate`` refuses first; ``run`` refuses it before physics.

The names an ``expect:`` block may use come from catalogues that validation reads without
building a simulation: they must be the names a real run registers. A world's default spawn
inside an obstacle, arguments that are not UTF-8, a folder given as an output file and a
``--live`` address nobody can listen on are refused with one line and exit 2, nothing written.
"""

from __future__ import annotations

import enum
import io
import socket
import sys
from pathlib import Path

import pytest

from baobab.missions.cli.command_line import main
from baobab.missions.language.error_codes import MissionErrorCode, error_codes
from baobab.missions.language.loader import load_mission
from baobab.missions.language.metric_names import metric_names, structured_metric_names
from baobab.missions.run.rig import build_rig
from baobab.nav import errors as nav_errors
from baobab.robots.catalog import ROBOTS

HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
MOBILE = HEADER + "mission: m\nworld: walls\nrobot: turtlebot3\ntree: {wait: 1}\n"
ARM = HEADER + "mission: m\nrobot: panda\ntree: {gripper: open}\n"
BLOCKED_WORLD = (
    "name: blocked\nfloor: {size: [6, 6]}\n"
    "cylinders:\n  - {name: pillar, center: [0, 0], radius: 0.5}\n"
    "spawns:\n  default: {x: 0, y: 0}\n  free: {x: 2, y: 2}\n"
)


@pytest.mark.parametrize("text", [MOBILE, ARM], ids=["turtlebot3", "panda"])
def test_the_metric_catalogue_is_what_a_run_registers(text: str, tmp_path: Path) -> None:
    path = tmp_path / "m.yaml"
    path.write_text(text)
    mission = load_mission(path)
    rig = build_rig(mission, seed=0)
    assert list(metric_names(mission.robot)) == rig.metrics.number_names()
    every = set(metric_names(mission.robot)) | set(structured_metric_names(mission.robot))
    assert every == set(rig.metrics.names())


def test_error_code_names_are_those_of_the_robots_capabilities() -> None:
    mobile = error_codes(ROBOTS["turtlebot3"])
    arm = error_codes(ROBOTS["panda"])
    assert mobile["NO_VALID_PATH"] == {208, 308}
    assert mobile["FAILED_TO_MAKE_PROGRESS"] == {105, 801}  # Nav2's controller, the base's
    assert "GRASP_FAILED" not in mobile and arm["GRASP_FAILED"] == {4}
    assert "NO_VALID_PATH" not in arm
    for codes in (mobile, arm):
        assert {member.name for member in MissionErrorCode} <= set(codes)
    nav_enums = [
        value
        for value in vars(nav_errors).values()
        if isinstance(value, type) and issubclass(value, enum.IntEnum) and value is not enum.IntEnum
    ]
    assert len(nav_enums) == 18  # with docking (2), following (1), routes (2) and GPS (1) codes
    assert mobile["FAILED_TO_DETECT_DOCK"] == {904}
    assert mobile["NO_VALID_ROUTE"] == {405} and mobile["OPERATION_FAILED"] == {406}
    assert all(member.name in mobile for codes_enum in nav_enums for member in codes_enum)


@pytest.mark.parametrize(
    ("robot", "code", "accepted"),
    [
        ("turtlebot3", "NO_VALID_PATH", True),
        ("turtlebot3", 104, True),
        ("turtlebot3", "MISSION_TIMEOUT", True),
        ("turtlebot3", "GRASP_FAILED", False),
        ("panda", "GRASP_FAILED", True),
        ("panda", 4, True),
        ("panda", "NO_VALID_PATH", False),
        ("panda", 208, False),
    ],
)
def test_expect_error_code_is_checked_against_the_robot(
    robot: str, code: str | int, accepted: bool, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "m.yaml"
    text = MOBILE if robot == "turtlebot3" else ARM
    path.write_text(text + f"expect:\n  result: FAILED\n  error_code: {code}\n")
    assert main(["validate", str(path)]) == (0 if accepted else 2)
    if not accepted:
        err = capsys.readouterr().err
        assert f"unknown error code '{code}' in runs of {robot}" in err


def _blocked(tmp_path: Path) -> Path:
    world = tmp_path / "blocked.yaml"
    world.write_text(BLOCKED_WORLD)
    return world


def test_a_default_spawn_in_an_obstacle_is_refused_by_validate_and_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _blocked(tmp_path)
    mission = tmp_path / "m.yaml"
    mission.write_text(
        HEADER + "mission: m\nworld: blocked.yaml\nrobot: turtlebot3\ntree: {wait: 1}\n"
    )
    expected = (
        f"{mission}:3:1: the start (world 'blocked', spawn 'default') (0.00, 0.00) is inside "
        "obstacle 'pillar'; give the mission a start: in free space\n"
    )
    assert main(["validate", str(mission)]) == 2
    assert capsys.readouterr().err == expected
    assert main(["run", str(mission), "--out", str(tmp_path / "run")]) == 2
    assert capsys.readouterr().err == expected
    assert not (tmp_path / "run").exists()
    with_start = mission.read_text() + "start: free\n"
    mission.write_text(with_start)
    assert main(["validate", str(mission)]) == 0


def test_nav2_and_teleop_refuse_a_world_whose_default_spawn_is_blocked(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    world = _blocked(tmp_path)
    script = tmp_path / "script.py"
    script.write_text("open('ran', 'w').close()\n")
    monkeypatch.chdir(tmp_path)
    blocked = (
        "the default spawn (0.000, 0.000) is not free in world 'blocked': 'pillar' is -0.500 m "
        "from it, the robot's footprint needs 0.105 m\n"
    )
    assert main(["nav2", str(script), "--world", str(world)]) == 2
    assert capsys.readouterr().err == f"baobab nav2: {blocked}"
    assert not (tmp_path / "ran").exists()
    monkeypatch.setattr(sys, "stdin", io.StringIO("w"))
    assert main(["teleop", "--world", str(world)]) == 2
    assert capsys.readouterr().err == f"baobab teleop: {blocked}"


@pytest.mark.parametrize("command", ["validate", "run"])
@pytest.mark.parametrize("where", ["--set value", "mission path"])
def test_arguments_that_are_not_utf8_are_refused_before_anything_runs(
    command: str, where: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    undecodable = b"\xff\xfe".decode("utf-8", "surrogateescape")  # as os.fsdecode gives argv
    mission = tmp_path / ("m.yaml" if where == "--set value" else f"m{undecodable}.yaml")
    mission.write_text(MOBILE.replace("tree:", "params:\n  label: {type: str, default: a}\ntree:"))
    args = [command, str(mission)]
    args += ["--set", f"label={undecodable}"] if where == "--set value" else []
    args += ["--out", str(tmp_path / "run")] if command == "run" else []
    assert main(args) == 2
    err = capsys.readouterr().err
    shown = "label=\\xff\\xfe" if where == "--set value" else f"{tmp_path}/m\\xff\\xfe.yaml"
    assert err == (
        f"baobab: argument '{shown}' is not valid UTF-8 text; write it (and name files) in UTF-8\n"
    )
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("flag", ["--record", "--video", "--btlog"])
def test_a_folder_given_as_an_output_file_is_refused_before_the_run(
    flag: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    mission = tmp_path / "m.yaml"
    mission.write_text(MOBILE)
    folder = tmp_path / "out.btlog"
    folder.mkdir()
    assert main(["run", str(mission), flag, str(folder), "--out", str(tmp_path / "run")]) == 2
    assert (
        capsys.readouterr().err == f"baobab run: {flag} {folder}: is a folder; give a file name\n"
    )
    assert not (tmp_path / "run").exists()


@pytest.fixture
def taken_port() -> int:
    """A TCP port on 127.0.0.1 that another socket is listening on."""
    server = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    server.bind(("127.0.0.1", 0))
    server.listen()
    yield server.getsockname()[1]
    server.close()


@pytest.mark.parametrize("address", ["unknown host", "foreign address", "taken port", "empty"])
def test_an_unusable_live_address_is_refused_before_the_run(
    address: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    request: pytest.FixtureRequest,
) -> None:
    mission = tmp_path / "m.yaml"
    mission.write_text(MOBILE)
    host, port = {
        "unknown host": ("no-such-host.invalid", "8765"),
        "foreign address": ("192.0.2.1", "8765"),  # TEST-NET-1: never this machine's
        "taken port": ("127.0.0.1", "TAKEN"),
        "empty": ("", "8765"),
    }[address]
    if port == "TAKEN":
        port = str(request.getfixturevalue("taken_port"))
    argv = ["run", str(mission), "--live", "--host", host, "--port", port]
    assert main([*argv, "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("baobab run: ") and err.count("\n") == 1, err
    assert "cannot serve" in err and f" on {host}:{port}: " in err  # before any server starts
    assert not (tmp_path / "run").exists()
