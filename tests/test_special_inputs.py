"""Inputs that are not regular files, or are too big: refused by type or size before reading.

A mission, world, baseline, campaign mission or ``baobab nav2`` script path may name a device
that never ends (``/dev/zero``, ``/dev/urandom``), a FIFO that blocks until someone writes, a
socket or a folder. Each is one located line and exit 2, nothing written. The devices and FIFOs
are real; the console-script cases run as real processes, with a guard that turns a hang into
a failure instead of a stuck suite.
"""

from __future__ import annotations

import os
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from baobab.missions.cli.command_line import main
from baobab.sim.errors import SourceError
from baobab.sim.input_files import MAX_INPUT_BYTES, read_input_file

HANG_GUARD = 60.0
"""Seconds a refused input may take before the test gives up (a guard, not a check: a read of
/dev/zero or a FIFO would otherwise hang the suite)."""
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
MISSION = HEADER + "mission: m\nworld: walls\nrobot: turtlebot3\ntree: {wait: 1}\n"
BAOBAB = str(Path(sys.executable).with_name("baobab"))


@pytest.fixture
def fifo(tmp_path: Path) -> Path:
    """A FIFO nobody writes to."""
    path = tmp_path / "fifo.yaml"
    os.mkfifo(path)
    return path


@pytest.fixture
def fifo_with_a_writer(tmp_path: Path) -> Iterator[Path]:
    """A FIFO held open for writing (so a blocking read would wait for data forever)."""
    path = tmp_path / "held.yaml"
    os.mkfifo(path)
    writer = os.open(path, os.O_RDWR | os.O_NONBLOCK)
    try:
        yield path
    finally:
        os.close(writer)


@pytest.fixture
def unix_socket(tmp_path: Path) -> Iterator[Path]:
    """A listening Unix socket file."""
    path = tmp_path / "socket.yaml"
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(str(path))
    server.listen()
    try:
        yield path
    finally:
        server.close()


def _special(kind: str, request: pytest.FixtureRequest) -> tuple[Path, str]:
    """(path, the words of the refusal) for each kind of special file."""
    if kind == "/dev/zero" or kind == "/dev/urandom":
        return Path(kind), "is a character device; expected"
    if kind == "fifo":
        return request.getfixturevalue("fifo"), "is a FIFO (named pipe); expected"
    if kind == "fifo with a writer":
        return request.getfixturevalue("fifo_with_a_writer"), "is a FIFO (named pipe); expected"
    return request.getfixturevalue("unix_socket"), "is a socket; expected"


SPECIAL_KINDS = ["/dev/zero", "/dev/urandom", "fifo", "fifo with a writer", "socket"]


def _one_line(stderr: str) -> str:
    assert "Traceback" not in stderr, stderr
    assert stderr.endswith("\n") and stderr.count("\n") == 1, stderr
    return stderr.rstrip("\n")


@pytest.mark.parametrize("command", ["validate", "run"])
@pytest.mark.parametrize("kind", SPECIAL_KINDS)
def test_the_console_script_refuses_a_special_file_as_mission(
    kind: str, command: str, tmp_path: Path, request: pytest.FixtureRequest
) -> None:
    path, words = _special(kind, request)
    out = tmp_path / "run"
    args = [BAOBAB, command, str(path)] + (["--out", str(out)] if command == "run" else [])
    done = subprocess.run(args, capture_output=True, text=True, timeout=HANG_GUARD, check=False)
    assert done.returncode == 2, done.stderr
    assert done.stdout == ""
    assert _one_line(done.stderr) == f"{path}:1:1: {words} a YAML file"
    assert not out.exists()


@pytest.mark.parametrize("kind", ["fifo", "fifo with a writer", "socket"])
def test_a_special_world_file_is_refused_at_the_missions_world_key(
    kind: str, tmp_path: Path, request: pytest.FixtureRequest, capsys: pytest.CaptureFixture[str]
) -> None:
    special, words = _special(kind, request)
    folder = tmp_path / "mission"
    folder.mkdir()
    world = folder / "w.yaml"
    special.rename(world)  # a FIFO or socket keeps its kind when moved
    mission = folder / "m.yaml"
    mission.write_text(HEADER + "mission: m\nworld: w.yaml\nrobot: turtlebot3\ntree: {wait: 1}\n")
    assert main(["validate", str(mission)]) == 2
    kind_words = words.removesuffix("; expected")
    assert _one_line(capsys.readouterr().err) == (
        f"{mission}:3:1: world file 'w.yaml' {kind_words}; expected a file"
    )


@pytest.mark.parametrize("kind", SPECIAL_KINDS)
def test_a_special_world_given_to_nav2_is_refused(
    kind: str, tmp_path: Path, request: pytest.FixtureRequest, capsys: pytest.CaptureFixture[str]
) -> None:
    world, words = _special(kind, request)
    script = tmp_path / "script.py"
    script.write_text("open('ran', 'w').close()\n")
    assert main(["nav2", str(script), "--world", str(world)]) == 2
    assert _one_line(capsys.readouterr().err) == f"{world}:1:1: {words} a YAML file"


@pytest.mark.parametrize("kind", SPECIAL_KINDS)
def test_a_special_nav2_script_is_refused(
    kind: str, request: pytest.FixtureRequest, capsys: pytest.CaptureFixture[str]
) -> None:
    script, words = _special(kind, request)
    assert main(["nav2", str(script), "--world", "walls"]) == 2
    assert _one_line(capsys.readouterr().err) == f"{script}:1:1: {words} a Python script"


@pytest.mark.parametrize("kind", SPECIAL_KINDS)
def test_a_special_baseline_is_refused_before_the_run(
    kind: str, tmp_path: Path, request: pytest.FixtureRequest, capsys: pytest.CaptureFixture[str]
) -> None:
    baseline, words = _special(kind, request)
    mission = tmp_path / "m.yaml"
    mission.write_text(MISSION)
    out = tmp_path / "run"
    code = main(["run", str(mission), "--baseline", str(baseline), "--out", str(out)])
    assert code == 2
    assert _one_line(capsys.readouterr().err) == f"{baseline}:1:1: {words} a baseline JSON file"
    assert not out.exists()


def test_a_folder_as_baseline_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    mission = tmp_path / "m.yaml"
    mission.write_text(MISSION)
    code = main(["run", str(mission), "--baseline", str(tmp_path), "--out", str(tmp_path / "r")])
    assert code == 2
    err = _one_line(capsys.readouterr().err)
    assert err == f"{tmp_path}:1:1: is a directory; expected a baseline JSON file"


@pytest.mark.parametrize("kind", ["/dev/zero", "fifo", "socket"])
def test_a_special_campaign_mission_is_refused(
    kind: str, tmp_path: Path, request: pytest.FixtureRequest, capsys: pytest.CaptureFixture[str]
) -> None:
    mission, words = _special(kind, request)
    out = tmp_path / "campaign"
    assert main(["campaign", str(mission), "--runs", "2", "--out", str(out)]) == 2
    assert _one_line(capsys.readouterr().err) == f"{mission}:1:1: {words} a YAML file"
    assert not out.exists()


def test_a_regular_file_that_reads_longer_than_its_size_is_cut_at_the_limit() -> None:
    # /proc files report a size of 0 and hold more: the read stops one byte past the limit.
    maps = Path("/proc/self/maps")
    if not maps.is_file():
        pytest.skip("no /proc on this machine")
    assert maps.stat().st_size == 0
    with pytest.raises(SourceError) as raised:
        read_input_file(maps, limit=100)
    assert (
        str(raised.value)
        == "/proc/self/maps:1:1: file holds more than 100 bytes; the limit is 100 bytes"
    )


@pytest.mark.parametrize("what", ["script", "baseline"])
def test_a_file_over_the_size_limit_is_refused_before_it_is_read(
    what: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    big = tmp_path / ("big.py" if what == "script" else "big.json")
    with big.open("wb") as stream:
        stream.truncate(MAX_INPUT_BYTES + 1)  # sparse: nothing is written or read
    mission = tmp_path / "m.yaml"
    mission.write_text(MISSION)
    if what == "script":
        code = main(["nav2", str(big), "--world", "walls"])
    else:
        code = main(["run", str(mission), "--baseline", str(big), "--out", str(tmp_path / "r")])
    assert code == 2
    assert _one_line(capsys.readouterr().err) == (
        f"{big}:1:1: file is {MAX_INPUT_BYTES + 1} bytes; the limit is {MAX_INPUT_BYTES} bytes"
    )


def test_a_symlink_loop_and_a_file_below_a_file_are_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    loop = tmp_path / "loop.yaml"
    loop.symlink_to(loop)
    below = tmp_path / "m.yaml" / "x.yaml"
    (tmp_path / "m.yaml").write_text(MISSION)
    assert main(["validate", str(loop), str(below)]) == 2
    lines = capsys.readouterr().err.splitlines()
    assert lines == [
        f"{loop}:1:1: cannot read: Too many levels of symbolic links",
        f"{below}:1:1: no such file (a part of the path is not a folder)",
    ]
