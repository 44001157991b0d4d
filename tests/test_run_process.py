"""The run in a child process: results, messages, errors and deaths cross back to the parent."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
from pathlib import Path
from typing import Any

import pytest

from baobab.missions.language.errors import MissionError
from baobab.missions.run.child_process import (
    ChildProcessDiedError,
    handle_forwarded_signals,
    run_in_child,
    start_child,
)
from baobab.sim.errors import BaobabError

REPO = Path(__file__).resolve().parents[1]


def _python(script: str) -> str:
    """Run ``script`` in a fresh interpreter in the repository; what it printed. It must exit 0."""
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, cwd=REPO, check=False
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_messages_arrive_in_order_then_the_result() -> None:
    seen: list[Any] = []

    def job(send: Any) -> dict[str, int]:
        for index in range(5):
            send(("progress", index))
        return {"pid": os.getpid()}

    result = run_in_child(job, seen.append)
    assert seen == [("progress", index) for index in range(5)]
    assert result["pid"] != os.getpid()  # it ran in another process


def test_a_located_error_keeps_its_type_and_its_line() -> None:
    def job(_send: Any) -> None:
        raise MissionError("m.yaml", 3, 7, "unknown leaf 'fly'")

    with pytest.raises(MissionError) as raised:
        run_in_child(job, print)
    assert str(raised.value) == "m.yaml:3:7: unknown leaf 'fly'"
    assert (raised.value.line, raised.value.column) == (3, 7)


def test_a_bug_in_the_child_keeps_its_type() -> None:
    def job(_send: Any) -> None:
        raise KeyError("missing")

    with pytest.raises(KeyError, match="missing"):
        run_in_child(job, print)


# A lock cannot be pickled however exceptions are (tblib, which dask installs, pickles any
# exception's __dict__ without calling __init__).
class _UnpicklableError(BaobabError):
    def __init__(self, first: str, second: str) -> None:
        super().__init__(f"{first} and {second}")
        self.lock = threading.Lock()


class _UnpicklableBugError(Exception):
    def __init__(self, first: str, second: str) -> None:
        super().__init__(f"{first} and {second}")
        self.lock = threading.Lock()


@pytest.mark.parametrize(
    ("raised", "arrives", "text"),
    [
        # baobab's own error keeps its words, so `baobab run` still prints its one line
        (_UnpicklableError, BaobabError, "one and two"),
        # a bug arrives with the child's traceback
        (_UnpicklableBugError, RuntimeError, "Traceback"),
    ],
)
def test_an_exception_that_cannot_be_pickled_arrives_as_the_nearest_one_that_can(
    raised: type[Exception], arrives: type[Exception], text: str
) -> None:
    def job(_send: Any) -> None:
        raise raised("one", "two")

    with pytest.raises(arrives) as caught:
        run_in_child(job, print)
    assert type(caught.value) is arrives
    assert text in str(caught.value) and "one and two" in str(caught.value)


def test_a_child_killed_by_a_signal_is_reported_with_its_name() -> None:
    def job(send: Any) -> None:
        send("about to die")
        os.kill(os.getpid(), signal.SIGKILL)

    seen: list[Any] = []
    with pytest.raises(ChildProcessDiedError, match=r"signal 9 \(SIGKILL\)"):
        run_in_child(job, seen.append)
    assert seen == ["about to die"]


def test_keyboard_interrupt_in_the_child_reaches_the_parent() -> None:
    def job(_send: Any) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_in_child(job, print)


def test_the_plotting_process_never_loads_the_simulation_stack(tmp_path: Path) -> None:
    # The parent of `baobab run` writes the run folder (matplotlib); MuJoCo's physics runs,
    # and numba's LLVM is loaded, only in the run's own process.
    out = tmp_path / "run"
    script = (
        "import json, sys\n"
        "from baobab.missions.cli.command_line import main\n"
        f"code = main(['run', 'walls_go_to_goal', '--json', '--out', {str(out)!r}])\n"
        "print(json.dumps({'code': code, 'modules': sorted(sys.modules)}))\n"
    )
    lines = _python(script).strip().splitlines()
    result, parent = json.loads(lines[0]), json.loads(lines[-1])
    assert (parent["code"], result["result"]) == (0, "SUCCEEDED")
    assert (out / "plot.png").stat().st_size > 10_000
    assert "matplotlib" in parent["modules"]
    # Nor MuJoCo: what the run sends back (its plot data) is plain data.
    simulation_stack = ("numba", "llvmlite", "mujoco")
    loaded = [name for name in parent["modules"] if name.split(".")[0] in simulation_stack]
    assert loaded == []
    assert "baobab.missions.run.runner" not in parent["modules"]


_PREPARED: list[str] = []


def _prepare() -> None:
    _PREPARED.append(f"prepared in {os.getpid()}")


def _report(payload: dict[str, int], send: Any) -> dict[str, Any]:
    send(("progress", payload["n"]))
    return {"pid": os.getpid(), "prepared": list(_PREPARED), "n": payload["n"]}


def test_a_started_child_prepares_before_it_knows_its_job() -> None:
    child = start_child(_prepare)
    seen: list[Any] = []
    result = child.run(_report, {"n": 7}, seen.append)  # the job and its payload travel
    assert seen == [("progress", 7)]
    assert result["pid"] != os.getpid() and result["n"] == 7
    assert result["prepared"] == [f"prepared in {result['pid']}"]  # there, not here
    assert _PREPARED == []
    child.discard()  # after a job: nothing left to do


def _signal_seen(_payload: None, _send: Any) -> str | None:
    seen: list[int] = []
    signal.signal(signal.SIGTERM, lambda signum, _frame: seen.append(signum))
    handle_forwarded_signals()  # blocked until now: the earlier signal waited
    return signal.Signals(seen[0]).name if seen else None


def test_a_signal_that_came_before_the_job_reaches_it_once_it_handles_signals() -> None:
    child = start_child(lambda: None)
    name = child.run(_signal_seen, None, print, earlier=lambda: signal.SIGTERM)
    assert name == "SIGTERM"


def test_a_started_child_that_gets_no_job_is_ended_and_reaped() -> None:
    child = start_child(lambda: None)
    pid = child._child.pid
    child.discard()
    with pytest.raises(ChildProcessError):  # reaped: no longer this process's child
        os.waitpid(pid, os.WNOHANG)


def test_a_refused_mission_leaves_no_run_process_behind(tmp_path: Path) -> None:
    # `baobab run` forks its run's process before it loads the mission; refused input ends it.
    bad = REPO / "tests" / "bad_inputs" / "missions" / "seed_word.yaml"
    script = (
        "import contextlib, io, json, os\n"
        "from baobab.missions.cli.command_line import main\n"
        "with contextlib.redirect_stderr(io.StringIO()):\n"
        f"    code = main(['run', {str(bad)!r}, '--out', {str(tmp_path / 'run')!r}])\n"
        "children = [c for t in os.listdir('/proc/self/task')\n"
        "            for c in open(f'/proc/self/task/{t}/children').read().split()]\n"
        "print(json.dumps({'code': code, 'children': children}))\n"
    )
    assert json.loads(_python(script)) == {"code": 2, "children": []}
    assert not (tmp_path / "run").exists()


def test_the_run_process_is_forked_before_the_run_command_loads(tmp_path: Path) -> None:
    # The child starts loading the simulation stack while this process parses the arguments
    # and loads the mission language (pydantic) and the mission.
    bad = REPO / "tests" / "bad_inputs" / "missions" / "seed_word.yaml"
    script = (
        "import contextlib, io, json, sys\n"
        "from baobab.missions.run import child_process\n"
        "forks = []\n"
        "real = child_process.start_child\n"
        "def start_child(prepare):\n"
        "    forks.append(sorted(m for m in sys.modules if m.split('.')[0] in\n"
        "                        ('pydantic', 'py_trees', 'yaml', 'baobab')))\n"
        "    return real(prepare)\n"
        "child_process.start_child = start_child\n"
        "from baobab.missions.cli.command_line import main\n"
        "with contextlib.redirect_stderr(io.StringIO()):\n"
        f"    code = main(['run', {str(bad)!r}, '--out', {str(tmp_path / 'run')!r}])\n"
        "print(json.dumps({'code': code, 'forks': forks}))\n"
    )
    report = json.loads(_python(script))
    assert report["code"] == 2 and len(report["forks"]) == 1
    loaded = report["forks"][0]
    assert "baobab.missions.cli.run_command" not in loaded
    assert "pydantic" not in loaded and "py_trees" not in loaded  # its plugin stand-in only


def test_the_run_process_loads_its_stack_with_the_collector_paused_then_frozen() -> None:
    script = (
        "import gc, json\n"
        "from baobab.missions.cli.run_process import prepare_run_process\n"
        "prepare_run_process()\n"
        "print(json.dumps([gc.isenabled(), gc.get_freeze_count() > 100_000]))\n"
    )
    assert json.loads(_python(script)) == [True, True]  # enabled again; the modules' objects frozen
