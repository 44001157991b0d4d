"""``baobab`` under signals and with closed or broken standard streams, as real processes.

Signals go to a real ``baobab run`` at moments hypothesis draws (seeded, so every run of the
suite sends the same ones): during start-up, while the mission loads, while it runs and
while the run folder is written. Whatever the moment: exit ``128 + signal`` (or the run's own
code when it had ended), no traceback, the run folder complete or absent, no temporary left.
"""

from __future__ import annotations

import json
import os
import pty
import select
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from baobab.missions.cli.command_line import main
from baobab.missions.run import plotting
from baobab.missions.run.run_folder import PLOT_FILE, RESULT_FILE, TRACE_FILE

BAOBAB = str(Path(sys.executable).parent / "baobab")
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
PAUSE = HEADER + "mission: pause\nworld: walls\nrobot: turtlebot3\ntree:\n  wait: 1\n"
SIGNALS = [signal.SIGINT, signal.SIGTERM, signal.SIGHUP]


def _mission(folder: Path) -> Path:
    path = folder / "pause.yaml"
    path.write_text(PAUSE, encoding="utf-8")
    return path


def _handles_sighup(pid: int) -> bool:
    """Whether process ``pid`` handles SIGHUP itself yet (baobab's first statements) or ended."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return True  # gone already, or no procfs: nothing to wait for
    fields = dict(line.split(":", 1) for line in status.splitlines() if ":" in line)
    if fields["State"].split()[0] in ("Z", "X"):
        return True  # it has ended (and waits to be reaped)
    return bool(int(fields["SigCgt"], 16) & (1 << (signal.SIGHUP - 1)))


def _check_folder(folder: Path, code: int, signum: int, stdout: str) -> None:
    """The folder is complete or absent, and says how the run ended."""
    leftovers = [p.name for p in folder.parent.iterdir() if p.name.startswith(".")]
    assert leftovers == []
    if not folder.exists():
        assert code == 128 + signum and stdout == ""
        return
    assert sorted(p.name for p in folder.iterdir()) == sorted([PLOT_FILE, RESULT_FILE, TRACE_FILE])
    result: dict[str, Any] = json.loads((folder / RESULT_FILE).read_text())
    assert json.loads(stdout) == result
    name = signal.Signals(signum).name
    if result["result"] == "CANCELED":
        assert result["error_msg"] == f"interrupted ({name})"
        assert code == result["exit_code"] == 128 + signum
    else:  # the run had ended: the signal came while the folder was written, or later
        assert result["result"] == "SUCCEEDED" and code in (0, 128 + signum)


@settings(max_examples=15)
@given(signum=st.sampled_from(SIGNALS), delay=st.floats(0.0, 3.0))
@example(signum=signal.SIGINT, delay=0.0)
@example(signum=signal.SIGTERM, delay=0.0)
def test_a_signal_at_any_moment_ends_the_run_cleanly(signum: int, delay: float) -> None:
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary) / "run"
        process = subprocess.Popen(
            [BAOBAB, "run", str(_mission(Path(temporary))), "--json", "--out", str(folder)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        while not _handles_sighup(process.pid):
            time.sleep(0.001)  # the interpreter's own start-up: no baobab code runs yet
        try:
            process.wait(timeout=delay)
        except subprocess.TimeoutExpired:
            process.send_signal(signum)
        stdout, stderr = process.communicate(timeout=300)
        assert "Traceback" not in stderr and "Exception" not in stderr, stderr
        assert process.returncode in (0, 128 + signum), stderr
        _check_folder(folder, process.returncode, signum, stdout)


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP])
def test_sigterm_and_sighup_cancel_a_running_run_as_sigint_does(
    signum: signal.Signals, tmp_path: Path
) -> None:
    mission = tmp_path / "long.yaml"
    mission.write_text(PAUSE.replace("wait: 1", "wait: 60"), encoding="utf-8")
    folder = tmp_path / "run"
    process = subprocess.Popen(
        [BAOBAB, "run", str(mission), "--json", "--realtime", "--out", str(folder)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert process.stderr is not None
    while not process.stderr.readline().startswith("t="):
        pass  # the run's first tick
    process.send_signal(signum)
    stdout, stderr = process.communicate(timeout=300)
    assert process.returncode == 128 + signum
    assert "Traceback" not in stderr
    _check_folder(folder, process.returncode, signum, stdout)
    assert json.loads(stdout)["result"] == "CANCELED"


def _signal_while_writing(
    monkeypatch: pytest.MonkeyPatch, signals: list[signal.Signals]
) -> list[signal.Signals]:
    """Send ``signals`` to this process while the run folder's plot is being saved."""
    real_save = plotting.save_plot
    sent: list[signal.Signals] = []

    def save_plot(*arguments: Any) -> None:
        for signum in signals:
            sent.append(signum)
            os.kill(os.getpid(), signum)
        real_save(*arguments)

    monkeypatch.setattr(plotting, "save_plot", save_plot)
    return sent


@pytest.mark.parametrize("signum", SIGNALS)
def test_a_signal_while_the_folder_is_written_lets_it_finish(
    signum: signal.Signals,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    sent = _signal_while_writing(monkeypatch, [signum])
    folder = tmp_path / "run"
    code = main(["run", str(_mission(tmp_path)), "--json", "--out", str(folder)])
    assert sent == [signum]
    assert code == 128 + signum
    _check_folder(folder, code, signum, capsys.readouterr().out)
    assert json.loads((folder / RESULT_FILE).read_text())["exit_code"] == 0  # it had ended


def test_a_second_sigint_while_the_folder_is_written_stops_and_leaves_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    _signal_while_writing(monkeypatch, [signal.SIGINT, signal.SIGINT])
    code = main(["run", str(_mission(tmp_path)), "--json", "--out", str(tmp_path / "run")])
    assert code == 130
    assert capsys.readouterr().out == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pause.yaml"]


# --- streams ----------------------------------------------------------------------------------


def _shell(command: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    """Run ``command`` in bash (for its redirections); prints ``rc=<baobab's exit code>``."""
    return subprocess.run(
        ["bash", "-c", f"{command}; rc=${{PIPESTATUS[0]}}; echo; echo rc=$rc"],
        capture_output=True,
        text=True,
        cwd=cwd,
        env={**os.environ, "PATH": f"{Path(BAOBAB).parent}:{os.environ['PATH']}"},
        timeout=300,
    )


@pytest.mark.parametrize(
    "command",
    [
        "baobab list | head -c0",
        "baobab schema | head -c1",
        "baobab validate pause.yaml pause.yaml pause.yaml pause.yaml | head -c1",
        "baobab tree pause.yaml | head -c0",
        "baobab list >&-",
        "baobab validate pause.yaml >&- 2>&-",
    ],
)
def test_a_closed_or_broken_stdout_ends_quietly(command: str, tmp_path: Path) -> None:
    _mission(tmp_path)
    done = _shell(command, tmp_path)
    assert done.stdout.splitlines()[-1] == "rc=0"
    assert done.stderr == ""


@pytest.mark.parametrize("redirection", [">&-", "--json 2>&- >/dev/null", "2>&1 | head -c1"])
def test_a_run_with_a_closed_or_broken_stream_still_writes_its_folder(
    redirection: str, tmp_path: Path
) -> None:
    done = _shell(f"baobab run pause.yaml --out run {redirection}", _mission(tmp_path).parent)
    assert done.stdout.splitlines()[-1] == "rc=0"
    assert "Traceback" not in done.stderr + done.stdout
    result = json.loads((tmp_path / "run" / RESULT_FILE).read_text())
    assert result["result"] == "SUCCEEDED"


# --- what the terminal shows --------------------------------------------------------------------


def _on_a_terminal(arguments: list[str], cwd: Path) -> tuple[int, str]:
    """Run ``baobab`` with stdout and stderr on a pseudo-terminal; its exit code and screen."""
    controller, terminal = pty.openpty()
    process = subprocess.Popen(
        [BAOBAB, *arguments], stdout=terminal, stderr=terminal, stdin=subprocess.DEVNULL, cwd=cwd
    )
    os.close(terminal)
    screen = b""
    while True:
        ready, _, _ = select.select([controller], [], [], 300)
        assert ready, "no output for 300 s"
        try:
            chunk = os.read(controller, 65536)
        except OSError:  # EIO: the process closed the terminal
            break
        if not chunk:
            break
        screen += chunk
    os.close(controller)
    return process.wait(timeout=300), screen.decode("utf-8", "replace")


def test_a_terminal_is_told_what_happens_before_and_after_the_run(tmp_path: Path) -> None:
    code, screen = _on_a_terminal(["run", "pause.yaml", "--out", "run"], _mission(tmp_path).parent)
    assert code == 0
    assert "starting: " in screen and "kernels" in screen
    assert "writing the run folder" in screen


def test_json_gets_nothing_extra_on_a_terminal(tmp_path: Path) -> None:
    arguments = ["run", "pause.yaml", "--out", "run", "--json"]
    code, screen = _on_a_terminal(arguments, _mission(tmp_path).parent)
    assert code == 0
    assert "starting: " not in screen and "writing the run folder" not in screen
