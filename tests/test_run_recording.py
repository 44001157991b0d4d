"""Seeing what happened: ``baobab run --record/--live/--video/--btlog``, plots, Groot2 export.

Recording only reads the simulation, so every recorded run here is checked against the same
run unrecorded: the trace digests must be equal.
"""

from __future__ import annotations

import json
import math
import os
import re
import signal
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET
from collections import defaultdict
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import Any

import av
import numpy as np
import pytest
from mcap.decoder import DecoderFactory as McapDecoderFactory
from mcap.reader import make_reader
from mcap.records import Schema as McapSchema
from mcap_protobuf.decoder import DecoderFactory

from baobab.behaviours.builtin import default_registry
from baobab.behaviours.ports import Capabilities
from baobab.behaviours.registry import NodeKind
from baobab.missions.cli.command_line import main
from baobab.missions.language.bundled_missions import resolve_mission
from baobab.missions.language.compiler import compile_mission
from baobab.missions.language.loader import load_mission
from baobab.missions.language.tree_export import BUILTIN_MODELS, preorder, to_btcpp, to_btcpp_log
from baobab.missions.run.plot_data import ArmPlot
from baobab.missions.run.plotting import save_plot
from baobab.missions.run.runner import RecordingOptions, run_mission

BAOBAB = str(Path(sys.executable).parent / "baobab")
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
BUNDLED = sorted(Path(str(resources.files("baobab.missions"))).glob("*.yaml"))
BLACKBOARD_KEY = re.compile(r"\{[A-Za-z_][A-Za-z0-9_]*\}")
NAVIGATE = """
mission: short_hop
world: walls
robot: turtlebot3
start: {x: 0.0, y: 0.0, yaw: 0.0}
seed: 1
tree:
  navigate_to_pose: {x: 1.0, y: 0.5}
timeout: 30
"""
NUDGE = """
mission: nudge
robot: panda
world: panda_table
seed: 3
tree:
  move_to: {relative_to: tcp, offset: [0, 0, 0.05], duration: 0.5}
timeout: 5
"""
PAUSE = "mission: pause\nworld: walls\nrobot: turtlebot3\ntree:\n  wait: 0.3\n"


class JsonDecoderFactory(McapDecoderFactory):
    """Decodes JSON channels with the standard library."""

    def decoder_for(
        self, message_encoding: str, schema: McapSchema | None
    ) -> Callable[[bytes], Any] | None:
        return json.loads if message_encoding == "json" else None


def read_mcap(path: Path) -> tuple[dict[str, str], dict[str, list[tuple[int, Any]]]]:
    """Topic -> schema name, and topic -> [(log time ns, decoded message)] in file order."""
    messages: dict[str, list[tuple[int, Any]]] = defaultdict(list)
    with path.open("rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory(), JsonDecoderFactory()])
        summary = reader.get_summary()
        assert summary is not None
        schemas = {c.topic: summary.schemas[c.schema_id].name for c in summary.channels.values()}
        for _, channel, message, decoded in reader.iter_decoded_messages(log_time_order=False):
            messages[channel.topic].append((message.log_time, decoded))
    return schemas, messages


def assert_in_time_order(messages: dict[str, list[tuple[int, Any]]]) -> None:
    for topic, stamped in messages.items():
        times = [t for t, _ in stamped]
        assert times == sorted(times), f"{topic} goes back in time"


def stamp_ns(timestamp: Any) -> int:
    return int(timestamp.seconds) * 1_000_000_000 + int(timestamp.nanos)


def planar(position: Any, orientation: Any) -> tuple[float, float, float]:
    """(x, y, yaw) of a decoded position and quaternion (m, rad)."""
    yaw = math.atan2(
        2 * (orientation.w * orientation.z + orientation.x * orientation.y),
        1 - 2 * (orientation.y**2 + orientation.z**2),
    )
    return position.x, position.y, yaw


def compose(
    a: tuple[float, float, float], b: tuple[float, float, float]
) -> tuple[float, float, float]:
    """Planar pose ``b`` (in ``a``'s frame) in the frame ``a`` is given in."""
    cos, sin = math.cos(a[2]), math.sin(a[2])
    yaw = math.remainder(a[2] + b[2], math.tau)
    return a[0] + cos * b[0] - sin * b[1], a[1] + sin * b[0] + cos * b[1], yaw


def mission_file(tmp_path: Path, body: str, name: str) -> Path:
    path = tmp_path / name
    path.write_text(HEADER + body, encoding="utf-8")
    return path


def run_json(
    capsys: pytest.CaptureFixture[str], mission: str | Path, out: Path, *extra: str
) -> tuple[int, dict[str, Any], str]:
    code = main(["run", str(mission), "--json", "--out", str(out), *extra])
    captured = capsys.readouterr()
    return code, json.loads(captured.out), captured.err


# --- TurtleBot3 ------------------------------------------------------------------------------


def test_a_recorded_and_filmed_go_to_goal_run_is_the_same_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    mcap, video, btlog = tmp_path / "run.mcap", tmp_path / "run.mp4", tmp_path / "run.btlog"
    plain = run_mission(load_mission(resolve_mission("walls_go_to_goal")))
    code, result, _ = run_json(
        capsys,
        "walls_go_to_goal",
        tmp_path / "recorded",
        *("--record", str(mcap), "--btlog", str(btlog)),
        *("--video", str(video), "--fps", "2", "--video-size", "64x48"),
    )
    assert (code, result["result"]) == (0, "SUCCEEDED")
    assert result["trace_digest"] == plain.trace_digest
    assert result["recording"] == {
        "mcap": str(mcap),
        "video": str(video),
        "video_frames": 30,  # 2 fps over 14.7 s: frames at 0.0, 0.5, ..., 14.5 s
        "btlog": str(btlog),
    }

    schemas, messages = read_mcap(mcap)
    assert schemas == {
        "/tf": "foxglove.FrameTransforms",
        "/scan": "foxglove.LaserScan",
        "/robot_pose": "foxglove.PoseInFrame",
        "/followed_path": "foxglove.PosesInFrame",
        "/robot/scene": "foxglove.SceneUpdate",
        "/world/scene": "foxglove.SceneUpdate",
        "/behavior_tree/status": "baobab.BehaviourTreeStatus",
        "/task/feedback": "baobab.TaskFeedback",
    }  # no navigation server: no plan and no costmap
    assert_in_time_order(messages)
    end_ns = round(result["sim_time"] * 1e9)
    assert len(messages["/robot_pose"]) == 294  # 20 Hz over 14.7 s
    assert len(messages["/scan"]) == 74  # the lidar's 5 Hz
    assert all(stamp_ns(m.timestamp) == t for t, m in messages["/robot_pose"])
    last = messages["/robot_pose"][-1][1].pose.position
    assert math.hypot(last.x - 2.0, last.y - 2.0) < 0.06  # goal_open, 5 cm tolerance
    tf = messages["/tf"][-1][1].transforms
    assert [(f.parent_frame_id, f.child_frame_id) for f in tf] == [
        ("map", "odom"),
        ("odom", "base_link"),
    ]
    assert math.hypot(tf[1].translation.x - last.x, tf[1].translation.y - last.y) < 0.05
    # One robot, not two: map -> odom corrects the odometry, so map -> odom -> base_link is the
    # ground truth (/robot_pose, where the model and the scan are drawn) at every stamp, while
    # odom -> base_link keeps the odometry's drift.
    truth = {t: planar(m.pose.position, m.pose.orientation) for t, m in messages["/robot_pose"]}
    start = messages["/tf"][0][1].transforms[0]
    first_map_odom = planar(start.translation, start.rotation)
    drift = []
    for t, message in messages["/tf"]:
        map_odom, odom_base = (planar(f.translation, f.rotation) for f in message.transforms)
        np.testing.assert_allclose(compose(map_odom, odom_base), truth[t], rtol=0, atol=1e-9)
        x, y, _ = compose(first_map_odom, odom_base)
        drift.append(math.hypot(x - truth[t][0], y - truth[t][1]))
    assert len(drift) == 294 and max(drift) > 0.002  # 4.5 mm in this run
    statuses = messages["/behavior_tree/status"]
    times = [t for t, _ in statuses]  # on each change, at least once a second, at the end
    assert times[0] == 0 and max(np.diff(times)) <= 1_000_000_000 and times[-1] == end_ns
    assert [m["root_status"] for _, m in statuses[:2]] == ["RUNNING", "RUNNING"]
    assert statuses[-1][1]["root_status"] == "SUCCESS" and statuses[-1][1]["tick"] == 148
    assert [n["type"] for n in statuses[0][1]["nodes"]] == ["timeout", "go_to_goal"]
    assert {m["task"] for _, m in messages["/task/feedback"]} == {"go_to_goal"}
    world = messages["/world/scene"][0][1]
    ids = {entity.id for entity in world.entities}
    assert {"location/goal_open", "location/goal_behind_wall"} <= ids
    assert len(world.deletions) == 1  # each update replaces the whole scene
    robot_entities = {entity.id: entity for entity in messages["/robot/scene"][0][1].entities}
    assert "tb3/base_link" in robot_entities
    footprint = robot_entities["footprint"]  # the Burger's 0.105 m circle, in base_link
    assert footprint.frame_id == "base_link"
    (outline,) = footprint.lines
    assert len(outline.points) == 16
    assert {round(math.hypot(p.x, p.y), 6) for p in outline.points} == {0.105}

    with av.open(str(video)) as container:
        stream = container.streams.video[0]
        assert (stream.codec_context.name, stream.width, stream.height) == ("h264", 64, 48)
        assert sum(1 for _ in container.decode(stream)) == 30

    raw = btlog.read_bytes()
    (xml_length,) = struct.unpack_from("<i", raw, 19)
    tree = ET.fromstring(raw[23 : 23 + xml_length])
    uids = {e.get("_uid"): e.tag for e in tree.iter() if e.get("_uid")}
    assert uids == {"1": "Timeout", "2": "GoToGoal"}
    body = raw[31 + xml_length :]
    records = [
        (int.from_bytes(body[i : i + 6], "little"), *struct.unpack_from("<HB", body, i + 6))
        for i in range(0, len(body), 9)
    ]
    end_us = round(result["sim_time"] * 1e6)
    # the Timeout starts RUNNING before its child does, and finishes after it, as in BT.CPP
    assert records == [(0, 1, 1), (0, 2, 1), (end_us, 2, 2), (end_us, 1, 2)]


def test_a_navigation_run_records_its_plans_and_costmap(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = mission_file(tmp_path, NAVIGATE, "hop.yaml")
    mcap = tmp_path / "hop.mcap"
    plain = run_mission(load_mission(path))
    code, result, _ = run_json(capsys, path, tmp_path / "recorded", "--record", str(mcap))
    assert (code, result["result"]) == (0, "SUCCEEDED")
    assert result["trace_digest"] == plain.trace_digest
    schemas, messages = read_mcap(mcap)
    assert schemas["/plan"] == "foxglove.PosesInFrame"
    assert schemas["/global_costmap/costmap"] == "foxglove.Grid"
    assert_in_time_order(messages)
    plans = [m for _, m in messages["/plan"]]
    first = plans[0].poses
    assert len(first) > 10
    end = first[-1].position
    assert math.hypot(end.x - 1.0, end.y - 0.5) < 0.05
    assert plans[-1].poses == []  # the task ended: the plan is cleared
    grid = messages["/global_costmap/costmap"][0][1]
    cells = np.frombuffer(grid.data, dtype=np.uint8).reshape(-1, grid.column_count)
    assert grid.cell_size.x == pytest.approx(0.05)
    assert cells.max() >= 253 and (cells == 0).mean() > 0.3  # walls inflated, free space
    assert len(messages["/global_costmap/costmap"]) == math.ceil(result["sim_time"])


# --- Panda ----------------------------------------------------------------------------------


def test_a_panda_run_records_the_impedance_poses_and_plots_the_tracking_error(
    tmp_path: Path,
) -> None:
    mission = load_mission(mission_file(tmp_path, NUDGE, "nudge.yaml"))
    plain = run_mission(mission)
    mcap, video = tmp_path / "nudge.mcap", tmp_path / "nudge.mp4"
    options = RecordingOptions(record=mcap, video=video, fps=10, video_size=(64, 48))
    record = run_mission(mission, recording=options)
    assert record.outcome.result == "SUCCEEDED"
    assert record.trace_digest == plain.trace_digest
    assert record.extra["recording"]["video_frames"] == 6  # 10 fps over 0.6 s

    schemas, messages = read_mcap(mcap)
    assert_in_time_order(messages)
    impedance = [
        "/cartesian_impedance/current_pose",
        "/cartesian_impedance/desired_pose",
        "/cartesian_impedance/filt_ref_pose",
    ]
    for topic in impedance:
        assert schemas[topic] == "foxglove.PoseInFrame"
        assert len(messages[topic]) == 60  # 100 Hz over 0.6 s
        assert {m.frame_id for _, m in messages[topic]} == {"panda/link0"}
    desired = [m.pose.position.z for _, m in messages[impedance[1]]]
    current = [m.pose.position.z for _, m in messages[impedance[0]]]
    assert desired[-1] - desired[0] == pytest.approx(0.05, abs=1e-6)
    assert current[-1] - current[0] == pytest.approx(0.05, abs=0.01)
    joints = messages["/joint_states"][-1][1].joints
    assert [j.name for j in joints][:2] == ["panda/joint1", "panda/joint2"] and len(joints) == 9
    assert "/tf" not in messages
    ((_, tf),) = messages["/tf_static"]  # at 0 s; again every second
    assert tf.transforms[0].child_frame_id == "panda/link0"
    assert {"cube", "panda/hand"} <= {e.id for e in messages["/scene"][0][1].entities}

    plot = record.plot
    assert isinstance(plot, ArmPlot)
    assert len(plot.tracking_errors) == 30  # 50 Hz over 0.6 s
    assert record.metrics["max_tracking_error"] == max(plot.tracking_errors)
    assert 0.0 < max(plot.tracking_errors) < 0.05
    assert plot.setpoint_path[-1][2] - plot.setpoint_path[0][2] == pytest.approx(0.05, abs=1e-6)
    save_plot(plot, tmp_path / "plot.png")
    assert (tmp_path / "plot.png").read_bytes()[:4] == b"\x89PNG"


# --- live, flags, start-up ------------------------------------------------------------------


def test_live_on_a_free_port_serves_and_the_run_completes(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = mission_file(tmp_path, PAUSE, "pause.yaml")
    code, result, err = run_json(capsys, path, tmp_path / "run", "--live", "--port", "0")
    assert (code, result["result"], result["sim_time"]) == (0, "SUCCEEDED", 0.3)
    url = result["recording"]["live"]
    assert url.startswith("ws://127.0.0.1:") and not url.endswith(":0")
    assert f"live: open Foxglove and connect to {url}" in err


@pytest.mark.parametrize(
    ("flags", "message"),
    [
        (["--fps", "5"], "--fps and --video-size set up --video, which is not given"),
        (["--port", "9000"], "--host and --port set up --live, which is not given"),
        (["--record", "/no/such/folder/run.mcap"], "the folder /no/such/folder does not exist"),
        (["--btlog", "run.log"], "Groot2 reads only files ending in .btlog"),
    ],
)
def test_recording_flags_are_checked_before_anything_runs(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], flags: list[str], message: str
) -> None:
    out = tmp_path / "run"
    code = main(["run", "walls_go_to_goal", "--out", str(out), *flags])
    captured = capsys.readouterr()
    assert (code, captured.out) == (2, "")
    assert captured.err == f"baobab run: {captured.err.split(': ', 1)[1]}"
    assert message in captured.err and captured.err.count("\n") == 1
    assert not out.exists()


def test_video_without_pyav_says_how_to_install_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "av", None)  # import av now raises ImportError
    out = tmp_path / "run"
    code = main(["run", "walls_go_to_goal", "--out", str(out), "--video", str(tmp_path / "v.mp4")])
    captured = capsys.readouterr()
    assert code == 2
    assert captured.err == (
        'baobab run: --video needs PyAV, which is not installed: pip install "baobab[video]"\n'
    )
    assert not out.exists() and not (tmp_path / "v.mp4").exists()


def test_a_run_without_recording_imports_neither_foxglove_nor_av(tmp_path: Path) -> None:
    path = mission_file(tmp_path, PAUSE, "pause.yaml")
    script = (
        "import os, sys\nfrom baobab.missions.cli.command_line import main\n"
        f"code = main(['run', {str(path)!r}, '--out', {str(tmp_path / 'run')!r}])\n"
        "loaded = sorted({m.split('.')[0] for m in sys.modules} & {'foxglove', 'av', 'mcap'})\n"
        "print('LOADED', code, loaded, os.environ.get('MUJOCO_GL'))\n"
    )
    headless = {
        k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "MUJOCO_GL")
    }
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=headless
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[-1] == "LOADED 0 [] egl"  # set before mujoco is imported


def test_sigint_still_finishes_the_recording(tmp_path: Path) -> None:
    long_pause = PAUSE.replace("wait: 0.3", "sequence: [{wait: 0.5}, {wait: 50}]")
    path = mission_file(tmp_path, long_pause, "long.yaml")
    mcap = tmp_path / "long.mcap"
    process = subprocess.Popen(
        [BAOBAB, "run", str(path), "--json", "--realtime", "--record", str(mcap)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=tmp_path,
    )
    assert process.stderr is not None and process.stdout is not None
    lines = iter(process.stderr.readline, "")
    progress = (line for line in lines if line.startswith("t="))
    next(progress), next(progress)  # the second wait has begun: 0.5 s have run
    process.send_signal(signal.SIGINT)
    stdout, _ = process.communicate(timeout=300)
    assert process.returncode == 130
    result = json.loads(stdout)
    assert result["result"] == "CANCELED"
    _, messages = read_mcap(mcap)  # the summary and indexes are there: the file is complete
    final = messages["/behavior_tree/status"][-1][1]
    assert final["root_status"] == "INVALID"  # halted
    poses = [t for t, _ in messages["/robot_pose"]]
    assert len(poses) >= 10 and poses[-1] <= round(result["sim_time"] * 1e9)


# --- BehaviorTree.CPP / Groot2 --------------------------------------------------------------


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_the_btcpp_export_of_every_bundled_mission_is_fully_modelled(path: Path) -> None:
    mission = load_mission(path)
    root = ET.fromstring(to_btcpp(mission))
    (model,) = root.findall("TreeNodesModel")
    declared = {entry.get("ID"): entry for entry in model}
    registry = {b.xml_id: b for b in default_registry()}
    for tree in root.findall("BehaviorTree"):
        for element in tree.iter():
            if element is tree:
                continue
            if element.tag == "SubTree":
                entry = declared[element.get("ID")]
                assert entry.tag == "SubTree" and "name" not in element.attrib
                ports = {port.get("name") for port in entry}
                assert set(element.attrib) - {"ID"} <= ports
                continue
            if element.tag in BUILTIN_MODELS:
                _, builtin_ports = BUILTIN_MODELS[element.tag]
                assert set(element.attrib) - {"name"} <= {name for name, _, _ in builtin_ports}
                assert element.tag not in declared  # Groot2 knows its built-ins
                continue
            entry = declared[element.tag]
            behaviour = registry[element.tag]
            category = {
                NodeKind.ACTION: "Action",
                NodeKind.CONDITION: "Condition",
                NodeKind.DECORATOR: "Decorator",
                NodeKind.COMPOSITE: "Control",
            }[behaviour.kind]
            assert entry.tag == category
            ports = [port.get("name") for port in entry.findall("input_port")]
            assert ports == list(behaviour.ports())  # every port, in order
            assert set(element.attrib) - {"name"} <= set(ports)
    for entry in model:
        types = {port.get("type") for port in entry.findall("input_port")}
        assert types <= {"int", "double", "bool", "std::string", "Pose", "vector", "any"}
    for element in root.iter():
        for key, value in element.attrib.items():
            if value.startswith("{") and value.endswith("}"):  # BT.CPP: a blackboard entry
                assert BLACKBOARD_KEY.fullmatch(value), (element.tag, key, value)


def test_structured_port_values_are_never_read_as_blackboard_entries(tmp_path: Path) -> None:
    mission = load_mission(mission_file(tmp_path, NAVIGATE, "hop.yaml"))
    (leaf,) = ET.fromstring(to_btcpp(mission)).iter("NavigateToPose")
    goal = leaf.get("goal", "")
    assert goal.startswith("json:") and json.loads(goal[5:]) == {"x": 1.0, "y": 0.5}
    tour = NAVIGATE.replace(
        "navigate_to_pose: {x: 1.0, y: 0.5}", "follow_waypoints: [goal_open, goal_behind_wall]"
    )
    patrol = load_mission(mission_file(tmp_path, tour, "tour.yaml"))
    (leaf,) = ET.fromstring(to_btcpp(patrol)).iter("FollowWaypoints")
    assert leaf.get("waypoints") == "goal_open;goal_behind_wall"  # BT.CPP's vector form


ERRANDS = """
mission: errands
world: walls
robot: turtlebot3
subtrees:
  visit:
    params:
      place: {type: str}
    tree:
      sequence:
        - go_to_goal: "${place}"
        - wait: 1
tree:
  sequence:
    - subtree: {name: visit, args: {place: goal_open}}
    - retry:
        num_failures: 2
        child: {subtree: {name: visit, args: {place: goal_behind_wall}}}
"""


def test_the_groot2_log_xml_numbers_nodes_in_tick_order_through_subtree_instances(
    tmp_path: Path,
) -> None:
    mission = load_mission(mission_file(tmp_path, ERRANDS, "errands.yaml"))
    compiled = compile_mission(mission, Capabilities(clock=lambda: 0.0), require_ports=False)
    root = ET.fromstring(to_btcpp_log(mission))
    trees = root.findall("BehaviorTree")
    assert [(t.get("ID"), t.get("_fullpath")) for t in trees] == [
        ("errands", ""),
        ("visit", "visit::2"),
        ("visit", "visit::7"),
    ]
    numbered = {int(e.get("_uid", "0")): e for e in root.iter() if e.get("_uid")}
    behaviours = list(preorder(compiled.root))
    assert sorted(numbered) == list(range(1, len(behaviours) + 1))
    assert [numbered[uid].tag for uid in sorted(numbered)] == [
        "Sequence",
        "SubTree",
        "Sequence",
        "GoToGoal",
        "Sleep",
        "RetryUntilSuccessful",
        "SubTree",
        "Sequence",
        "GoToGoal",
        "Sleep",
    ]
    for uid, behaviour in enumerate(behaviours, start=1):
        element = numbered[uid]
        if element.tag != "SubTree":
            assert element.get("name") == behaviour.name
    assert [numbered[4].get("goal"), numbered[9].get("goal")] == ["goal_open", "goal_behind_wall"]
    model = {entry.get("ID"): entry.tag for entry in root.find("TreeNodesModel") or []}
    assert model["Sequence"] == "Control" and model["RetryUntilSuccessful"] == "Decorator"
    assert model["Sleep"] == "Action" and model["GoToGoal"] == "Action"
    assert model["visit"] == "SubTree"
