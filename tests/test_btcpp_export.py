"""The BehaviorTree.CPP export, checked by BehaviorTree.CPP itself (``behaviortreepy``).

Every bundled mission and a corpus that uses every node type, parameters inside (nested)
subtrees and every pose form is exported, loaded by BT.CPP 4 with dummy nodes registered from
the exported ``TreeNodesModel``, and ticked to completion. Durations must reach ``Sleep`` and
``Timeout`` in ms whatever their source; trees BT.CPP cannot express are refused with a
located error; ``--btlog`` orders one instant's records as BT.CPP's own ``FileLogger2`` does.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from importlib import resources
from pathlib import Path

import behaviortreepy as bt
import pytest
from btcpp_harness import (
    MAX_TICKS,
    btcpp_tree,
    finished_btlog,
    instances,
    read_btlog,
    read_btlog_once,
    read_msec,
    resolved,
    tick_to_completion,
)

from baobab.behaviours.builtin import default_registry
from baobab.behaviours.ports import Capabilities
from baobab.missions.cli.command_line import main
from baobab.missions.language.btcpp_limits import BTCPP_NODE_IDS
from baobab.missions.language.btcpp_log import PY_TREES_STATUS, BtLogWriter
from baobab.missions.language.btcpp_ports import msec
from baobab.missions.language.compiler import compile_mission
from baobab.missions.language.loader import Mission, load_mission
from baobab.missions.language.tree_export import preorder, to_btcpp, to_btcpp_log

HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
BUNDLED = sorted(Path(str(resources.files("baobab.missions"))).glob("*.yaml"))
SHORT_WAITS = {"cafe_delivery": {"pickup": "0.05"}, "lobby_dock": {"charge_time": "0.05"}}
"""BT.CPP's Sleep waits in wall-clock time: shorten the bundled waits it would sit through."""

MOBILE = """
mission: btcpp_mobile
world: walls
robot: turtlebot3
params:
  pause: {type: float, default: 0.02}
locations:
  spot_1.0: {x: 0.5, y: 0.5}
subtrees:
  park:
    params:
      slot: {type: float}
    tree: {navigate_to_pose: "spot_${slot}"}
  visit:
    params:
      place: {type: pose}
      pause: {type: float, default: 0.02}
      laps: {type: int, default: 1}
    tree:
      sequence:
        - clear_costmaps_when_stuck:
            period: 0.5
            child: {navigate_to_pose: "${place}"}
        - wait: ${pause}
        - timeout: {duration: "${pause}", child: {always_success: {}}}
        - repeat: {num_success: "${laps}", child: {spin: {angle_deg: 90}}}
  tour:
    params:
      side: {type: str}
      pause: {type: float}
    tree:
      sequence:
        - navigate_to_pose: "goal_${side}"
        - subtree: {name: visit, args: {place: "goal_${side}", pause: "${pause}"}}
        - follow_waypoints: {waypoints: ["goal_${side}", goal_open], wait_at_waypoint: "${pause}"}
        - timeout: {duration: 30, child: {wait: "${pause}"}}
tree:
  sequence:
    - subtree: {name: tour, args: {side: open, pause: "${pause}"}}
    - subtree: {name: tour, args: {side: behind_wall, pause: 0.01}}
    - subtree: {name: visit, args: {place: {x: 1.0, y: 0.5}}}
    - subtree:
        name: visit
        args:
          place: {position: [0.5, -1.0, 0.0], orientation: [0, 0, 0.7071068, 0.7071068]}
          pause: 0.001
          laps: 2
    - sequence:
        memory: false
        children: [{is_at: {x: 0, y: 0, yaw: 0}}, {navigate_to_pose: {x: 0.5, y: 0.5, yaw_deg: 90}}]
    - selector: {memory: false, children: [{invert: {is_at: goal_open}}, {go_to_goal: goal_open}]}
    - selector: [{always_failure: {}}, {bug2: goal_behind_wall}]
    - parallel:
        policy: success_on_all
        children: [{back_up: {distance: 0.2}}, {drive_on_heading: {distance: 0.1}}]
    - parallel:
        policy: success_on_one
        children: [{assisted_teleop: {time_allowance: 5}}, {wait: 0.01}]
    - retry: {num_failures: 2, child: {navigate_through_poses: [goal_open, {x: 1.0, y: 1.0}]}}
    - force_success: {always_failure: {}}
    - invert: {force_failure: {clear_costmaps: local}}
    - force_success: {dock_robot: {dock_pose: {x: 2.0, y: -2.0}, navigate_to_staging_pose: false}}
    - force_success: {undock_robot: {}}
    - follow_path: {path: [{x: 0, y: 0}, {x: 0.5, y: 0, yaw: 0.1}]}
    - timeout: {duration: 60.5, child: {elapsed: 0}}
    - subtree: {name: park, args: {slot: 1}}
    - parallel:
        policy: success_on_one
        children:
          - ros_node:
              script: node.py
              params: {rate: 2.0, frame: odom, gains: [1.0, 2.5]}
              node_name: talker
          - wait: 0.01
    - toggle_collision_monitor: false
    - toggle_collision_monitor: {enable: true}
collision_monitor:
  polygons: [PolygonStop]
  PolygonStop: {type: circle, radius: 0.3, action_type: stop}
  observation_sources: [scan]
  scan: {type: scan, topic: /scan}
timeout: 100
"""

ARM = """
mission: btcpp_arm
robot: panda
world: panda_table
locations:
  above_target: {position: [0.45, 0.3, 0.68], orientation: [1, 0, 0, 0]}
subtrees:
  raise:
    params:
      lift: {type: float, default: 0.1}
      hold: {type: float, default: 0.01}
      grip: {type: str, default: close}
    tree:
      sequence:
        - gripper: "${grip}"
        - move_to: {relative_to: tcp, offset: [0, 0, "${lift}"], duration: "${hold}"}
        - wait: "${hold}"
tree:
  sequence:
    - subtree: {name: raise, args: {lift: 0.15}}
    - move_to: above_target
    - move_to: {pose: {position: [0.4, 0.0, 0.7], orientation: [1, 0, 0, 0]}, duration: 1.5}
    - subtree: {name: raise, args: {lift: -0.05, grip: open}}
    - object_at: {object: cube, target: {position: [0.45, 0.3, 0.525]}}
timeout: 60
"""
LOBBY = """
mission: btcpp_lobby
world: lobby
robot: turtlebot3
tree:
  sequence:
    - dock_robot: charger
    - undock_robot: {}
    - follow_object: {topic: /visitor/pose, max_duration: 5}
    - follow_object: {frame: visitor}
timeout: 60
"""
ROUTES = """
mission: btcpp_routes
world: town
robot: turtlebot3
tree:
  sequence:
    - follow_route: 22
    - follow_route: {start: 3, goal: 5}
    - follow_route: {goal: fast_food, start: {x: 0, y: 0}}
timeout: 100
"""

GPS = """
mission: btcpp_gps
world: farm
robot: turtlebot3
tree:
  follow_gps_waypoints:
    - {latitude: 38.538162164, longitude: -121.761631182, yaw_deg: 90}
    - {latitude: 38.538180181, longitude: -121.761631182, altitude: 12.5}
timeout: 100
"""
CORPUS = {"mobile": MOBILE, "arm": ARM, "routes": ROUTES, "gps": GPS, "lobby": LOBBY}


def mission_file(tmp_path: Path, body: str, name: str) -> Path:
    (tmp_path / "node.py").write_text("print('a node file next to the mission')\n")
    path = tmp_path / f"{name}.yaml"
    path.write_text(HEADER + body, encoding="utf-8")
    return path


def durations_msec(mission: Mission) -> list[int]:
    """The mission's waits and timeouts in ms, in tick order (subtrees expanded)."""
    timed = [node for node in mission.tree.walk() if node.type in ("wait", "timeout")]
    return [msec(node.raw["duration"]) for node in timed]


# --- the export loads and runs ---------------------------------------------------------------


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_behaviortree_cpp_loads_and_runs_every_bundled_mission(path: Path) -> None:
    mission = load_mission(path, SHORT_WAITS.get(path.stem, {}))
    xml = to_btcpp(mission)
    assert tick_to_completion(btcpp_tree(xml)) == bt.NodeStatus.SUCCESS
    assert read_msec(xml) == durations_msec(mission)


@pytest.mark.parametrize("name", CORPUS)
def test_behaviortree_cpp_loads_and_runs_the_corpus(tmp_path: Path, name: str) -> None:
    mission = load_mission(mission_file(tmp_path, CORPUS[name], name))
    xml = to_btcpp(mission)
    assert tick_to_completion(btcpp_tree(xml)) == bt.NodeStatus.SUCCESS
    assert read_msec(xml) == durations_msec(mission)
    # each node reads what the expanded tree holds: subtrees' derived ports are computed right
    assert resolved(xml) == instances(to_btcpp_log(mission))


def test_the_corpus_uses_every_node_type_and_pose_form(tmp_path: Path) -> None:
    missions = [load_mission(mission_file(tmp_path, body, n)) for n, body in CORPUS.items()]
    nodes = [node for mission in missions for node in mission.tree.walk()]
    assert {node.type for node in nodes} == set(default_registry().names())
    memories = {(node.type, node.raw.get("memory", True)) for node in nodes}
    assert {(kind, memory) for kind in ("sequence", "selector") for memory in (True, False)} <= (
        memories
    )
    assert {node.raw.get("policy") for node in nodes if node.type == "parallel"} == {
        "success_on_all",
        "success_on_one",
    }
    poses = [
        value
        for node in nodes
        for key in ("goal", "location", "place", "pose", "target", "poses", "path", "waypoints")
        for value in _as_list(node.raw.get(key, node.raw.get("args", {}).get(key)))
    ]
    forms = {frozenset(pose) if isinstance(pose, dict) else "name" for pose in poses}
    assert {
        "name",
        frozenset({"x", "y"}),
        frozenset({"x", "y", "yaw"}),
        frozenset({"x", "y", "yaw_deg"}),
        frozenset({"position", "orientation"}),
        frozenset({"position"}),
    } <= forms
    shapes = [shape for mission in missions for shape in mission.subtree_shapes.values()]
    assert any(child.type == "subtree" for shape in shapes for child in shape.children)


def _as_list(value: object) -> list[object]:
    if value is None:
        return []
    return list(value) if isinstance(value, list) else [value]


# --- durations ---------------------------------------------------------------------------------


def test_subtree_and_mission_parameters_reach_sleep_and_timeout_in_milliseconds(
    tmp_path: Path,
) -> None:
    mission = load_mission(mission_file(tmp_path, MOBILE, "mobile"), {"pause": "0.25"})
    xml = to_btcpp(mission)
    tour_open = [250, 250, 30000, 250]  # --set pause=0.25 through tour into visit
    tour_behind_wall = [10, 10, 30000, 10]
    visits = [20, 20, 1, 1]  # visit's default pause, then 0.001 s
    expected = tour_open + tour_behind_wall + visits + [10, 60500, 10]  # 10: beside ros_node
    assert read_msec(xml) == expected == durations_msec(mission)
    root = ET.fromstring(xml)
    visit = next(tree for tree in root.findall("BehaviorTree") if tree.get("ID") == "visit")
    assert [e.get("msec") for e in visit.iter() if e.tag in ("Sleep", "Timeout")] == [
        "{pause_msec}",
        "{pause_msec}",
    ]
    port = root.find("TreeNodesModel/SubTree[@ID='visit']/input_port[@name='pause_msec']")
    assert port is not None and (port.get("type"), port.get("default")) == ("unsigned int", "20")


def test_parameters_inside_text_and_lists_reach_their_ports_whole(tmp_path: Path) -> None:
    root = ET.fromstring(to_btcpp(load_mission(mission_file(tmp_path, MOBILE, "mobile"))))
    calls = [e.attrib for e in root.iterfind("BehaviorTree//SubTree[@ID='tour']")]
    assert [(c["side"], c["goal"], c["waypoints"]) for c in calls] == [
        ("open", "goal_open", "goal_open;goal_open"),
        ("behind_wall", "goal_behind_wall", "goal_behind_wall;goal_open"),
    ]
    tour = next(tree for tree in root.findall("BehaviorTree") if tree.get("ID") == "tour")
    (goal,) = tour.iter("NavigateToPose")
    (inner,) = tour.iter("SubTree")  # visit, its place and pause passed on whole
    assert (goal.get("goal"), inner.get("place"), inner.get("pause_msec")) == (
        "{goal}",
        "{goal}",
        "{pause_msec}",
    )
    arm = ET.fromstring(to_btcpp(load_mission(mission_file(tmp_path, ARM, "arm"))))
    raises = [(e.get("offset"), e.get("hold_msec")) for e in arm.iterfind("BehaviorTree//SubTree")]
    assert raises == [("0;0;0.15", "10"), ("0;0;-0.05", "10")]


# --- what BehaviorTree.CPP cannot express ------------------------------------------------------

SUBTREE_CALL = """
mission: refused
world: walls
robot: turtlebot3
subtrees:
  {name}:
    params:
      {param}: {spec}
    tree:
      {body}
tree:
  sequence:
    - subtree: {{name: {name}, args: {args}}}
    - {main}
timeout: 10
"""
TEXT = '{type: str, default: "kitchen"}'


def _refused(name: str = "hold", param: str = "note", spec: str = TEXT,
             body: str = "always_success: {}", args: str = "{}",
             main: str = "always_success: {}") -> str:  # fmt: skip
    return SUBTREE_CALL.format(name=name, param=param, spec=spec, body=body, args=args, main=main)


REFUSED = {  # the mission, the line blamed, words of the message
    "subtree named like a BT.CPP node": (_refused(name="Sleep"), 7, "BehaviorTree.CPP node type"),
    "subtree named like the mission": (_refused(name="refused"), 7, "the mission's name"),
    "parameter named name": (_refused(param="name"), 9, "attribute of <SubTree>"),
    "parameter starting with _": (_refused(param="_note"), 9, "reserves names"),
    "memory from a parameter": (
        _refused(
            param="flag",
            spec="{type: bool, default: true}",
            body='sequence: {memory: "${flag}", children: [wait: 1]}',
        ),
        11,
        "'memory' from a parameter",
    ),
    "parallel without synchronise": (
        _refused(main="parallel: {synchronise: false, children: [wait: 1, wait: 2]}"),
        15,
        "never ticks a child again",
    ),
    "timeout under a millisecond": (
        _refused(main="timeout: {duration: 0.0004, child: {wait: 1}}"),
        15,
        "is 0 ms",
    ),
    "wait longer than 49 days": (_refused(main="wait: 5.0e+6"), 15, "more than BehaviorTree.CPP"),
    "value read as a blackboard entry": (
        _refused(args='{note: "{kitchen}"}'),
        14,
        "reads as a blackboard entry",
    ),
    "subtree duration under a millisecond": (
        _refused(
            param="t",
            spec="{type: float}",
            body='timeout: {duration: "${t}", child: {wait: 1}}',
            args="{t: 0.0001}",
        ),
        11,
        "in the subtree called at line 14",
    ),
}


@pytest.mark.parametrize("case", REFUSED)
def test_trees_behaviortree_cpp_cannot_express_are_refused_at_the_cause(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], case: str
) -> None:
    body, line, words = REFUSED[case]
    path = mission_file(tmp_path, body, "refused")
    assert main(["validate", str(path)]) == 0  # a valid mission
    capsys.readouterr()
    assert main(["tree", str(path), "--format", "btcpp"]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    (message,) = err.splitlines()
    assert message.startswith(f"{path}:{line}:"), message
    assert words in message


def test_the_list_of_btcpp_node_types_has_every_builtin_of_the_library(tmp_path: Path) -> None:
    tree = bt.BehaviorTreeFactory().create_tree_from_text(
        '<root BTCPP_format="4"><BehaviorTree ID="M"><AlwaysSuccess/></BehaviorTree></root>'
    )
    log_path = tmp_path / "builtins.btlog"
    logger = bt.FileLogger(tree, str(log_path))
    tree.tick_once()
    logger.flush()
    del logger
    xml, _ = read_btlog(log_path)
    builtins = {entry.get("ID") for entry in ET.fromstring(xml).iterfind("TreeNodesModel/*")}
    assert builtins <= BTCPP_NODE_IDS


# --- the Groot2 log orders an instant as BT.CPP does --------------------------------------------

LOGGED = """
mission: logged
world: walls
robot: turtlebot3
subtrees:
  settle:
    params:
      pause: {type: float}
    tree:
      sequence:
        - wait: ${pause}
        - force_success: {always_failure: {}}
tree:
  sequence:
    - elapsed: 0
    - invert: {invert: {wait: 0.02}}
    - subtree: {name: settle, args: {pause: 0.02}}
    - selector: [{always_failure: {}}, {always_success: {}}]
timeout: 10
"""


def _finished(records: list[tuple[int, int, int]]) -> list[tuple[int, int]]:
    """The (uid, status) records of nodes finishing (SUCCESS 2, FAILURE 3), in log order."""
    return [(uid, status) for _, uid, status in records if status in (2, 3)]


def test_the_groot2_log_orders_each_instant_as_behaviortree_cpp_file_logger2(
    tmp_path: Path,
) -> None:
    mission = load_mission(mission_file(tmp_path, LOGGED, "logged"))
    reference_path = tmp_path / "btcpp.btlog"
    tree = btcpp_tree(to_btcpp(mission))
    assert finished_btlog(tree, reference_path) == bt.NodeStatus.SUCCESS
    reference_xml, reference = read_btlog_once(reference_path)

    ours_path = tmp_path / "baobab.btlog"
    _run_logged(mission, ours_path)
    ours_xml, ours = read_btlog(ours_path)

    def numbered(xml: str) -> dict[int, str]:
        return {int(e.get("_uid", "")): e.tag for e in ET.fromstring(xml).iter() if e.get("_uid")}

    assert numbered(ours_xml) == numbered(reference_xml)  # the same nodes, the same uids
    assert _finished(ours) == _finished(reference)  # children finish before their parents


def _run_logged(mission: Mission, path: Path) -> None:
    """Tick ``mission`` over a 10 ms clock, logging each tick's statuses as ``--btlog`` does."""
    clock = [0.0]
    compiled = compile_mission(mission, Capabilities(clock=lambda: clock[0]), require_ports=False)
    behaviours = list(preorder(compiled.root))
    with BtLogWriter(path, to_btcpp_log(mission)) as log:
        for _ in range(MAX_TICKS):
            compiled.tree.tick()
            statuses = {uid: PY_TREES_STATUS[b.status.name] for uid, b in enumerate(behaviours, 1)}
            log.update(clock[0], statuses)
            if compiled.root.status.name != "RUNNING":
                return
            clock[0] += 0.01
    raise AssertionError("the mission did not finish")
