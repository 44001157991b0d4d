"""Simulation clock, periodic callbacks and divergence detection on real MuJoCo models."""

from __future__ import annotations

import math
import os
from pathlib import Path

import mujoco
import numpy as np
import pytest

from baobab.robots.diff_drive.go_to_goal import GoToGoalController, GoToGoalParams
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim import Simulation, SimulationError
from baobab.sim.builder import MOVABLE_GROUP, STATIC_GROUP, geom_ids_in_group, world_spec
from baobab.sim.world import Box, Cylinder, Floor, Pose2D, World

FALLING_BALL = """
<mujoco>
  <option timestep="0.002"/>
  <worldbody>
    <body name="ball" pos="0 0 1"><freejoint name="ball"/><geom size="0.05" mass="1"/></body>
  </worldbody>
</mujoco>
"""


def _ball_sim(seed: int = 0) -> Simulation:
    return Simulation(mujoco.MjModel.from_xml_string(FALLING_BALL), seed=seed)


def test_callbacks_run_at_their_rates_in_sim_time() -> None:
    sim = _ball_sim()
    fast: list[float] = []
    slow: list[float] = []
    sim.every(0.01, fast.append, name="fast")
    sim.every(0.1, slow.append, name="slow", first_call=0.05)
    sim.step_for(1.0)
    assert sim.time == pytest.approx(1.0)
    assert len(fast) == 100
    assert fast[:3] == pytest.approx([0.0, 0.01, 0.02])
    assert slow == pytest.approx([0.05 + 0.1 * k for k in range(10)])


def test_callbacks_due_together_run_in_registration_order() -> None:
    sim = _ball_sim()
    order: list[str] = []
    sim.every(0.02, lambda t: order.append("a"), name="a")
    sim.every(0.01, lambda t: order.append("b"), name="b")
    sim.step_for(0.02)
    assert order == ["a", "b", "b"]


def test_cancelled_callback_stops() -> None:
    sim = _ball_sim()
    calls: list[float] = []
    handle = sim.every(0.01, calls.append, name="c")
    sim.step_for(0.05)
    handle.cancel()
    handle.cancel()
    sim.step_for(0.05)
    assert len(calls) == 5


def test_physics_follows_gravity_between_callbacks() -> None:
    sim = _ball_sim()
    sim.step_for(0.2)
    height = float(sim.data.body("ball").xpos[2])
    assert height == pytest.approx(1.0 - 0.5 * 9.81 * 0.2**2, abs=2e-3)


@pytest.mark.parametrize("period", [0.003, -0.01, 0.0, float("nan")])
def test_period_must_be_a_positive_multiple_of_the_step(period: float) -> None:
    sim = _ball_sim()
    with pytest.raises(SimulationError):
        sim.every(period, lambda t: None, name="bad")


def test_non_finite_state_raises_simulation_error() -> None:
    sim = _ball_sim()
    sim.data.joint("ball").qvel[0] = np.inf
    with pytest.raises(SimulationError, match="diverged"):
        sim.step_for(0.01)


def test_identical_runs_are_bitwise_identical() -> None:
    def run() -> np.ndarray:
        sim = _ball_sim()
        sim.data.joint("ball").qvel[:3] = [0.3, -0.2, 0.0]
        sim.step_for(0.5)
        return sim.data.qpos.copy()

    assert np.array_equal(run(), run())


def test_world_spec_builds_floor_obstacles_and_movable_slots() -> None:
    world = World(
        name="room",
        floor=Floor(size=(6.0, 4.0)),
        boxes=[Box(name="wall", center=(1.0, 0.0), size=(0.1, 2.0), yaw=0.3)],
        cylinders=[Cylinder(name="table", center=(-1.0, 1.0), radius=0.4)],
        spawns={"default": Pose2D(x=0.0, y=0.0)},
    )
    model = world_spec(world, movable_slots=3).compile()
    assert model.geom("wall").size[2] == pytest.approx(0.25)
    assert model.geom("table").size[0] == pytest.approx(0.4)
    assert len(geom_ids_in_group(model, STATIC_GROUP)) == 2
    assert len(geom_ids_in_group(model, MOVABLE_GROUP)) == 3
    sim = Simulation(model)
    sim.step_for(0.1)
    assert sim.data.ncon == 0


def test_a_non_finite_state_read_by_a_controller_is_a_simulation_error(tmp_path: Path) -> None:
    # A NaN written between steps reaches the controllers before MuJoCo's own check: the
    # controller's ValueError must surface as the SimulationError it really is, and MuJoCo
    # must not write MUJOCO_LOG.TXT into the working directory.
    sim, robot = build_turtlebot3_sim("walls")
    controller = GoToGoalController(sim, robot.base, GoToGoalParams())
    controller.set_goal(2.0, 2.0)
    sim.step_for(0.5)
    sim.data.joint(robot.names.root_joint).qpos[0] = math.nan
    with pytest.raises(SimulationError, match="non-finite qpos"):
        sim.step_for(0.1)
    sim.data.joint(robot.names.root_joint).qpos[0] = 0.0
    sim.data.joint(robot.names.root_joint).qvel[0] = math.inf
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        with pytest.raises(SimulationError):
            sim.step_for(0.1)
    finally:
        os.chdir(cwd)
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
