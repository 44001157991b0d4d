"""Start-up cost: which modules a command imports (checked on sys.modules, never on wall time).

Each check runs in a fresh interpreter, since this test process has everything loaded already.
The wall-clock figures live in ``bench/run.py --only startup``.
"""

from __future__ import annotations

import importlib
import json
import subprocess
import sys
from pathlib import Path

import pytest

from baobab.robots.catalog import ENTRY_MODULE, ROBOT_FOLDERS

REPO = Path(__file__).resolve().parents[1]
ON_MAPS = ("office_patrol",)
"""Bundled missions on a map_server map: validating them reads the map's image (numpy, Pillow)
and checks their poses against its walls."""
BUNDLED = sorted(
    str(path) for path in (REPO / "missions").glob("*.yaml") if path.stem not in ON_MAPS
)
LAZY_PACKAGES = (
    "baobab.sim",
    "baobab.nav",
    "baobab.robots.diff_drive",
    "baobab.robots.turtlebot3",
    "baobab.robots.panda",
)

VALIDATE_MUST_NOT_LOAD = (
    "numpy",
    "scipy",
    "mujoco",
    "numba",
    "pinocchio",
    "matplotlib",
    "rich",
    "foxglove",
    "av",
    "baobab.nav",
    "baobab.robots.panda",
    "baobab.robots.diff_drive.base",
    # a loaded mission is valid: validate builds no py_trees tree
    "py_trees",
    # pydantic's plugin discovery, skipped while plugins are disabled
    "importlib.metadata",
    # what only other commands need: `tree`, `schema`, `run`, `teleop`, `nav2`
    "baobab.missions.language.tree_export",
    "baobab.missions.language.json_schema",
    "baobab.missions.run.recording_hook",
    "baobab.missions.cli.teleop_command",
    "baobab.missions.cli.nav2_command",
    "baobab.robots.diff_drive.teleop_terminal",
)
VALIDATE_MAY_LOAD = (
    # the collision monitor's parameter checks (plain Python), for a collision_monitor: block;
    # the package itself is lazy (LAZY_PACKAGES)
    "baobab.nav",
    "baobab.nav.collision_monitor_config",
    "baobab.nav.collision_monitor_geometry",
    "baobab.nav.collision_monitor_params",
)
"""Exceptions to ``VALIDATE_MUST_NOT_LOAD``, by exact module name."""
REFUSED_RUN_MUST_NOT_LOAD = ("numpy", "scipy", "mujoco", "numba", "matplotlib", "baobab.nav")
MOBILE_RUN_MUST_NOT_LOAD = (
    "pinocchio",
    "baobab.robots.panda",
    "matplotlib",
    "rich",
    "foxglove",
    "av",
)


TREE_TICKER = ("baobab.nav", "baobab.nav.direct_tick")
"""What every run loads of the navigation package: the tree ticker the mission tree shares with
the Nav2 trees (the package's ``__init__`` loads nothing on import)."""


def _loaded(script: str) -> list[str]:
    """Run ``script`` in a fresh interpreter; it prints a JSON list of module names last."""
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, cwd=REPO, check=False
    )
    assert done.returncode == 0, done.stderr
    names: list[str] = json.loads(done.stdout.splitlines()[-1])
    return names


REGISTRY_DATA = frozenset(
    name
    for folder in ROBOT_FOLDERS
    for name in (f"baobab.robots.{folder}", f"baobab.robots.{folder}.{ENTRY_MODULE}")
)
"""A robot folder's package (lazy) and its registry entries: data the registry always loads."""


def _matching(loaded: list[str], prefixes: tuple[str, ...]) -> list[str]:
    return sorted(
        name
        for name in loaded
        if name not in REGISTRY_DATA
        and any(name == p or name.startswith(p + ".") for p in prefixes)
    )


def test_validate_of_every_bundled_mission_loads_no_physics_plots_or_navigation() -> None:
    script = (
        "import contextlib, io, json, sys\n"
        "from baobab.missions.cli.command_line import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        f"    code = main(['validate', *{BUNDLED!r}])\n"
        "assert code == 0, code\n"
        "print(json.dumps(sorted(sys.modules)))\n"
    )
    loaded = _loaded(script)
    assert "baobab.missions.language.loader" in loaded  # the check really loaded the missions
    # GPS waypoints are converted to the map while the mission loads, by pymap3d, which
    # imports numpy when it is installed: numpy is the only module a GPS mission adds.
    gps = "farm_gps_patrol" in {Path(path).stem for path in BUNDLED}
    allowed = ("numpy",) if gps else ()
    assert "pymap3d" in loaded or not gps
    refused = _matching(loaded, tuple(m for m in VALIDATE_MUST_NOT_LOAD if m not in allowed))
    assert [name for name in refused if name not in VALIDATE_MAY_LOAD] == []


def test_validate_of_other_robots_and_a_robot_file_loads_no_physics(tmp_path: Path) -> None:
    rover = tmp_path / "rover.yaml"
    rover.write_text(
        "footprint: {polygon: [[0.16, 0.15], [-0.2, 0.15], [-0.2, -0.15], [0.16, -0.15]]}\n"
        "body: {shape: box, length: 0.32, width: 0.26, height: 0.12, bottom: 0.02}\n"
        "wheels: {radius: 0.04, separation: 0.24, width: 0.02, mass: 0.15}\n"
        "casters: [{x: -0.15}, {x: 0.12}]\nmass: 3.0\n"
        "limits: {linear_speed: 0.4, angular_speed: 2.0, linear_accel: 1.0, angular_accel: 4.0}\n"
        "lidar: {x: 0.0, z: 0.2, range_min: 0.12, range_max: 8.0, rate: 10, beams: 360}\n",
        encoding="utf-8",
    )
    mission = tmp_path / "mission.yaml"
    mission.write_text(
        "mission: m\nworld: walls\nrobot: ./rover.yaml\n"
        "tree: {navigate_to_pose: {goal: goal_open}}\n",
        encoding="utf-8",
    )
    farm = str(REPO / "missions" / "farm_rows.yaml")
    script = (
        "import contextlib, io, json, sys\n"
        "from baobab.missions.cli.command_line import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        f"    assert main(['validate', {farm!r}, '--robot', 'turtlebot3_waffle']) == 0\n"
        f"    assert main(['validate', {str(mission)!r}]) == 0\n"
        "print(json.dumps(sorted(sys.modules)))\n"
    )
    loaded = _loaded(script)
    assert "baobab.robots.robot_file" in loaded
    assert _matching(loaded, VALIDATE_MUST_NOT_LOAD) == []


def test_validate_of_a_mission_on_a_map_loads_numpy_for_the_image_and_no_more() -> None:
    missions = [str(REPO / "missions" / f"{name}.yaml") for name in ON_MAPS]
    script = (
        "import contextlib, io, json, sys\n"
        "from baobab.missions.cli.command_line import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        f"    code = main(['validate', *{missions!r}])\n"
        "assert code == 0, code\n"
        "print(json.dumps(sorted(sys.modules)))\n"
    )
    loaded = _loaded(script)
    assert "PIL.Image" in loaded  # the map was read
    assert _matching(loaded, tuple(p for p in VALIDATE_MUST_NOT_LOAD if p != "numpy")) == []


def test_run_refuses_a_bad_mission_before_loading_the_simulation(tmp_path: Path) -> None:
    bad = REPO / "tests" / "bad_inputs" / "missions" / "seed_word.yaml"
    script = (
        "import contextlib, io, json, sys\n"
        "from baobab.missions.cli.command_line import main\n"
        "with contextlib.redirect_stderr(io.StringIO()):\n"
        f"    code = main(['run', {str(bad)!r}, '--out', {str(tmp_path / 'run')!r}])\n"
        "assert code == 2, code\n"
        "print(json.dumps(sorted(sys.modules)))\n"
    )
    loaded = _loaded(script)
    assert "baobab.missions.language.loader" in loaded
    assert _matching(loaded, REFUSED_RUN_MUST_NOT_LOAD) == []


def test_importing_sim_errors_does_not_load_mujoco_or_the_world_loader() -> None:
    script = (
        "import json, sys\n"
        "from baobab.sim.errors import BaobabError\n"
        "import baobab.sim, baobab.nav, baobab.robots.turtlebot3, baobab.robots.panda\n"
        "print(json.dumps(sorted(sys.modules)))\n"
    )
    loaded = _loaded(script)
    assert _matching(loaded, ("mujoco", "pydantic", "numpy", "scipy", "baobab.sim.world")) == []


@pytest.mark.parametrize(
    ("mission", "must_not_load"),
    [
        ("walls_go_to_goal", (*MOBILE_RUN_MUST_NOT_LOAD, "baobab.nav")),  # numba: the base
        ("town_nav_to_pose", MOBILE_RUN_MUST_NOT_LOAD),
    ],
)
def test_a_mobile_run_reaches_its_first_tick_without_arm_or_display_modules(
    mission: str, must_not_load: tuple[str, ...], tmp_path: Path
) -> None:
    # The first progress line is due at the first tree tick: snapshot sys.modules there, in
    # the run's process (SystemExit reaches the parent, which exits with it).
    script = (
        "import json, sys\n"
        "from baobab.missions.run import progress_display as progress\n"
        "def first_tick(self, snapshot):\n"
        "    print(json.dumps(sorted(sys.modules)), flush=True)\n"
        "    raise SystemExit(0)\n"
        "progress.LineSchedule.due = first_tick\n"
        "from baobab.missions.cli.command_line import main\n"
        f"main(['run', {mission!r}, '--out', {str(tmp_path / 'run')!r}])\n"
        "raise SystemExit('the mission never ticked')\n"
    )
    loaded = _loaded(script)
    assert "mujoco" in loaded and "py_trees" in loaded  # it did build the sim and the tree
    assert [name for name in _matching(loaded, must_not_load) if name not in TREE_TICKER] == []


@pytest.mark.parametrize("package", LAZY_PACKAGES)
def test_every_public_name_of_a_lazy_package_resolves(package: str) -> None:
    module = importlib.import_module(package)
    for name in module.__all__:
        value = getattr(module, name)
        assert value is not None
        assert getattr(module, name) is value  # cached after the first look-up
    assert set(module.__all__) <= set(dir(module))
    with pytest.raises(AttributeError, match="no attribute 'not_a_name'"):
        module.not_a_name  # noqa: B018 (the look-up itself is the check)


def test_public_import_paths_keep_working() -> None:
    from baobab.nav import BasicNavigator, TaskResult
    from baobab.robots.panda import build_panda_sim
    from baobab.robots.turtlebot3 import build_turtlebot3_sim
    from baobab.sim import Simulation, load_world
    from baobab.sim.simulation import Simulation as DefinedSimulation

    assert Simulation is DefinedSimulation
    assert load_world("walls").name == "walls"
    assert callable(build_panda_sim) and callable(build_turtlebot3_sim)
    assert BasicNavigator.__name__ == "BasicNavigator" and TaskResult.__name__ == "TaskResult"
