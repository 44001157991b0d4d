"""``baobab run`` through the run server, as real processes: the same run, codes, signals, streams.

Each test starts its own server on a socket in a fresh folder and reads its log (standard
error, a pipe here) to know what it did; the suite's other ``baobab run`` processes run
without a server (``tests/conftest.py``).
"""

from __future__ import annotations

import json
import os
import select
import shutil
import signal
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

from baobab.missions.cli.run_server_protocol import server_command, socket_path
from baobab.missions.run.run_folder import RESULT_FILE, TRACE_FILE

BAOBAB = str(Path(sys.executable).parent / "baobab")
GOLDEN = json.loads((Path(__file__).parent / "golden_digests.json").read_text())
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
PAUSE = HEADER + "mission: pause\nworld: walls\nrobot: turtlebot3\ntree:\n  wait: 60\n"
UNEQUAL = ("wall_time", "speedup", "run_folder")
"""result.json fields that differ between any two runs (wall clock, where the folder is)."""


class Server:
    """A run server on its own socket folder, and the environment that reaches it."""

    def __init__(self, extra: dict[str, str] | None = None) -> None:
        self.folder = Path(tempfile.mkdtemp(prefix="bb-", dir="/tmp"))  # a socket path is short
        self.environ = {
            **os.environ,
            **(extra or {}),
            "BAOBAB_RUN_SERVER": "1",
            "BAOBAB_RUN_SERVER_DIR": str(self.folder),
        }
        path = socket_path(self.environ)
        assert path is not None
        self.process = subprocess.Popen(
            server_command(path),
            stdin=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            env=self.environ,
        )
        self.unread = b""
        assert "serving" in self.next_line()

    def next_line(self) -> str:
        """The server's next log line (its handlers log on the same pipe)."""
        assert self.process.stderr is not None
        descriptor = self.process.stderr.fileno()
        while b"\n" not in self.unread:
            ready, _, _ = select.select([descriptor], [], [], 120)
            assert ready, "the run server said nothing for 120 s"
            chunk = os.read(descriptor, 65536)
            assert chunk, f"the run server ended; it said {self.unread!r}"
            self.unread += chunk
        line, self.unread = self.unread.split(b"\n", 1)
        return line.decode()

    def stop(self) -> None:
        self.process.terminate()
        self.process.wait(timeout=60)
        shutil.rmtree(self.folder, ignore_errors=True)


@pytest.fixture
def server() -> Iterator[Server]:
    started = Server()
    yield started
    started.stop()


def _run(arguments: list[str], cwd: Path, environ: dict[str, str]) -> subprocess.CompletedProcess:
    return subprocess.run(
        [BAOBAB, *arguments], cwd=cwd, env=environ, capture_output=True, text=True, timeout=300
    )


def _long_run_started(server: Server, folder: Path, stdout: int) -> subprocess.Popen:
    """A served ``baobab run`` of a 60 s pause paced to the wall clock, once it has ticked
    (its standard error read up to the first progress line)."""
    (folder / "long.yaml").write_text(PAUSE, encoding="utf-8")
    process = subprocess.Popen(
        [BAOBAB, "run", "long.yaml", "--json", "--realtime", "--out", "run"],
        cwd=folder,
        env=server.environ,
        stdout=stdout,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert process.stderr is not None
    while not (line := process.stderr.readline()).startswith("t="):
        assert line, f"baobab ended before its run's first tick: {process.wait()}"
    return process


@pytest.mark.parametrize("mission", ["walls_go_to_goal", "panda_pick"])  # the arm: BLAS, Pinocchio
def test_a_served_run_is_the_run_its_own_process_makes(
    server: Server, mission: str, tmp_path: Path
) -> None:
    arguments = ["run", mission, "--json", "--out"]
    served = _run([*arguments, "served"], tmp_path, server.environ)
    assert served.returncode == 0, served.stderr
    assert "worker" in server.next_line() and "ended with exit code 0" in server.next_line()
    alone = _run([*arguments, "alone"], tmp_path, {**os.environ, "BAOBAB_RUN_SERVER": "0"})
    assert alone.returncode == 0, alone.stderr
    folders = [tmp_path / "served", tmp_path / "alone"]
    results = [json.loads((folder / RESULT_FILE).read_text()) for folder in folders]
    for result in results:
        for field in UNEQUAL:
            result.pop(field)
    assert results[0] == results[1]
    assert results[0]["result"] == "SUCCEEDED"
    assert results[0]["trace_digest"] == GOLDEN[mission]
    traces = [(folder / TRACE_FILE).read_bytes() for folder in folders]
    assert traces[0] == traces[1]
    assert json.loads(served.stdout)["run_folder"] == "served"  # as given, relative to its cwd


def test_bad_input_gets_the_same_one_line_error_and_exit_2(server: Server, tmp_path: Path) -> None:
    (tmp_path / "bad.yaml").write_text(HEADER + "mission: bad\nworld: walls\nrobot: nope\n")
    served = _run(["run", "bad.yaml"], tmp_path, server.environ)
    alone = _run(["run", "bad.yaml"], tmp_path, {**os.environ, "BAOBAB_RUN_SERVER": "0"})
    assert served.returncode == alone.returncode == 2
    assert served.stderr == alone.stderr and len(served.stderr.splitlines()) == 1
    assert "ended with exit code 2" in [server.next_line(), server.next_line()][1]


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_a_signal_to_the_caller_cancels_the_served_run(
    server: Server, signum: signal.Signals, tmp_path: Path
) -> None:
    process = _long_run_started(server, tmp_path, stdout=subprocess.PIPE)
    process.send_signal(signum)
    stdout, stderr = process.communicate(timeout=300)
    assert process.returncode == 128 + signum, stderr
    result = json.loads((tmp_path / "run" / RESULT_FILE).read_text())
    assert json.loads(stdout) == result
    assert result["result"] == "CANCELED"
    assert result["error_msg"] == f"interrupted ({signal.Signals(signum).name})"


def test_a_caller_that_is_killed_hangs_its_run_up(server: Server, tmp_path: Path) -> None:
    process = _long_run_started(server, tmp_path, stdout=subprocess.DEVNULL)
    process.kill()
    process.wait(timeout=60)
    assert "worker" in server.next_line()
    assert f"ended with exit code {128 + signal.SIGHUP}" in server.next_line()
    result = json.loads((tmp_path / "run" / RESULT_FILE).read_text())
    assert result["error_msg"] == "interrupted (SIGHUP)"


def test_a_closed_stdout_and_a_broken_pipe_reach_the_served_run(
    server: Server, tmp_path: Path
) -> None:
    (tmp_path / "short.yaml").write_text(PAUSE.replace("wait: 60", "wait: 1"), encoding="utf-8")
    for redirection, folder in ((">&-", "closed"), ("2>&1 | head -c1", "broken")):
        done = subprocess.run(
            f"baobab run short.yaml --out {folder} {redirection}; echo rc=$?",
            shell=True,
            cwd=tmp_path,
            env={**server.environ, "PATH": f"{Path(BAOBAB).parent}:{os.environ['PATH']}"},
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert "Traceback" not in done.stderr + done.stdout
        assert json.loads((tmp_path / folder / RESULT_FILE).read_text())["result"] == "SUCCEEDED"
        assert "worker" in server.next_line() and "exit code 0" in server.next_line()


def test_a_changed_module_makes_the_server_decline_and_leave(tmp_path: Path) -> None:
    site = tmp_path / "site"
    site.mkdir()
    module = site / "sitecustomize.py"  # every interpreter loads it, the server too
    module.write_text("")
    server = Server({"PYTHONPATH": str(site), "BAOBAB_RUN_SERVER_IDLE": "1"})
    try:
        module.write_text("# changed\n")
        done = _run(["run", "walls_go_to_goal", "--out", "run"], tmp_path, server.environ)
        assert done.returncode == 0, done.stderr
        assert "declined a run: changed since the server loaded it" in server.next_line()
        assert server.process.wait(timeout=60) == 0  # it left; the next run starts anew
        assert json.loads((tmp_path / "run" / RESULT_FILE).read_text())["result"] == "SUCCEEDED"
        path = socket_path(server.environ)
        assert path is not None and path.with_suffix(".log").exists()  # a fresh server started
    finally:
        server.stop()


def test_with_the_server_off_a_run_starts_none(tmp_path: Path) -> None:
    folder = Path(tempfile.mkdtemp(prefix="bb-", dir="/tmp"))
    try:
        environ = {**os.environ, "BAOBAB_RUN_SERVER": "0", "BAOBAB_RUN_SERVER_DIR": str(folder)}
        done = _run(["run", "walls_go_to_goal", "--out", "run"], tmp_path, environ)
        assert done.returncode == 0, done.stderr
        assert list(folder.iterdir()) == []  # no socket, lock or log: no server was started
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def test_a_worker_killed_outright_is_reported_by_its_caller(server: Server, tmp_path: Path) -> None:
    process = _long_run_started(server, tmp_path, stdout=subprocess.DEVNULL)
    worker = int(server.next_line().split("worker ")[1].split(":")[0])
    os.kill(worker, signal.SIGKILL)
    _, stderr = process.communicate(timeout=300)
    assert process.returncode == 128 + signal.SIGKILL
    assert stderr.splitlines()[-1] == "baobab run: the run's process was killed by SIGKILL"
    assert f"ended with exit code {128 + signal.SIGKILL}" in server.next_line()


def test_the_server_outlives_a_stray_sigint_or_sighup(server: Server, tmp_path: Path) -> None:
    for signum in (signal.SIGINT, signal.SIGHUP):  # it has no terminal: neither means "stop"
        server.process.send_signal(signum)
    done = _run(["run", "walls_go_to_goal", "--out", "run"], tmp_path, server.environ)
    assert done.returncode == 0, done.stderr
    assert "worker" in server.next_line() and "exit code 0" in server.next_line()
