"""baobab's build backend: setuptools, and a wheel that carries the kernels compiled here.

``pip install .`` builds a wheel on this machine. After the modules are copied into the build
folder, the bundled missions run once on those copies (:mod:`baobab.missions.run.kernel_warmup`),
so numba writes the kernels' machine code into the ``__pycache__`` folders that go into the
wheel, and the first ``baobab run`` after the install loads them instead of compiling for a
quarter of a minute or more (see the README's figures). The mobile robot's missions and the
arm's run in two processes, one per core. When this fails (say a dependency has no build for
this platform) the build goes on and the first run compiles, as it would without this step.

Only a wheel's build needs the run's dependencies (:data:`PRECOMPILE_REQUIRES`); editable
installs and sdists skip the step and need only setuptools, and so does any build with
``BAOBAB_PRECOMPILE=0``. ``setup.py`` puts :class:`BuildPyWithKernels` in place.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

from setuptools import build_meta
from setuptools.command.build_py import build_py

PROJECT_FILE = Path(__file__).resolve().parents[1] / "pyproject.toml"


def _run_dependencies() -> list[str]:
    """pyproject.toml's run dependencies: what running the bundled missions may load."""
    with PROJECT_FILE.open("rb") as file:
        return list(tomllib.load(file)["project"]["dependencies"])


PRECOMPILE_REQUIRES = _run_dependencies()
"""What a wheel's build installs to run the bundled missions: all of the project's run
dependencies (a hand-kept subset fell behind when a mission came to need pymap3d, and the
wheels then shipped no kernels)."""


def precompiling() -> bool:
    """Whether wheels built now carry compiled kernels (``BAOBAB_PRECOMPILE=0``: no)."""
    return os.environ.get("BAOBAB_PRECOMPILE") != "0"


def get_requires_for_build_wheel(config_settings: dict[str, Any] | None = None) -> list[str]:
    """setuptools' requirements, and the run's for the kernels' compilation."""
    requires = list(build_meta.get_requires_for_build_wheel(config_settings))
    return requires + (PRECOMPILE_REQUIRES if precompiling() else [])


get_requires_for_build_sdist = build_meta.get_requires_for_build_sdist
get_requires_for_build_editable = build_meta.get_requires_for_build_editable
prepare_metadata_for_build_wheel = build_meta.prepare_metadata_for_build_wheel
prepare_metadata_for_build_editable = build_meta.prepare_metadata_for_build_editable
build_wheel = build_meta.build_wheel
build_sdist = build_meta.build_sdist
build_editable = build_meta.build_editable

PRECOMPILE_TIMEOUT = 1800.0
"""Seconds the kernels may take to compile on a slow machine before the build goes on."""


class BuildPyWithKernels(build_py):
    """build_py, then the kernels compiled into the build folder's ``__pycache__``."""

    def run(self) -> None:
        super().run()
        if getattr(self, "editable_mode", False) or not precompiling():
            return
        precompile_kernels(Path(self.build_lib).resolve())


def precompile_kernels(build_lib: Path) -> None:
    """Run the bundled missions on the modules in ``build_lib``; warn and go on if it fails."""
    # The built modules first; then what was on the path: pip's isolated build environment
    # reaches its packages (the run's dependencies) through PYTHONPATH.
    path = [str(build_lib), *filter(None, [os.environ.get("PYTHONPATH")])]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(path), PYTHONDONTWRITEBYTECODE="1")
    env.setdefault("MUJOCO_GL", "egl")
    for variable in ("NUMBA_CACHE_DIR", "NUMBA_DISABLE_JIT", "PYTHONPYCACHEPREFIX"):
        env.pop(variable, None)
    print("compiling baobab's kernels for this machine (about half a minute)", flush=True)
    command = [sys.executable, "-m", "baobab.missions.run.kernel_warmup"]
    groups = [
        subprocess.Popen([*command, group], cwd=build_lib, env=env, stdout=subprocess.DEVNULL)
        for group in ("--mobile", "--arm")
    ]
    failed = []
    for group in groups:
        try:
            if group.wait(timeout=PRECOMPILE_TIMEOUT) != 0:
                failed.append(" ".join(map(str, group.args[-1:])))
        except subprocess.TimeoutExpired:
            group.kill()
            group.wait()
            failed.append(f"{group.args[-1]} (timed out)")
    if failed:
        print(
            f"warning: baobab's kernels ({', '.join(failed)}) were not compiled ahead of time; "
            "the first run compiles them",
            file=sys.stderr,
        )
