"""Kernels compiled ahead of time: the warm-up the wheel's build runs (tools/baobab_build.py)."""

from __future__ import annotations

import importlib.util
import tomllib
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from baobab.missions.language.bundled_missions import bundled_missions
from baobab.missions.run import kernel_warmup

REPO = Path(__file__).resolve().parents[1]


def test_the_two_groups_cover_every_bundled_mission_once() -> None:
    mobile, arm = kernel_warmup.missions_by_base()
    assert sorted([*mobile, *arm]) == sorted(bundled_missions())
    assert "panda_pick" in arm and "cafe_delivery" in mobile
    assert "panda_pick" not in mobile and "cafe_delivery" not in arm


def test_the_command_line_expands_groups_and_runs_each_mission(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    asked: list[list[str]] = []
    monkeypatch.setattr(kernel_warmup, "warm_kernels", lambda names: asked.append(names) or [])
    assert kernel_warmup.main(["--arm", "walls_bug2"]) == 0
    assert asked == [["panda_pick", "walls_bug2"]]


def test_a_warm_up_runs_the_mission_to_its_end() -> None:
    (line,) = kernel_warmup.warm_kernels(["walls_go_to_goal"])
    assert line.startswith("walls_go_to_goal: SUCCEEDED after 14.")


def _backend() -> ModuleType:
    path = REPO / "tools" / "baobab_build.py"
    spec = importlib.util.spec_from_file_location("baobab_build", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class _Process:
    """Stands for a warm-up process: records its command, exits with ``code``."""

    def __init__(self, code: int, started: list[tuple[list[str], dict[str, Any]]]) -> None:
        self.code = code
        self.started = started

    def __call__(self, args: list[str], **options: Any) -> _Process:
        self.started.append((args, options))
        self.args = args
        return self

    def wait(self, timeout: float) -> int:
        return self.code


@pytest.mark.parametrize("code", [0, 1])
def test_the_build_step_runs_both_groups_on_the_built_modules(
    code: int,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    backend = _backend()
    started: list[tuple[list[str], dict[str, Any]]] = []
    monkeypatch.setattr(backend.subprocess, "Popen", _Process(code, started))
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "elsewhere"))
    monkeypatch.setenv("PYTHONPATH", "/pip-build-env/site")  # how pip's isolation finds packages
    backend.precompile_kernels(tmp_path)
    assert [args[-2:] for args, _ in started] == [
        ["baobab.missions.run.kernel_warmup", "--mobile"],
        ["baobab.missions.run.kernel_warmup", "--arm"],
    ]
    for _, options in started:
        # The modules being packaged, and numba's cache beside them (the wheel's).
        assert options["cwd"] == tmp_path
        assert options["env"]["PYTHONPATH"] == f"{tmp_path}:/pip-build-env/site"
        assert "NUMBA_CACHE_DIR" not in options["env"]
    warning = capsys.readouterr().err
    assert ("first run compiles them" in warning) is (code != 0)  # the build goes on


def test_editable_installs_and_the_switch_skip_the_build_step(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    backend = _backend()
    compiled: list[Path] = []
    monkeypatch.setattr(backend, "precompile_kernels", compiled.append)
    monkeypatch.setattr(backend.build_py, "run", lambda self: None)
    monkeypatch.delenv("BAOBAB_PRECOMPILE", raising=False)
    command = backend.BuildPyWithKernels.__new__(backend.BuildPyWithKernels)
    command.build_lib = "build/lib"
    command.editable_mode = True
    command.run()
    command.editable_mode = False
    monkeypatch.setenv("BAOBAB_PRECOMPILE", "0")
    command.run()
    assert compiled == []
    monkeypatch.delenv("BAOBAB_PRECOMPILE")
    command.run()
    assert compiled == [Path("build/lib").resolve()]


def test_only_a_wheel_build_asks_for_the_runs_dependencies(monkeypatch: pytest.MonkeyPatch) -> None:
    backend = _backend()
    monkeypatch.setattr(backend.build_meta, "get_requires_for_build_wheel", lambda _: ["wheel"])
    monkeypatch.delenv("BAOBAB_PRECOMPILE", raising=False)
    project = tomllib.loads((REPO / "pyproject.toml").read_text())
    assert project["project"]["dependencies"] == backend.PRECOMPILE_REQUIRES
    assert backend.get_requires_for_build_wheel() == ["wheel", *backend.PRECOMPILE_REQUIRES]
    assert project["build-system"]["requires"] == ["setuptools>=77", "wheel"]  # editable, sdist
    monkeypatch.setenv("BAOBAB_PRECOMPILE", "0")
    assert backend.get_requires_for_build_wheel() == ["wheel"]
