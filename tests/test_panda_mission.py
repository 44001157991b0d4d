"""The bundled Panda mission, and the arm-table contact metric its ``no_contact`` reads."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from baobab.missions.language.loader import load_mission
from baobab.missions.run.runner import run_mission

PANDA_PICK = Path(str(resources.files("baobab.missions"))) / "panda_pick.yaml"

# The tool goes to 10 cm beside the cube, 5 cm above its centre, then 8 cm down: the
# fingertips press into the table top.
PRESS = """\
# yaml-language-server: $schema=mission.schema.json
mission: press
robot: panda
tree:
  sequence:
    - move_to: {relative_to: cube, offset: [0.1, 0, 0.05], orientation: [1, 0, 0, 0]}
    - move_to: {relative_to: tcp, offset: [0, 0, -0.08], duration: 1.0}
timeout: 10
expect:
  no_contact: true
"""


def test_panda_pick_lifts_and_places_the_cube_without_touching_the_table() -> None:
    record = run_mission(load_mission(PANDA_PICK))
    results = {e.name: e for e in record.expectations}
    assert record.exit_code == 0, [e.as_dict() for e in record.expectations]
    assert list(results) == ["result", "no_contact", "object_lifted", "object_placed"]
    assert results["object_lifted"].measured >= 0.14  # the lift is 15 cm
    assert results["object_placed"].measured <= 0.02
    assert record.metrics["contacts"] == 0 and record.metrics["contact_objects"] == []


def test_the_arm_pressing_on_the_table_counts_as_contact(tmp_path: Path) -> None:
    path = tmp_path / "press.yaml"
    path.write_text(PRESS, encoding="utf-8")
    record = run_mission(load_mission(path))
    (no_contact,) = record.expectations
    assert not no_contact.passed and record.exit_code == 1
    assert record.metrics["contact_objects"] == ["table"]
    contacts = record.metrics["contacts"]
    assert isinstance(contacts, int) and contacts > 100  # physics steps at 1 kHz: over 0.1 s
