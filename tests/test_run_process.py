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
from baobab.missions.run.child_process import ChildProcessDiedError, run_in_child
from baobab.sim.errors import BaobabError

REPO = Path(__file__).resolve().parents[1]


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
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, cwd=REPO, check=False
    )
    assert done.returncode == 0, done.stderr
    lines = done.stdout.strip().splitlines()
    result, parent = json.loads(lines[0]), json.loads(lines[-1])
    assert (parent["code"], result["result"]) == (0, "SUCCEEDED")
    assert (out / "plot.png").stat().st_size > 10_000
    assert "matplotlib" in parent["modules"]
    loaded = [name for name in parent["modules"] if name.split(".")[0] in ("numba", "llvmlite")]
    assert loaded == []
    assert "baobab.missions.run.runner" not in parent["modules"]
