"""Mission loading: the fixtures load, and each kind of mistake is one located line.

The malformed missions are small YAML strings; each row names the exact ``line:col`` the
error must point at and a fragment of its message. Line 1 of each is the editor comment.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
import yaml

from baobab.missions.cli.command_line import main
from baobab.missions.language.errors import MissionError
from baobab.missions.language.loader import load_mission
from baobab.sim.errors import SourceError

FIXTURES = Path(__file__).parent / "missions"
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
# Lines 2-7; a case's own text starts on line 8.
WALLS = """mission: m
world: walls
robot: turtlebot3
locations:
  dock: {x: 0.5, y: 0.5}
  corner: {x: 2.0, y: 2.0}
"""
# Lines 2-6; a case's own text starts on line 7.
PANDA = """mission: m
robot: panda
locations:
  above: {position: [0.5, 0.0, 0.7], orientation: [1, 0, 0, 0]}
  flat: {x: 0.5, y: 0.0}
"""
SUBTREE = """subtrees:
  deliver:
    params:
      t: {type: int, choices: [1, 2]}
    tree: {wait: "${t}"}
"""
WAIT_TREE = "tree: {wait: 1}\n"


def _write(folder: Path, text: str, name: str = "mission.yaml") -> Path:
    path = folder / name
    path.write_text(text)
    return path


MALFORMED = [
    # (id, text after the header, line:col, message fragment)
    ("unknown top-level key", WALLS + "tre: {wait: 1}\n", "8:1",
     "unknown top-level key 'tre'; did you mean 'tree'?"),
    ("missing tree", WALLS, "2:1", "missing required key 'tree'"),
    ("duplicate key", WALLS + WAIT_TREE + WAIT_TREE, "9:1", "duplicate key 'tree'"),
    ("unknown robot", "mission: m\nworld: walls\nrobot: turtlebot\n" + WAIT_TREE, "4:1",
     "unknown robot 'turtlebot'; did you mean 'turtlebot4'? valid: panda, turtlebot3,"),
    ("unknown world", "mission: m\nworld: wals\nrobot: turtlebot3\n" + WAIT_TREE, "3:1",
     "unknown world 'wals'; did you mean 'walls'?"),
    ("mobile robot without world", "mission: m\nrobot: turtlebot3\n" + WAIT_TREE, "3:1",
     "robot 'turtlebot3' needs a world"),
    ("unknown behaviour", WALLS + "tree:\n  sequence:\n    - navigate_to_pos: dock\n", "10:7",
     "unknown behaviour 'navigate_to_pos'; did you mean 'navigate_to_pose'? valid: "),
    ("unknown location", WALLS + "tree:\n  navigate_to_pose: dok\n", "9:3",
     "unknown location 'dok'; did you mean 'dock'? valid: corner, default, dock, goal_"),
    ("node is a bare string", WALLS + "tree:\n  sequence:\n    - always_success\n", "10:7",
     "expected a node {type: parameters}, got 'always_success' (write 'always_success: {}'"),
    ("node with two keys", WALLS + "tree:\n  sequence:\n    - wait: 1\n      spin: 1\n",
     "11:7", "a node has exactly one key, its type; found wait, spin"),
    ("wrong parameter type", WALLS + "tree:\n  wait: {duration: soon}\n", "9:10",
     "wait.duration: Input should be a valid number"),
    ("unknown parameter", WALLS + "tree:\n  wait: {duraton: 5}\n", "9:10",
     "unknown parameter 'duraton' in wait; did you mean 'duration'? valid: duration, name"),
    ("negative shorthand", WALLS + "tree:\n  wait: -1\n", "9:3",
     "wait.duration: Input should be greater than or equal to 0"),
    ("no children", WALLS + "tree:\n  sequence: []\n", "9:3",
     "sequence.children: List should have at least 1 item"),
    ("decorator without child", WALLS + "tree:\n  retry: {num_failures: 2}\n", "9:3",
     "retry: missing required key 'child'"),
    ("scalar for a mapping-only node", WALLS + "tree:\n  retry: 3\n", "9:3",
     "retry takes a mapping of parameters, e.g. 'retry: {num_failures: ...}'"),
    ("both spin angles", WALLS + "tree:\n  spin: {angle: 1.0, angle_deg: 90}\n", "9:22",
     "give either angle (rad) or angle_deg, not both"),
    ("back_up cannot finish in time", WALLS + "tree:\n  back_up: {distance: 1.0, speed: 0.05}\n",
     "9:3", "1 m at 0.05 m/s takes 20 s, more than the time_allowance 10 s"),
    ("back_up faster than the robot", WALLS + "tree:\n  back_up: {speed: 0.5}\n", "9:13",
     "speed 0.5 m/s exceeds turtlebot3's limit 0.22 m/s"),
    ("synchronise with success_on_one",
     WALLS + "tree:\n  parallel:\n    policy: success_on_one\n    synchronise: true\n"
     "    children: [{wait: 1}]\n", "9:3", "synchronise applies to policy success_on_all only"),
    ("goal inside an obstacle", WALLS + "tree:\n  navigate_to_pose: {x: 1.2, y: 0.0}\n", "9:3",
     "goal (1.20, 0.00) is inside obstacle 'wall_east'"),
    ("goal within the footprint radius", WALLS + "tree:\n  go_to_goal: {x: 1.3, y: -0.5}\n",
     "9:3", "is inside obstacle 'wall_east' for this robot: 0.050 m from it, less than the 0.105"),
    ("goal off the floor", WALLS + "tree:\n  navigate_through_poses: [dock, {x: 5.0, y: 0}]\n",
     "9:34", "goal (5.00, 0.00) is outside the floor of world 'walls' (x -3.3..3.3"),
    ("start inside an obstacle", WALLS + "start: {x: 1.2, y: 0.0}\n" + WAIT_TREE, "8:1",
     "start (1.20, 0.00) is inside obstacle 'wall_east'"),
    ("zero quaternion",
     "mission: m\nworld: walls\nrobot: turtlebot3\nlocations:\n"
     "  bad: {position: [1, 1, 0], orientation: [0, 0, 0, 0]}\n" + WAIT_TREE, "6:30",
     "orientation quaternion has zero norm"),
    ("both yaw forms", WALLS + "tree:\n  navigate_to_pose: {x: 0.5, y: 0.5, yaw: 1, yaw_deg: 9}\n",
     "9:46", "give either yaw (rad) or yaw_deg (deg), not both"),
    ("capability the robot lacks", PANDA + "tree:\n  navigate_to_pose: above\n", "8:3",
     "navigate_to_pose needs capability 'navigation'; robot 'panda' has: arm"),
    ("unknown object", PANDA + "tree:\n  move_to: {relative_to: cub}\n", "8:13",
     "unknown object 'cub'; did you mean 'cube'? valid: cube, tcp"),
    ("planar arm target", PANDA + "tree:\n  move_to: flat\n", "8:3",
     "location 'flat' is planar (x, y, yaw); an arm target needs"),
    ("start for a fixed robot", PANDA + "start: above\n" + WAIT_TREE, "7:1",
     "start applies to mobile robots"),
    ("unknown subtree", WALLS + SUBTREE + "tree:\n  subtree: delivr\n", "14:3",
     "unknown subtree 'delivr'; did you mean 'deliver'? valid: deliver"),
    ("missing subtree argument", WALLS + SUBTREE + "tree:\n  subtree: deliver\n", "14:3",
     "subtree 'deliver' needs argument 't' (int) in args"),
    ("extra subtree argument",
     WALLS + SUBTREE + "tree:\n  subtree: {name: deliver, args: {t: 1, u: 2}}\n", "14:41",
     "unknown argument 'u' in subtree 'deliver'; valid: t"),
    ("subtree argument outside choices",
     WALLS + SUBTREE + "tree:\n  subtree: {name: deliver, args: {t: 3}}\n", "14:35",
     "argument 't' of subtree 'deliver': 3 is not one of the choices 1, 2"),
    ("subtree uses itself",
     WALLS + "subtrees:\n  a: {tree: {subtree: b}}\n  b: {tree: {sequence: [{subtree: a}]}}\n"
     + "tree:\n  subtree: a\n", "10:26", "subtree 'a' uses itself: a -> b -> a"),
    ("unknown parameter in a subtree",
     WALLS + "subtrees:\n  s: {params: {t: {type: float}}, tree: {wait: '${dt}'}}\n"
     + "tree: {subtree: {name: s, args: {t: 1}}}\n", "9:42",
     "unknown parameter 'dt' in subtree 's'; did you mean 't'? valid: t"),
    ("unknown parameter in the tree", WALLS + "tree:\n  wait: ${dur}\n", "9:3",
     "unknown parameter 'dur' in the mission; valid: (none)"),
    ("pose parameter inside text",
     WALLS + "params:\n  p: {type: pose, default: dock}\ntree:\n  navigate_to_pose: x${p}\n",
     "11:3", "parameter 'p' is a pose: use it as a whole value"),
    ("parameter where none is substituted",
     "mission: m\nworld: '${w}'\nrobot: turtlebot3\n" + WAIT_TREE, "3:1",
     "parameters are not substituted in 'world'"),
    ("default outside choices",
     WALLS + "params:\n  t: {type: int, default: 7, choices: [1, 2]}\n" + WAIT_TREE, "9:18",
     "params.t.default: 7 is not one of the choices 1, 2"),
    ("unknown parameter type", WALLS + "params:\n  t: {type: integer}\n" + WAIT_TREE, "9:7",
     "params.t.type: got 'integer'; input should be 'int', 'float', 'str', 'bool' or 'pose'"),
    ("substituted value out of range",
     WALLS + "params:\n  d: {type: float, default: 100.0}\ntree:\n  timeout: {duration: 1, "
     "child: {back_up: {time_allowance: '${d}', distance: 100}}}\n", "11:44",
     "takes 666.667 s, more than the time_allowance 100 s (${d} = 100.0)"),
    ("event without an action", WALLS + WAIT_TREE + "events:\n  - {at: 1.0}\n", "10:5",
     "an event has 'at' and exactly one of: cancel, spawn_obstacle, move_obstacle, teleop, fault"),
    ("event after the timeout",
     WALLS + WAIT_TREE + "timeout: 10\nevents:\n  - {at: 20, cancel: true}\n", "11:6",
     "event at 20 s comes after the mission timeout 10 s"),
    ("moving an obstacle never spawned",
     WALLS + WAIT_TREE + "events:\n  - {at: 2, move_obstacle: {name: box, x: 0, y: 1}}\n",
     "10:29", "unknown obstacle 'box'; valid: (none) (spawn it with an earlier spawn_obstacle"),
    ("teleop too fast",
     WALLS + WAIT_TREE + "events:\n  - {at: 1, duration: 2, teleop: {linear: 0.5}}\n", "10:35",
     "teleop linear 0.5 m/s exceeds turtlebot3's limit 0.22 m/s"),
    ("unknown expectation", WALLS + WAIT_TREE + "expect:\n  max_sim_tme: 10\n", "10:3",
     "unknown expectation 'max_sim_tme' in expect; did you mean 'max_sim_time'?"),
    ("error code without failure",
     WALLS + WAIT_TREE + "expect:\n  result: SUCCEEDED\n  error_code: 104\n", "11:3",
     "error_code is only meaningful with result: FAILED"),
    ("arm expectation for a base", WALLS + WAIT_TREE + "expect:\n  object_lifted: 0.1\n", "10:3",
     "expectation 'object_lifted' needs a robot with capability 'arm', not turtlebot3"),
    ("unknown visited location",
     WALLS + WAIT_TREE + "expect:\n  visited_in_order: [dock, cornr]\n", "10:28",
     "unknown location 'cornr'; did you mean 'corner'?"),
]  # fmt: skip


@pytest.mark.parametrize(
    ("text", "where", "fragment"),
    [case[1:] for case in MALFORMED],
    ids=[case[0] for case in MALFORMED],
)
def test_malformed_missions_fail_with_one_located_line(
    tmp_path: Path, text: str, where: str, fragment: str
) -> None:
    path = _write(tmp_path, HEADER + text)
    with pytest.raises(MissionError) as caught:
        load_mission(path)
    message = str(caught.value)
    assert message.startswith(f"{path}:{where}: "), message
    assert fragment in message, message
    assert "\n" not in message
    assert "Traceback" not in message


def test_the_table_covers_at_least_thirty_mistakes() -> None:
    assert len(MALFORMED) >= 30
    assert len({case[0] for case in MALFORMED}) == len(MALFORMED)


WITHOUT_EDITOR_COMMENT = {
    "no comment": WALLS + WAIT_TREE,
    "licence comment": "# SPDX-License-Identifier: Apache-2.0\n" + WALLS + WAIT_TREE,
    "yaml.dump": yaml.dump(yaml.safe_load(WALLS + WAIT_TREE)),
    "comment later": WALLS + WAIT_TREE + HEADER,
}


@pytest.mark.parametrize("text", WITHOUT_EDITOR_COMMENT.values(), ids=WITHOUT_EDITOR_COMMENT)
def test_the_editor_comment_is_optional(tmp_path: Path, text: str) -> None:
    mission = load_mission(_write(tmp_path, text))
    assert (mission.name, mission.world_name, mission.tree.label) == ("m", "walls", "wait 1 s")


def test_a_mission_written_by_yaml_dump_validates_and_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _write(tmp_path, WITHOUT_EDITOR_COMMENT["yaml.dump"])
    assert not path.read_text().startswith("#")
    assert main(["validate", str(path)]) == 0
    assert main(["run", str(path), "--json", "--out", str(tmp_path / "run")]) == 0
    result = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert (result["mission"], result["result"]) == ("m", "SUCCEEDED")


@pytest.mark.parametrize("name", ["delivery.yaml", "patrol.yaml", "pick.yaml"])
def test_fixture_missions_load(name: str) -> None:
    mission = load_mission(FIXTURES / name)
    assert mission.path == FIXTURES / name
    assert mission.tree.walk()


def test_delivery_resolves_start_world_subtree_and_expectations() -> None:
    mission = load_mission(FIXTURES / "delivery.yaml")
    assert mission.world is not None and mission.world.name == "diner"
    assert mission.world_name == str((FIXTURES / "worlds" / "diner.yaml").resolve())
    assert mission.start is not None
    assert (mission.start.x, mission.start.y) == (-3.0, 1.2)
    assert mission.start.yaw == pytest.approx(math.pi / 2)
    assert mission.params == {"table": 3, "dwell": 2.0}
    labels = [node.label for node in mission.tree.walk()]
    assert "subtree deliver(table=3, dwell=2.0)" in labels
    assert "navigate_to_pose table_3" in labels
    assert mission.expect is not None
    assert mission.expect.visited_in_order == ["table_3", "kitchen"]
    assert mission.timeout == 300.0 and mission.seed == 7


def test_set_changes_the_substituted_location() -> None:
    mission = load_mission(FIXTURES / "delivery.yaml", {"table": "5"})
    goals = [node.params for node in mission.tree.walk() if node.type == "navigate_to_pose"]
    assert [goal.goal.location for goal in goals] == ["table_5", "kitchen"]  # type: ignore[attr-defined]
    table_5 = goals[0].goal  # type: ignore[attr-defined]
    assert (table_5.x, table_5.y) == (1.5, -2.2)
    assert mission.params["table"] == 5
    assert mission.expect is not None and mission.expect.visited_in_order == ["table_5", "kitchen"]


def test_set_outside_the_choices_points_at_the_declaration() -> None:
    path = FIXTURES / "delivery.yaml"
    with pytest.raises(MissionError) as caught:
        load_mission(path, {"table": "9"})
    assert str(caught.value) == (
        f"{path}:9:3: --set table=9: 9 is not one of the choices 1, 2, 3, 4, 5"
    )


@pytest.mark.parametrize(
    ("overrides", "where", "fragment"),
    [
        (
            {"tabel": "2"},
            "8:1",
            "--set tabel=2: unknown parameter 'tabel'; did you mean 'table'? valid: dwell, table",
        ),
        ({"table": "two"}, "9:3", "--set table=two: expected an integer, got 'two'"),
        ({"dwell": "-1"}, "14:3", "--set dwell=-1: -1.0 is below the minimum 0"),
    ],
)
def test_set_mistakes_are_located(overrides: dict[str, str], where: str, fragment: str) -> None:
    path = FIXTURES / "delivery.yaml"
    with pytest.raises(MissionError) as caught:
        load_mission(path, overrides)
    assert str(caught.value) == f"{path}:{where}: {fragment}"


def test_a_value_from_a_parameter_names_its_origin(tmp_path: Path) -> None:
    text = (
        WALLS + "params:\n  goal: {type: str, default: dock}\ntree:\n  navigate_to_pose: x${goal}\n"
    )
    path = _write(tmp_path, HEADER + text)
    with pytest.raises(MissionError, match=r"unknown location 'xdock'.*\(\$\{goal\} = dock\)$"):
        load_mission(path)
    with pytest.raises(MissionError, match=r"\(\$\{goal\} = corner\)$"):
        load_mission(path, {"goal": "corner"})


def test_pose_parameter_accepts_a_mapping_on_the_command_line(tmp_path: Path) -> None:
    text = WALLS + "params:\n  p: {type: pose, default: dock}\ntree:\n  navigate_to_pose: ${p}\n"
    path = _write(tmp_path, HEADER + text)
    mission = load_mission(path, {"p": "{x: -2.0, y: -0.5, yaw_deg: 180}"})
    goal = mission.tree.params.goal  # type: ignore[attr-defined]
    assert (goal.x, goal.y, goal.yaw) == (-2.0, -0.5, pytest.approx(math.pi))


def test_mission_locations_win_over_the_worlds_and_spatial_poses_give_a_yaw(
    tmp_path: Path,
) -> None:
    text = (
        "mission: m\nworld: walls\nrobot: turtlebot3\nlocations:\n"
        "  goal_open: {x: -2.0, y: -2.0}\n"
        "  tilted: {position: [1.0, 2.0, 0.3], orientation: [0, 0, 0.3826834, 0.9238795]}\n"
        "start: tilted\ntree: {navigate_to_pose: goal_open}\n"
    )
    mission = load_mission(_write(tmp_path, HEADER + text))
    assert mission.locations["goal_open"].position == (-2.0, -2.0, 0.0)
    assert mission.start is not None
    assert (mission.start.x, mission.start.y) == (1.0, 2.0)
    assert mission.start.yaw == pytest.approx(math.pi / 4)
    assert "default" in mission.locations  # the world's spawns are locations too


def test_world_file_inside_the_folder_is_accepted_and_escapes_are_refused(
    tmp_path: Path,
) -> None:
    folder = tmp_path / "missions"
    (folder / "worlds").mkdir(parents=True)
    world = (FIXTURES / "worlds" / "diner.yaml").read_text()
    (folder / "worlds" / "diner.yaml").write_text(world)
    (tmp_path / "outside.yaml").write_text(world)
    body = "mission: m\nrobot: turtlebot3\ntree: {navigate_to_pose: table_1}\nworld: "
    inside = _write(folder, HEADER + body + "worlds/diner.yaml\n")
    assert load_mission(inside).world is not None
    for written in ("../outside.yaml", str(tmp_path / "outside.yaml"), "worlds/../../outside.yaml"):
        path = _write(folder, HEADER + body + written + "\n")
        with pytest.raises(MissionError) as caught:
            load_mission(path)
        assert str(caught.value) == (
            f"{path}:5:1: world file '{written}' is outside the mission's folder; give a "
            "bundled world name or a path inside the folder"
        )
    missing = _write(folder, HEADER + body + "worlds/none.yaml\n")
    with pytest.raises(MissionError, match=r":5:1: no world file 'worlds/none.yaml'"):
        load_mission(missing)


def test_a_broken_world_file_is_reported_in_the_world_file(tmp_path: Path) -> None:
    (tmp_path / "w.yaml").write_text("name: w\nfloor: {size: [1, 1]}\nspawns: {}\nbogus: 1\n")
    path = _write(tmp_path, HEADER + "mission: m\nworld: w.yaml\nrobot: turtlebot3\n" + WAIT_TREE)
    with pytest.raises(SourceError) as caught:
        load_mission(path)
    assert str(caught.value).startswith(f"{tmp_path / 'w.yaml'}:")


def test_unused_subtrees_are_still_checked(tmp_path: Path) -> None:
    text = WALLS + WAIT_TREE + "subtrees:\n  spare: {tree: {sequence: [{wiat: 1}]}}\n"
    path = _write(tmp_path, HEADER + text)
    with pytest.raises(
        MissionError, match=r":10:30: unknown behaviour 'wiat'; did you mean 'wait'"
    ):
        load_mission(path)


def test_yaml_level_protections_still_apply(tmp_path: Path) -> None:
    bomb = ["a0: &a0 [x, x, x, x, x, x, x, x, x]"]
    bomb += [f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 9)}]" for i in range(1, 9)]
    path = _write(tmp_path, HEADER + "\n".join(bomb) + "\n")
    with pytest.raises(MissionError, match="aliases"):
        load_mission(path)
    path = _write(tmp_path, HEADER + WALLS + "tree: {wait: .nan}\n")
    with pytest.raises(MissionError, match=r":8:14: non-finite"):
        load_mission(path)


def test_events_are_sorted_and_obstacle_slots_are_bounded(tmp_path: Path) -> None:
    events = "".join(
        f"  - {{at: {5 - i}, spawn_obstacle: {{name: b{i}, x: 0, y: {i * 0.5 - 1}}}}}\n"
        for i in range(4)
    )
    path = _write(tmp_path, HEADER + WALLS + WAIT_TREE + "events:\n" + events)
    mission = load_mission(path)
    assert [event.at for event in mission.events] == [2, 3, 4, 5]
    fifth = "  - {at: 6, spawn_obstacle: {name: b4, x: 0, y: 1}}\n"
    path = _write(tmp_path, HEADER + WALLS + WAIT_TREE + "events:\n" + events + fifth)
    with pytest.raises(MissionError, match=r":14:13: at most 4 obstacles can be spawned"):
        load_mission(path)
