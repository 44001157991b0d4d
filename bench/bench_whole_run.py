"""What a user waits for, whole processes: `baobab run`, the bundled missions, the scenario suite.

Sections of ``bench/run.py`` (each figure names its mission and its command):

- ``whole``: ``baobab run walls_go_to_goal`` as a whole process, warm, beside a bare
  ``python -c "import mujoco"`` measured in turns with it (medians of ``repeats``);
- ``missions``: every bundled mission as its own ``baobab run M --json`` process, one after
  another: the real-time factor of its loop (the run's ``wall_time``) beside that of its whole
  process, a mission that fails as FAILED, and the whole sequence against the sum of its loops;
- ``suite``: ``pytest missions/ -n 2``, the sum of the missions' sim time over its wall time;
- ``install`` (optional, minutes): a fresh clone, a fresh venv and ``pip install .``, with and
  without the kernels compiled into the wheel, then the first ``baobab run cafe_delivery``
  (and, with ``--with-tests``, the first ``pytest -n 2``, as CI runs it).

Wall-clock figures on a shared machine: each is a median of repeats, or a ratio against a
baseline measured in the same run; the load average is recorded beside them.
"""

from __future__ import annotations

import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
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


def whole_figures(repeats: int = 5) -> list[Figure]:
    """``baobab run walls_go_to_goal``, whole process, warm, against ``import mujoco``."""
    whole: list[float] = []
    bare: list[float] = []
    with tempfile.TemporaryDirectory() as out:
        env = compiled_env(f"{out}/pycache")
        for index in range(repeats + 1):  # the first round warms the bytecode cache
            mujoco = timed_process([sys.executable, "-c", "import mujoco"], env)
            wall, result, _ = run_process("walls_go_to_goal", Path(out) / str(index), env)
            if index and result is not None:
                whole.append(wall)
                bare.append(mujoco)
    command = "baobab run walls_go_to_goal (whole process, warm)"
    if not whole:
        return [
            Figure(
                "whole process walls_go_to_goal",
                float("nan"),
                "s",
                1.0,
                False,
                command,
                failed="the run gave no result",
            )
        ]
    differences = [run - base for run, base in zip(whole, bare, strict=True)]
    return [
        Figure(
            "whole process walls_go_to_goal (median)",
            statistics.median(whole),
            "s",
            1.0,
            False,
            command,
        ),
        Figure(
            "bare python -c 'import mujoco' (median)",
            statistics.median(bare),
            "s",
            None,
            False,
            "python -c 'import mujoco'",
        ),
        Figure(
            "whole process walls_go_to_goal minus import mujoco (median of pairs)",
            statistics.median(differences),
            "s",
            0.5,
            False,
            command,
        ),
    ]


def mission_process_figures(missions: list[str]) -> list[Figure]:
    """Each bundled mission as its own process, one after another: loop and whole RTF."""
    figures: list[Figure] = []
    walls: list[float] = []
    loops: list[float] = []
    with tempfile.TemporaryDirectory() as out:
        env = compiled_env(f"{out}/pycache")
        run_process("walls_go_to_goal", Path(out) / "warm", env)  # bytecode cache
        for name in missions:
            wall, result, stderr = run_process(name, Path(out) / name, env)
            command = f"baobab run {name} --json"
            if result is None or result.get("result") in (None, "ERROR"):
                reason = stderr.strip().splitlines()[-1] if stderr.strip() else "no result"
                figures.append(
                    Figure(
                        f"real-time factor {name}",
                        float("nan"),
                        "x",
                        None,
                        True,
                        command,
                        failed=reason,
                    )
                )
                continue
            sim, loop = float(result["sim_time"]), float(result["wall_time"])
            walls.append(wall)
            loops.append(loop)
            outcome = "" if result["intended"] else f" ({result['result']}, not as intended)"
            figures.append(
                Figure(
                    f"real-time factor {name}, loop{outcome}",
                    sim / loop,
                    "x",
                    20.0 if name == "panda_pick" else 100.0,
                    True,
                    command,
                )
            )
            figures.append(
                Figure(
                    f"real-time factor {name}, whole process", sim / wall, "x", None, True, command
                )
            )
    if loops:
        figures.append(
            Figure(
                f"{len(loops)} bundled missions as processes: whole / sum of loops",
                sum(walls) / sum(loops),
                "ratio",
                2.0,
                False,
                "baobab run M --json, for each bundled mission in turn",
            )
        )
    return figures


def suite_figures() -> list[Figure]:
    """``pytest missions/ -n 2``: sim seconds of the suite per wall second."""
    with tempfile.TemporaryDirectory() as out:
        runs = Path(out) / "runs"
        env = compiled_env(f"{out}/pycache")
        command = [
            sys.executable,
            "-m",
            "pytest",
            "missions/",
            "-n",
            "2",
            "-q",
            "-p",
            "no:cacheprovider",
            "--baobab-runs",
            str(runs),
        ]
        subprocess.run(
            [*command[:4], "--collect-only", "-q"],
            cwd=REPO,
            env=env,
            capture_output=True,
            check=False,
        )  # warm the bytecode cache
        began = time.perf_counter()
        done = subprocess.run(
            command, cwd=REPO, env=env, capture_output=True, text=True, check=False
        )
        wall = time.perf_counter() - began
        results = [json.loads(path.read_text()) for path in runs.glob("*/result.json")]
    sim = sum(float(result["sim_time"]) for result in results)
    loops = sum(float(result["wall_time"]) for result in results)
    failed = None if done.returncode == 0 else (done.stdout.strip().splitlines() or ["?"])[-1]
    return [
        Figure(
            f"pytest missions/ -n 2: sim time of {len(results)} missions / wall",
            sim / wall,
            "x",
            200.0,
            True,
            "pytest missions/ -n 2",
            failed=failed,
        ),
        Figure("pytest missions/ -n 2: wall", wall, "s", None, False, "pytest missions/ -n 2"),
        Figure(
            "pytest missions/ -n 2: wall / (sum of the missions' loops / 2 workers)",
            wall / (loops / 2) if loops else math.nan,
            "ratio",
            None,
            False,
            "pytest missions/ -n 2 (loops: each run's wall_time)",
        ),
    ]


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
