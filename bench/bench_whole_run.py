"""What a user waits for, whole processes: `baobab run`, the bundled missions, the scenario suite.

Sections of ``bench/run.py`` (each figure names its mission and its command):

- ``whole``: ``baobab run walls_go_to_goal`` as a whole process, warm, beside a bare
  ``python -c "import mujoco"`` measured in turns with it (medians of ``repeats``): with the
  run server running, as after a first run (``missions/cli/run_server.py``), and without;
- ``missions``: every bundled mission as its own ``baobab run M --json`` process, one after
  another: the real-time factor of its loop (the run's ``wall_time``) beside that of its whole
  process, a mission that fails as FAILED, and the whole sequence against the sum of its loops,
  with the run server and without;
- ``suite``: ``pytest missions/ -n 2``, the sum of the missions' sim time over its wall time;
- ``install`` (optional, minutes): a fresh clone, a fresh venv and ``pip install .``, with and
  without the kernels compiled into the wheel, then the first ``baobab run cafe_delivery``
  (and, with ``--with-tests``, the first ``pytest -n 2``, as CI runs it).

Wall-clock figures on a shared machine: each is a median of repeats, or a ratio against a
baseline measured in the same run; the load average is recorded beside them.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]


@dataclass
class Figure:
    """One measured figure and its target; ``failed`` when it could not be measured."""

    name: str
    value: float
    unit: str
    target: float | None
    higher_is_better: bool
    command: str
    failed: str | None = None

    @property
    def met(self) -> bool | None:
        """True when the value reaches the target (None: no target)."""
        if self.failed is not None:
            return False
        if self.target is None:
            return None
        if self.higher_is_better:
            return self.value >= self.target
        return self.value <= self.target


def baobab_command(python: str = sys.executable) -> list[str]:
    """The ``baobab`` console script beside ``python``."""
    return [str(Path(python).with_name("baobab"))]


def compiled_env(cache: str) -> dict[str, str]:
    """The environment of an installed baobab: modules compiled to bytecode once, then reused.

    A development shell may set PYTHONDONTWRITEBYTECODE (this one does), which makes every
    process compile baobab's modules from source again (~0.1 s at start-up); the bytecode goes
    to a private cache here instead of the source tree.
    """
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPYCACHEPREFIX"] = cache
    env.setdefault("MUJOCO_GL", "egl")
    return env


@contextlib.contextmanager
def run_server(env: dict[str, str]) -> Iterator[dict[str, str]]:
    """A run server for ``env`` (as the first ``baobab run`` starts one), ready to serve; the
    environment that reaches it. Stopped on the way out."""
    from baobab.missions.cli.run_server_protocol import server_command, socket_path

    folder = tempfile.mkdtemp(prefix="bb-", dir="/tmp")  # socket paths are short
    served = {**env, "BAOBAB_RUN_SERVER": "1", "BAOBAB_RUN_SERVER_DIR": folder}
    path = socket_path(served)
    assert path is not None
    server = subprocess.Popen(
        server_command(path),
        env=served,
        stdin=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert server.stderr is not None and "serving" in server.stderr.readline()
        yield served
    finally:
        server.terminate()
        server.wait(timeout=60)
        shutil.rmtree(folder, ignore_errors=True)


def without_server(env: dict[str, str]) -> dict[str, str]:
    """``env`` with the run server off: each ``baobab run`` loads everything itself."""
    return {**env, "BAOBAB_RUN_SERVER": "0"}


def timed_process(command: list[str], env: dict[str, str], cwd: Path | None = None) -> float:
    """Wall seconds of ``command`` (output dropped)."""
    began = time.perf_counter()
    subprocess.run(command, env=env, cwd=cwd, capture_output=True, check=False)
    return time.perf_counter() - began


def run_process(
    mission: str, out: Path, env: dict[str, str], python: str = sys.executable
) -> tuple[float, dict[str, Any] | None, str]:
    """``baobab run MISSION --json``: (process wall s, its result or None, its stderr)."""
    began = time.perf_counter()
    done = subprocess.run(
        [*baobab_command(python), "run", mission, "--json", "--out", str(out)],
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    wall = time.perf_counter() - began
    try:
        result = json.loads(done.stdout.strip().splitlines()[-1])
    except (IndexError, json.JSONDecodeError):
        result = None
    return wall, result, done.stderr


def children_cpu() -> float:
    """CPU seconds (user + system) of this process's ended and reaped children so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _whole_rounds(env: dict[str, str], out: Path, repeats: int) -> dict[str, list[float]]:
    """``repeats`` rounds of ``import mujoco`` then ``baobab run walls_go_to_goal`` (after one
    round that warms the bytecode cache): wall and CPU seconds of each, the CPU of ended
    children (a run server's worker is not this process's child: not counted)."""
    rounds: dict[str, list[float]] = {"whole": [], "bare": [], "whole_cpu": [], "bare_cpu": []}
    for index in range(repeats + 1):
        before = children_cpu()
        mujoco = timed_process([sys.executable, "-c", "import mujoco"], env)
        between = children_cpu()
        wall, result, _ = run_process("walls_go_to_goal", out / str(index), env)
        if index and result is not None:
            rounds["whole"].append(wall)
            rounds["bare"].append(mujoco)
            rounds["bare_cpu"].append(between - before)
            rounds["whole_cpu"].append(children_cpu() - between)
    return rounds


def whole_figures(repeats: int = 5) -> list[Figure]:
    """``baobab run walls_go_to_goal``, whole process, warm, against ``import mujoco``: with
    the run server running (as after a first run), and without one (``BAOBAB_RUN_SERVER=0``:
    the wall and CPU seconds of the process and its run's process)."""
    command = "baobab run walls_go_to_goal (whole process, warm)"
    with tempfile.TemporaryDirectory() as out:
        env = compiled_env(f"{out}/pycache")
        with run_server(env) as served_env:
            served = _whole_rounds(served_env, Path(out) / "served", repeats)
        alone = _whole_rounds(without_server(env), Path(out) / "alone", repeats)
    if not served["whole"] or not alone["whole"]:
        failed = "the run gave no result"
        return [
            Figure("whole process walls_go_to_goal", math.nan, "s", 1.0, False, command, failed)
        ]
    figures = []
    for label, rounds, targets in (
        ("run server", served, (1.0, 0.5)),
        ("no run server", alone, (None, None)),
    ):
        differences = [
            run - bare for run, bare in zip(rounds["whole"], rounds["bare"], strict=True)
        ]
        figures += [
            Figure(
                f"whole process walls_go_to_goal, {label} (median)",
                statistics.median(rounds["whole"]),
                "s",
                targets[0],
                False,
                command + ("" if label == "run server" else ", BAOBAB_RUN_SERVER=0"),
            ),
            Figure(
                f"whole process walls_go_to_goal, {label}, minus import mujoco (median of pairs)",
                statistics.median(differences),
                "s",
                targets[1],
                False,
                command,
            ),
        ]
    return [
        *figures,
        Figure(
            "bare python -c 'import mujoco' (median)",
            statistics.median(served["bare"] + alone["bare"]),
            "s",
            None,
            False,
            "python -c 'import mujoco'",
        ),
        Figure(
            "CPU of baobab run walls_go_to_goal, no run server, both processes (median)",
            statistics.median(alone["whole_cpu"]),
            "s",
            None,
            False,
            command,
        ),
        Figure(
            "CPU of python -c 'import mujoco' (median)",
            statistics.median(alone["bare_cpu"]),
            "s",
            None,
            False,
            "python -c 'import mujoco'",
        ),
    ]


def _mission_sequence(
    missions: list[str], env: dict[str, str], out: Path
) -> tuple[list[Figure], list[float], list[float]]:
    """Each mission as a ``baobab run M --json`` process in turn: its figures (loop and whole
    real-time factors, or FAILED), and the whole and loop wall seconds of those that ran."""
    figures: list[Figure] = []
    walls: list[float] = []
    loops: list[float] = []
    run_process("walls_go_to_goal", out / "warm", env)  # bytecode cache
    for name in missions:
        wall, result, stderr = run_process(name, out / name, env)
        command = f"baobab run {name} --json"
        if result is None or result.get("result") in (None, "ERROR"):
            reason = stderr.strip().splitlines()[-1] if stderr.strip() else "no result"
            figures.append(
                Figure(f"real-time factor {name}", math.nan, "x", None, True, command, reason)
            )
            continue
        sim, loop = float(result["sim_time"]), float(result["wall_time"])
        walls.append(wall)
        loops.append(loop)
        outcome = "" if result["intended"] else f" ({result['result']}, not as intended)"
        target = 20.0 if name == "panda_pick" else 100.0
        figures.append(
            Figure(
                f"real-time factor {name}, loop{outcome}", sim / loop, "x", target, True, command
            )
        )
        figures.append(
            Figure(f"real-time factor {name}, whole process", sim / wall, "x", None, True, command)
        )
    return figures, walls, loops


def mission_process_figures(missions: list[str]) -> list[Figure]:
    """Each bundled mission as its own process, one after another, with the run server
    running: loop and whole real-time factors, and the whole sequence against the sum of its
    loops; the same sequence without a run server beside it."""
    command = "baobab run M --json, for each bundled mission in turn"
    with tempfile.TemporaryDirectory() as out:
        env = compiled_env(f"{out}/pycache")
        with run_server(env) as served_env:
            figures, walls, loops = _mission_sequence(missions, served_env, Path(out) / "served")
        _, alone_walls, alone_loops = _mission_sequence(
            missions, without_server(env), Path(out) / "alone"
        )
    for label, whole, loop, target in (
        ("run server", walls, loops, 2.0),
        ("no run server", alone_walls, alone_loops, None),
    ):
        if loop:
            figures.append(
                Figure(
                    f"{len(loop)} bundled missions as processes, {label}: whole / sum of loops",
                    sum(whole) / sum(loop),
                    "ratio",
                    target,
                    False,
                    command + ("" if target else ", BAOBAB_RUN_SERVER=0"),
                )
            )
    return figures


def _suite_session(out: Path, name: str, env: dict[str, str]) -> tuple[float, list[dict], str]:
    """One ``pytest missions/ -n 2`` session with its cache in ``out``: (wall s, the runs'
    results, the last line when it failed else "")."""
    runs = out / name
    command = [sys.executable, "-m", "pytest", "missions/", "-n", "2", "-q"]
    options = ["-p", "no:hypothesispytest", "-o", f"cache_dir={out / 'cache'}"]
    began = time.perf_counter()
    done = subprocess.run(
        [*command, *options, "--baobab-runs", str(runs)],
        cwd=REPO,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    wall = time.perf_counter() - began
    results = [json.loads(path.read_text()) for path in runs.glob("*/result.json")]
    failed = "" if done.returncode == 0 else (done.stdout.strip().splitlines() or ["?"])[-1]
    return wall, results, failed


def suite_figures() -> list[Figure]:
    """``pytest missions/ -n 2``: sim seconds of the suite per wall second, twice, after a
    session that warms the bytecode cache (as an install's compiled modules are warm): a first
    session (no pytest cache: the workers take the scenarios longest first by their timeouts)
    and a second one (by the loop times the first one kept in pytest's cache)."""
    figures: list[Figure] = []
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder)
        env = compiled_env(f"{out}/pycache")
        warm = out / "warm"  # a session of its own (its own pytest cache): the bytecode cache
        warm.mkdir()
        _suite_session(warm, "warm", env)
        for session in ("first session", "second session, longest first"):
            wall, results, failed = _suite_session(out, session.split(",")[0], env)
            sim = sum(float(result["sim_time"]) for result in results)
            loops = sum(float(result["wall_time"]) for result in results)
            command = "pytest missions/ -n 2"
            figures += [
                Figure(
                    f"pytest missions/ -n 2 ({session}): sim time of {len(results)} "
                    "missions / wall",
                    sim / wall,
                    "x",
                    200.0,
                    True,
                    command,
                    failed=failed or None,
                ),
                Figure(f"pytest missions/ -n 2 ({session}): wall", wall, "s", None, False, command),
                Figure(
                    f"pytest missions/ -n 2 ({session}): wall / (sum of loops / 2 workers)",
                    wall / (loops / 2) if loops else math.nan,
                    "ratio",
                    None,
                    False,
                    f"{command} (loops: each run's wall_time)",
                ),
            ]
    return figures


def _fresh_install(folder: Path, extra: str, env: dict[str, str]) -> tuple[str, float, Path]:
    """A fresh clone of this repository and a fresh venv with ``pip install EXTRA`` in it.

    Returns:
        The venv's python, the install's wall time (s) and the clone.
    """
    clone = folder / "clone"
    subprocess.run(["git", "clone", "-q", str(REPO), str(clone)], check=True)
    venv = folder / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    python = str(venv / "bin" / "python")
    return python, timed_process([python, "-m", "pip", "install", "-q", extra], env, clone), clone


def install_figures(with_tests: bool = False) -> list[Figure]:
    """A fresh clone and venv, ``pip install .``, then the first run (cold kernel caches).

    Twice: as built (the wheel carries the kernels compiled at its build) and with
    ``BAOBAB_PRECOMPILE=0`` (the first run compiles them), so both options are measured in
    the same run. With ``with_tests``, also CI's order in another fresh clone and venv:
    ``pip install ".[dev]"``, then the first ``pytest -n 2``.
    """
    figures: list[Figure] = []
    for precompiled in (True, False):
        label = "kernels in the wheel" if precompiled else "kernels compiled by the first run"
        env = dict(os.environ, BAOBAB_PRECOMPILE="1" if precompiled else "0", MUJOCO_GL="egl")
        for variable in ("NUMBA_CACHE_DIR", "PYTHONPYCACHEPREFIX", "PYTHONDONTWRITEBYTECODE"):
            env.pop(variable, None)
        with tempfile.TemporaryDirectory() as folder:
            python, install, _ = _fresh_install(Path(folder), ".", env)
            figures.append(
                Figure(
                    f"pip install . in a fresh venv ({label})",
                    install,
                    "s",
                    None,
                    False,
                    "pip install .",
                )
            )
            wall, result, stderr = run_process("cafe_delivery", Path(folder) / "run", env, python)
            figures.append(
                Figure(
                    f"first baobab run cafe_delivery after the install ({label})",
                    wall,
                    "s",
                    5.0 if precompiled else None,
                    False,
                    "baobab run cafe_delivery",
                    failed=None if result else (stderr.strip().splitlines() or ["?"])[-1],
                )
            )
        if not with_tests:
            continue
        with tempfile.TemporaryDirectory() as folder:
            python, install, clone = _fresh_install(Path(folder), ".[dev]", env)
            figures.append(
                Figure(
                    f'pip install ".[dev]" in a fresh venv ({label})',
                    install,
                    "s",
                    None,
                    False,
                    'pip install ".[dev]"',
                )
            )
            suite = timed_process([python, "-m", "pytest", "-n", "2", "-q"], env, clone)
            figures.append(
                Figure(
                    f"first pytest -n 2 on a fresh clone ({label})",
                    suite,
                    "s",
                    None,
                    False,
                    "pytest -n 2 (as .ci/run)",
                )
            )
    return figures
