"""Many runs in one process: nothing a run leaves behind changes the next one, nothing piles up.

A mission run after a different one (lidar noise, a spawned obstacle marking the costmaps) is
the same run as in a fresh process; py_trees' process-global blackboard is empty after a run;
a navigator made again starts from the static costmaps; runs draw only from their own seeded
generator; and sequential runs leave no simulation alive. The memory figures over hundreds of
runs, and the drift over hours, are measured in bench/bench_longrun.py.
"""

from __future__ import annotations

import gc
import random
import weakref
from collections.abc import Callable, Iterator
from pathlib import Path

import mujoco
import numpy as np
import py_trees
import pytest

from baobab.missions.language.loader import load_mission
from baobab.missions.run.runner import RunRecord, run_mission
from baobab.missions.run.tick_loop import ProgressSnapshot
from baobab.nav import BasicNavigator
from baobab.nav.msgs import pose_stamped
from baobab.sim.builder import movable_slot_name
from baobab.sim.simulation import Simulation
from baobab.sim.world import bundled_world_path, load_world

HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
MISSION_A = (
    HEADER
    + """\
mission: short_hop
world: walls
robot: turtlebot3
seed: 4
tree:
  navigate_to_pose: {x: 0.8, y: 0.6}
timeout: 30
"""
)
MISSION_B = (
    HEADER
    + """\
mission: noisy_detour
world: walls
robot: turtlebot3
start: {x: 0.0, y: -1.0}
seed: 9
noise: {lidar_std: 0.03}
events:
  - {at: 0.5, spawn_obstacle: {name: crate, x: 0.9, y: -0.4, size: [0.3, 0.3, 0.5]}}
tree:
  sequence:
    - navigate_to_pose: {x: 1.4, y: -1.2}
    - clear_costmaps: local
timeout: 40
"""
)


@pytest.fixture
def missions(tmp_path: Path) -> dict[str, Path]:
    paths = {"A": tmp_path / "a.yaml", "B": tmp_path / "b.yaml"}
    paths["A"].write_text(MISSION_A)
    paths["B"].write_text(MISSION_B)
    return paths


def run(path: Path, seed: int | None = None, **options: object) -> RunRecord:
    return run_mission(load_mission(path), seed=seed, **options)  # type: ignore[arg-type]


def fingerprint(record: RunRecord) -> tuple[object, ...]:
    outcome = record.outcome
    return (outcome.result, outcome.error_code, outcome.sim_time, record.trace_digest)


def test_a_run_after_a_different_one_is_the_run_of_a_fresh_process(
    missions: dict[str, Path],
) -> None:
    first = run(missions["A"])
    other = run(missions["B"])
    again = run(missions["A"])
    assert first.outcome.result == "SUCCEEDED" and other.outcome.result == "SUCCEEDED"
    assert "crate" in other.trace.text()  # B did spawn its obstacle
    assert fingerprint(again) == fingerprint(first)
    assert again.metrics == first.metrics


def test_the_blackboard_holds_nothing_after_a_run(missions: dict[str, Path]) -> None:
    # A node writing to py_trees' global blackboard mid-run, as user behaviours may do.
    writer = py_trees.blackboard.Client(name="writer")
    writer.register_key(key="seen", access=py_trees.common.Access.WRITE)

    class WritingSink:
        def update(self, snapshot: ProgressSnapshot) -> None:
            writer.seen = snapshot.sim_time

    run(missions["A"], progress=WritingSink())
    blackboard = py_trees.blackboard.Blackboard
    assert blackboard.storage == {}
    assert blackboard.clients == {} and blackboard.metadata == {}


def test_runs_draw_only_from_their_own_seeded_generator(missions: dict[str, Path]) -> None:
    np.random.seed(11)
    random.seed(11)
    numpy_state, python_state = np.random.get_state(), random.getstate()
    noisy = run(missions["B"], seed=21)
    # The process-wide generators are untouched: no run depends on what ran before it.
    after = np.random.get_state()
    assert all(np.array_equal(a, b) for a, b in zip(after, numpy_state, strict=True))
    assert random.getstate() == python_state
    same_seed = run(missions["B"], seed=21)
    other_seed = run(missions["B"], seed=22)
    assert fingerprint(same_seed) == fingerprint(noisy)
    assert other_seed.trace_digest != noisy.trace_digest  # the noise is really drawn


def costmap_bytes(navigator: BasicNavigator) -> tuple[bytes, bytes]:
    return bytes(navigator.getGlobalCostmap().data), bytes(navigator.getLocalCostmap().data)


def test_a_navigator_made_again_starts_from_the_static_costmaps() -> None:
    first = BasicNavigator(world="walls", seed=3)
    initial = costmap_bytes(first)
    sim = first.server.sim
    crate = sim.model.body(movable_slot_name(0))
    sim.data.mocap_pos[crate.mocapid[0]] = [0.5, -0.6, 0.25]  # beside the route, in view
    mujoco.mj_forward(sim.model, sim.data)
    first.goToPose(pose_stamped(1.0, 0.0))
    for _ in range(10):
        first.isTaskComplete()
    marked = costmap_bytes(first)
    assert marked[0] != initial[0] and marked[1] != initial[1]  # the crate is in both
    first.lifecycleShutdown()
    first.destroy_node()
    second = BasicNavigator(world="walls", seed=3)
    try:
        assert costmap_bytes(second) == initial
    finally:
        second.destroy_node()


@pytest.fixture
def live_simulations(monkeypatch: pytest.MonkeyPatch) -> Iterator[Callable[[], int]]:
    """Counts the Simulation and MjData objects still alive, by weak reference."""
    references: list[weakref.ref[object]] = []
    build = Simulation.__init__

    def tracked_init(self: Simulation, *args: object, **kwargs: object) -> None:
        build(self, *args, **kwargs)  # type: ignore[arg-type]
        references.extend((weakref.ref(self), weakref.ref(self.data)))

    monkeypatch.setattr(Simulation, "__init__", tracked_init)

    def alive() -> int:
        gc.collect()
        assert references, "no simulation was built"
        return sum(reference() is not None for reference in references)

    yield alive


def test_sequential_runs_leave_no_simulation_alive(
    missions: dict[str, Path], live_simulations: Callable[[], int]
) -> None:
    records = [run(missions["A"]) for _ in range(10)]
    assert len({fingerprint(record) for record in records}) == 1
    assert live_simulations() == 0  # the records keep the results, not the simulations


def test_destroyed_navigators_leave_no_simulation_alive(
    live_simulations: Callable[[], int],
) -> None:
    for _ in range(5):
        navigator = BasicNavigator(world="walls", seed=3)
        navigator.get_logger().set_level(40)
        navigator.goToPose(pose_stamped(0.8, 0.6))
        while not navigator.isTaskComplete():
            pass
        navigator.lifecycleShutdown()
        navigator.destroy_node()
    del navigator
    assert live_simulations() == 0


def test_a_world_file_loaded_again_is_shared_until_its_text_changes(tmp_path: Path) -> None:
    text = bundled_world_path("walls").read_text()
    path = tmp_path / "room.yaml"
    path.write_text(text)
    first = load_world(path)
    assert load_world(path) is first  # immutable, parsed once per process
    path.write_text(text.replace("name: walls", "name: wallz", 1))  # same size, same instant
    changed = load_world(path)
    assert changed.name == "wallz" and first.name == "walls"
