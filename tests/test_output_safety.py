"""Nothing the machine does loses a run: what ``baobab run`` writes is checked before it
simulates, and a file system that fails afterwards costs the output's place, not the run.

The file systems here are real: small tmpfs mounts, filled or remounted read-only while a
real ``baobab`` process runs (skipped, with the reason, where this machine cannot mount).
"""

from __future__ import annotations

import json
import os
import queue
import socket
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import foxglove
import pytest
from filesystems import fill, make_read_only, tmpfs

from baobab.missions.cli.command_line import main
from baobab.missions.run import run_folder as run_folder_module
from baobab.missions.run.exit_codes import EXIT_NOT_SAVED
from baobab.missions.run.output_checks import MIN_FREE_BYTES
from baobab.missions.run.run_folder import PLOT_FILE, RESULT_FILE, TRACE_FILE, write_run_folder
from baobab.missions.testing import baseline as baseline_module
from baobab.sim.output_file import OutputFile
from baobab.sim.recording_sinks import McapSink

BAOBAB = str(Path(sys.executable).parent / "baobab")
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
PAUSE = HEADER + "mission: pause\nworld: walls\nrobot: turtlebot3\ntree:\n  wait: {seconds}\n"
ROOMY_KIB = (MIN_FREE_BYTES >> 10) + 400
"""A tmpfs with room enough to pass the checks before the run, and little more (KiB)."""


def _mission(folder: Path, seconds: float = 0.5) -> Path:
    path = folder / "pause.yaml"
    path.write_text(PAUSE.format(seconds=seconds), encoding="utf-8")
    return path


def _cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _complete(folder: Path) -> dict[str, Any]:
    """The result of a complete run folder (its three files, no temporary left anywhere)."""
    assert sorted(p.name for p in folder.iterdir()) == sorted([PLOT_FILE, RESULT_FILE, TRACE_FILE])
    result: dict[str, Any] = json.loads((folder / RESULT_FILE).read_text())
    return result


def _hidden(folder: Path) -> list[str]:
    return [p.name for p in folder.iterdir() if p.name.startswith(".")]


@pytest.fixture
def read_only(tmp_path: Path) -> Iterator[Path]:
    with tmpfs(tmp_path / "ro", 4096) as where:
        make_read_only(where)
        yield where


@pytest.fixture
def full(tmp_path: Path) -> Iterator[Path]:
    with tmpfs(tmp_path / "full", 256) as where:
        fill(where)
        yield where


# --- refused before the run -------------------------------------------------------------------


def _refusals(tmp_path: Path, read_only: Path, full: Path) -> dict[str, tuple[list[str], str]]:
    """Case -> (extra arguments, what the one line says)."""
    (tmp_path / "a_file").write_text("x")
    (tmp_path / "not_empty").mkdir()
    (tmp_path / "not_empty" / "x").write_text("x")
    (tmp_path / "a_folder.mcap").mkdir()
    out = ["--out", str(tmp_path / "run")]
    return {
        "out on a read-only file system": (
            ["--out", str(read_only / "run")],
            f"--out {read_only / 'run'}: cannot write there ({read_only}): it is on a read-only",
        ),
        "out is a read-only mount point": (
            ["--out", str(read_only)],
            f"--out {read_only}: cannot write there: it is on a read-only file system",
        ),
        "out on a full disk": (["--out", str(full / "run")], "its file system is full"),
        "out is a file": (["--out", str(tmp_path / "a_file")], "is a file"),
        "out is not empty": (["--out", str(tmp_path / "not_empty")], "folder is not empty"),
        "record to a folder": (
            [*out, "--record", str(tmp_path / "a_folder.mcap")],
            "is a folder; give a file name",
        ),
        "record to a device": ([*out, "--record", os.devnull], "is not a regular file"),
        "record on a read-only file system": (
            [*out, "--record", str(read_only / "x.mcap")],
            "cannot write there: it is on a read-only file system",
        ),
        "btlog on a full disk": (
            [*out, "--btlog", str(full / "x.btlog")],
            "its file system is full",
        ),
        "video on a read-only file system": (
            [*out, "--video", str(read_only / "x.mp4")],
            "it is on a read-only file system",
        ),
        "baseline to be made on a read-only file system": (
            [*out, "--baseline", str(read_only / "sub" / "base.json")],
            f"--baseline {read_only / 'sub' / 'base.json'}: cannot write there: it is on a",
        ),
    }


CASES = [
    "out on a read-only file system",
    "out is a read-only mount point",
    "out on a full disk",
    "out is a file",
    "out is not empty",
    "record to a folder",
    "record to a device",
    "record on a read-only file system",
    "btlog on a full disk",
    "video on a read-only file system",
    "baseline to be made on a read-only file system",
]


@pytest.mark.parametrize("case", CASES)
def test_an_unwritable_output_is_refused_with_one_line_before_the_run(
    case: str,
    tmp_path: Path,
    read_only: Path,
    full: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    arguments, expected = _refusals(tmp_path, read_only, full)[case]
    code, out, err = _cli(capsys, "run", str(_mission(tmp_path)), *arguments)
    assert (code, out) == (2, "")  # no "running ..." line: nothing was simulated
    assert err.startswith("baobab run: --") and err.count("\n") == 1, err
    assert expected in err
    assert not (tmp_path / "run").exists()


def test_live_on_a_port_in_use_is_refused_before_the_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = str(taken.getsockname()[1])
        arguments = ["--out", str(tmp_path / "run"), "--live", "--port", port]
        code, out, err = _cli(capsys, "run", str(_mission(tmp_path)), *arguments)
    assert (code, out) == (2, "")
    assert err.startswith(f"baobab run: cannot serve Foxglove on 127.0.0.1:{port}: Address")
    assert err.count("\n") == 1 and not (tmp_path / "run").exists()


def test_an_empty_mount_point_is_a_run_folder(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with tmpfs(tmp_path / "volume", 4096) as volume:
        code, out, _ = _cli(capsys, "run", str(_mission(tmp_path)), "--out", str(volume), "--json")
        assert code == 0
        assert _complete(volume) == json.loads(out)
        assert _hidden(volume) == []


def test_the_current_folder_is_a_run_folder_when_empty(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    mission = _mission(tmp_path)
    here = tmp_path / "here"
    here.mkdir()
    monkeypatch.chdir(here)
    code, _, _ = _cli(capsys, "run", str(mission), "--out", ".")
    assert code == 0
    assert _complete(here)["result"] == "SUCCEEDED"


# --- two runs, one folder ---------------------------------------------------------------------


class Process:
    """A real ``baobab`` process whose stderr lines are read as they come."""

    def __init__(self, *arguments: str, env: dict[str, str] | None = None) -> None:
        self.popen = subprocess.Popen(
            [BAOBAB, *arguments],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=None if env is None else {**os.environ, **env},
        )
        self.lines: queue.Queue[str] = queue.Queue()
        self.err: list[str] = []
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.popen.stderr is not None
        for line in self.popen.stderr:
            self.err.append(line)
            self.lines.put(line)

    def await_line(self, prefix: str) -> None:
        """Block until a line starting with ``prefix`` arrives on stderr."""
        while not self.lines.get(timeout=300).startswith(prefix):
            pass

    def finish(self) -> tuple[int, str, str]:
        """Exit code, stdout, stderr."""
        assert self.popen.stdout is not None
        out = self.popen.stdout.read()
        code = self.popen.wait(timeout=300)
        self._reader.join(timeout=60)
        return code, out, "".join(self.err)


def test_a_second_run_on_the_same_out_is_refused_while_the_first_runs(tmp_path: Path) -> None:
    out = tmp_path / "run"
    first = Process("run", str(_mission(tmp_path, 60)), "--realtime", "--json", "--out", str(out))
    first.await_line("t=")
    second = subprocess.run(
        [BAOBAB, "run", str(_mission(tmp_path)), "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert (second.returncode, second.stdout) == (2, "")
    assert second.stderr == (
        f"baobab run: --out {out}: in use by another baobab run; wait for it to end or give "
        "another folder\n"
    )
    first.popen.send_signal(2)
    code, stdout, _ = first.finish()
    assert code == 130
    assert _complete(out) == json.loads(stdout)
    assert _complete(out)["result"] == "CANCELED"


# --- the file system fails during the run ---------------------------------------------------


@pytest.mark.parametrize("failure", ["full", "read-only"])
def test_a_run_folder_the_disk_refuses_after_the_run_goes_to_a_named_fallback(
    failure: str, tmp_path: Path
) -> None:
    fallbacks = tmp_path / "fallbacks"
    fallbacks.mkdir()
    with tmpfs(tmp_path / "disk", ROOMY_KIB) as disk:
        out = disk / "run"
        run = Process(
            "run",
            str(_mission(tmp_path, 2)),
            "--realtime",
            "--json",
            "--out",
            str(out),
            env={"TMPDIR": str(fallbacks)},
        )
        run.await_line("t=")
        fill(disk) if failure == "full" else make_read_only(disk)
        code, stdout, err = run.finish()
        result = json.loads(stdout)
        (fallback,) = fallbacks.iterdir()
        reason = "No space left on device" if failure == "full" else "Read-only file system"
        assert code == 0
        assert f"baobab run: could not write the run folder {out}: {reason}; " in err
        assert f"written to {fallback} instead\n" in err and "Traceback" not in err
        assert result["run_folder"] == str(fallback)
        assert _complete(fallback) == result
        assert not out.exists() or list(out.iterdir()) == []
        assert sorted(p.name for p in disk.iterdir() if not p.name.startswith("filler")) in (
            [],
            ["run"],  # a read-only disk cannot have the empty folder removed
        )


def test_a_run_folder_written_into_by_someone_else_goes_to_a_named_fallback(
    tmp_path: Path,
) -> None:
    fallbacks = tmp_path / "fallbacks"
    fallbacks.mkdir()
    out = tmp_path / "run"
    arguments = ["--realtime", "--json", "--out", str(out)]
    run = Process("run", str(_mission(tmp_path, 2)), *arguments, env={"TMPDIR": str(fallbacks)})
    run.await_line("t=")
    (out / "notes.txt").write_text("not baobab's")
    code, stdout, err = run.finish()
    (fallback,) = fallbacks.iterdir()
    assert code == 0
    assert f"baobab run: could not write the run folder: {out}: folder is not empty" in err
    assert f"written to {fallback} instead\n" in err
    assert _complete(fallback) == json.loads(stdout)
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]


def test_a_run_that_cannot_be_saved_anywhere_prints_its_result_and_exits_3(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    real_write = run_folder_module.write_run_folder

    with tmpfs(tmp_path / "disk", ROOMY_KIB) as disk:
        (disk / "tmp").mkdir()
        monkeypatch.setattr("tempfile.tempdir", str(disk / "tmp"))

        def disk_fails_first(folder: Path, *rest: Any) -> Path:
            make_read_only(disk)
            return real_write(folder, *rest)

        monkeypatch.setattr(run_folder_module, "write_run_folder", disk_fails_first)
        code, out, err = _cli(
            capsys, "run", str(_mission(tmp_path)), "--json", "--out", str(disk / "run")
        )
    result = json.loads(out)
    assert code == EXIT_NOT_SAVED == 3
    assert (result["result"], result["run_folder"]) == ("SUCCEEDED", None)
    assert err.splitlines()[-1] == (
        f"baobab run: could not write the run folder {disk / 'run'}: Read-only file system; "
        f"nor a fallback folder in {disk / 'tmp'}: Read-only file system; "
        f"the run is not saved (exit {EXIT_NOT_SAVED})"
    )


def test_a_baseline_the_disk_refuses_after_the_run_is_reported_and_the_run_kept(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    real_write = baseline_module.write_baseline
    with tmpfs(tmp_path / "disk", ROOMY_KIB) as disk:

        def disk_fails_first(path: Path, *rest: Any) -> Any:
            make_read_only(disk)
            return real_write(path, *rest)

        monkeypatch.setattr(baseline_module, "write_baseline", disk_fails_first)
        base = disk / "base.json"
        out = tmp_path / "run"
        arguments = ["--json", "--out", str(out), "--baseline", str(base)]
        code, stdout, err = _cli(capsys, "run", str(_mission(tmp_path)), *arguments)
        assert not base.exists() and _hidden(disk) == []
    status = "not created: Read-only file system"
    assert code == 0
    assert json.loads(stdout)["baseline"] == {"file": str(base), "status": status}
    assert f"baobab run: --baseline {base}: {status}\n" in err and "Traceback" not in err
    assert _complete(out)["baseline"]["status"] == status


# --- recordings on a disk that fills --------------------------------------------------------


def _log_until_full(sink: McapSink, messages: int) -> None:
    context = foxglove.Context()
    sink.attach(context)
    channel = foxglove.Channel("/filler", context=context)
    for index in range(messages):
        channel.log({"index": index, "padding": "x" * 200})
    sink.close()


def test_a_recording_that_fills_the_disk_stops_once_and_leaves_no_file(tmp_path: Path) -> None:
    reasons: list[str] = []
    with tmpfs(tmp_path / "disk", 64) as disk:
        _log_until_full(McapSink(disk / "run.mcap", on_failure=reasons.append), 30_000)
        assert list(disk.iterdir()) == []
    assert reasons == ["No space left on device"]


def test_a_video_or_tree_log_on_a_full_disk_raises_at_close_when_nobody_listens(
    tmp_path: Path,
) -> None:
    import numpy as np

    from baobab.missions.language.btcpp_log import BtLogWriter, BtStatus
    from baobab.sim.errors import BaobabError
    from baobab.sim.rendering import VideoWriter

    with tmpfs(tmp_path / "disk", 64) as disk:
        video = VideoWriter(disk / "x.mp4", width=320, height=240)
        noise = np.random.default_rng(7).integers(0, 255, (60, 240, 320, 3), dtype=np.uint8)
        for frame in noise:  # noise does not compress: well over 64 KiB
            video.write(frame)
        with pytest.raises(BaobabError, match=r"x\.mp4: cannot write video: No space left"):
            video.close()
        fill(disk)
        log = BtLogWriter(disk / "x.btlog", '<root BTCPP_format="4"/>')
        log.transition(0.0, 1, BtStatus.RUNNING)
        with pytest.raises(BaobabError, match=r"x\.btlog: cannot write the tree log: No space"):
            log.close()
        assert sorted(p.name for p in disk.iterdir()) == ["filler", "filler-tail"]


def test_a_complete_recording_appears_under_its_name_only_when_closed(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    file = OutputFile(path, on_failure=pytest.fail)
    file.write(b"MCAP")
    assert not path.exists() and file.temporary.exists()
    file.close()
    assert path.read_bytes() == b"MCAP" and not file.temporary.exists()
    unfinished = OutputFile(tmp_path / "lost.mcap", on_failure=pytest.fail)
    unfinished.write(b"half")
    temporary = unfinished.temporary
    del unfinished  # never closed (the process is going down): not complete, so not kept
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.mcap"] and not temporary.exists()


def test_recordings_on_a_disk_that_fills_during_the_run_stop_once_and_the_run_goes_on(
    tmp_path: Path,
) -> None:
    # Each output either stops (one line, no file) or, when the room another one freed by
    # stopping lets it, is finished whole: never a partial file, never a lost run.
    files = {"--record": ("run.mcap", "mcap"), "--video": ("run.mp4", "video")}
    files["--btlog"] = ("run.btlog", "btlog")
    with tmpfs(tmp_path / "disk", ROOMY_KIB) as disk:
        out = tmp_path / "run"
        arguments = ["--realtime", "--json", "--out", str(out)]
        for flag, (name, _) in files.items():
            arguments += [flag, str(disk / name)]
        run = Process("run", str(_mission(tmp_path, 2)), *arguments)
        run.await_line("t=")
        fill(disk)
        code, stdout, err = run.finish()
        kept = sorted(p.name for p in disk.iterdir() if not p.name.startswith("filler"))
    assert code == 0
    assert "Traceback" not in err and "error logging" not in err
    result = json.loads(stdout)
    assert result["result"] == "SUCCEEDED" and _complete(out) == result
    recording = result["recording"]
    full = "No space left on device"
    for flag, (name, key) in files.items():
        line = f"baobab run: {flag} {disk / name}: {full}; stopped, no file kept"
        if name in kept:
            assert key in recording and line not in err
        else:
            assert recording["stopped"][key] == full and err.count(line) == 1
    assert recording["stopped"]  # the disk was full: something had to stop
    assert len(kept) + len(recording["stopped"]) == len(files)


def test_write_run_folder_on_a_full_disk_leaves_nothing_behind(tmp_path: Path) -> None:
    with tmpfs(tmp_path / "disk", 64) as disk:
        target = disk / "run"
        target.mkdir()
        with pytest.raises(OSError, match="No space left"):
            write_run_folder(target, {"result": "SUCCEEDED"}, "x" * 200_000, None)
        assert list(target.iterdir()) == []
