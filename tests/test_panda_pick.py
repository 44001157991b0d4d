"""The scripted pick-and-place, end to end on the physics: seeded cubes, a heavy cube."""

from __future__ import annotations

import pytest

from baobab.robots.panda.pick import PickReport, pick_and_place
from baobab.robots.panda.scene import build_panda_sim, place_target
from baobab.sim.tasks import TaskStatus

STEPS = ["open", "pregrasp", "descend", "close", "lift", "transfer", "lower", "release", "retreat"]


def _pick(seed: int, cube_mass: float | None = None, cube_yaw: float = 0.0) -> PickReport:
    sim, arm = build_panda_sim(seed=seed, cube_mass=cube_mass, cube_yaw=cube_yaw)
    return pick_and_place(sim, arm, place_target(sim)[:2])


def _assert_clean_pick(report: PickReport) -> None:
    assert report.succeeded, report.failure
    assert [step.name for step in report.steps] == STEPS
    assert all(step.status is TaskStatus.SUCCEEDED for step in report.steps)
    assert report.max_lift >= 0.10
    assert report.place_error <= 0.02
    assert report.arm_table_contact_time == 0.0


@pytest.mark.parametrize("seed", range(10))
def test_pick_and_place_succeeds_for_seeded_cube_positions(seed: int) -> None:
    _assert_clean_pick(_pick(seed))


def test_the_hand_holds_a_half_kilogram_cube() -> None:
    report = _pick(seed=42, cube_mass=0.5)
    _assert_clean_pick(report)


def test_the_grasp_turns_to_a_rotated_cube() -> None:
    report = _pick(seed=7, cube_yaw=1.1)
    _assert_clean_pick(report)
