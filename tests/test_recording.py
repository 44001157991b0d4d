"""Foxglove recording: MCAP files read back and decoded, scene primitives, the live server."""

from __future__ import annotations

import json
import math
import struct
from collections import defaultdict
from collections.abc import Callable
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
import pytest
from mcap.decoder import DecoderFactory as McapDecoderFactory
from mcap.reader import make_reader
from mcap.records import Schema as McapSchema
from mcap_protobuf.decoder import DecoderFactory
from scipy.spatial.transform import Rotation
from websockets.sync.client import connect

from baobab.missions.language.btcpp_log import BtLogWriter, BtStatus
from baobab.missions.run.recording_topics import TASK_FEEDBACK_SCHEMA, TREE_STATUS_SCHEMA, Topics
from baobab.nav.layered_costmap import LayeredCostmap
from baobab.robots.panda.model import ARM_JOINTS
from baobab.robots.panda.scene import build_panda_sim
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.lidar import LaserScan
from baobab.sim.recording import (
    LiveSink,
    McapSink,
    Recorder,
    RecordingError,
    Trail,
    Transform,
)
from baobab.sim.scene_primitives import GeomScene, location_entities
from baobab.sim.world import Pose2D, load_world

HANG_GUARD = 20.0
"""Seconds a socket read may block before the live test gives up (a guard, not a check)."""


class JsonDecoderFactory(McapDecoderFactory):
    """Decodes JSON-encoded channels with the standard library."""

    def decoder_for(
        self, message_encoding: str, schema: McapSchema | None
    ) -> Callable[[bytes], Any] | None:
        return json.loads if message_encoding == "json" else None


def read_mcap(path: Path) -> tuple[dict[str, tuple[str, str]], dict[str, list[tuple[int, Any]]]]:
    """Topic -> (schema name, schema encoding), and topic -> [(log_time, decoded)] in file order."""
    messages: dict[str, list[tuple[int, Any]]] = defaultdict(list)
    with path.open("rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory(), JsonDecoderFactory()])
        summary = reader.get_summary()
        assert summary is not None
        schemas = {
            channel.topic: (
                summary.schemas[channel.schema_id].name,
                summary.schemas[channel.schema_id].encoding,
            )
            for channel in summary.channels.values()
        }
        for _, channel, message, decoded in reader.iter_decoded_messages(log_time_order=False):
            messages[channel.topic].append((message.log_time, decoded))
    return schemas, messages


def stamp_ns(timestamp: Any) -> int:
    return int(timestamp.seconds) * 1_000_000_000 + int(timestamp.nanos)


def test_turtlebot3_run_round_trips_through_mcap(tmp_path: Path) -> None:
    world = load_world("walls")
    sim, robot = build_turtlebot3_sim(world, seed=3)
    costmap = LayeredCostmap.global_costmap(world).costmap
    world_scene = GeomScene(sim.model, groups=(1, 2))
    robot_scene = GeomScene(sim.model, groups=(3,))
    trail = Trail(min_distance=0.05)
    trail_lengths: list[int] = []
    scans: list[LaserScan] = []
    truth: list[tuple[float, Pose2D]] = []
    path = tmp_path / "run.mcap"
    robot.base.command(0.2, 0.5)
    with Recorder([McapSink(path)]) as recorder:
        recorder.log_scene(
            Topics.WORLD_SCENE,
            sim.time,
            world_scene.entities(sim.data) + location_entities(world.locations),
        )
        plan = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 0.78], [2.0, 2.0, -2.5]])
        recorder.log_path(Topics.PLAN, sim.time, plan)

        def at_20_hz(t: float) -> None:
            pose, odom = robot.base.pose(), robot.base.odometry.pose
            origin = robot.base.odom_origin
            recorder.log_transforms(
                Topics.TF,
                t,
                [
                    Transform.planar("map", "odom", origin),
                    Transform.planar("odom", "base_link", odom),
                ],
            )
            recorder.log_planar_pose(Topics.ROBOT_POSE, t, pose)
            truth.append((t, pose))
            trail.add(pose)

        def at_10_hz(t: float) -> None:
            recorder.log_json(
                Topics.TREE_STATUS,
                t,
                {"tick": round(t * 10), "root_status": "RUNNING", "nodes": []},
                schema=TREE_STATUS_SCHEMA,
            )
            recorder.log_json(
                Topics.TASK_FEEDBACK,
                t,
                {"task": "NavigateToPose", "distance_remaining": math.inf, "eta": np.float32(1.5)},
                schema=TASK_FEEDBACK_SCHEMA,
            )

        def at_5_hz(t: float) -> None:
            recorder.log_scene(Topics.ROBOT_SCENE, t, robot_scene.entities(sim.data))

        def at_1_hz(t: float) -> None:
            recorder.log_grid(
                Topics.GLOBAL_COSTMAP,
                t,
                costmap.data,
                resolution=costmap.resolution,
                origin=costmap.origin,
            )
            recorder.log_path(Topics.FOLLOWED_PATH, t, trail.poses)
            trail_lengths.append(len(trail.poses))

        def on_scan(scan: LaserScan) -> None:
            scans.append(scan)
            recorder.log_scan(Topics.SCAN, scan, z=0.182)

        sim.every(0.05, at_20_hz, name="tf")
        sim.every(0.1, at_10_hz, name="tree")
        sim.every(0.2, at_5_hz, name="robot scene")
        sim.every(1.0, at_1_hz, name="costmap")
        robot.lidar.subscribe(on_scan)
        sim.step_for(2.0)
        assert recorder.topics[0] == Topics.WORLD_SCENE

    schemas, messages = read_mcap(path)
    assert schemas == {
        Topics.WORLD_SCENE: ("foxglove.SceneUpdate", "protobuf"),
        Topics.PLAN: ("foxglove.PosesInFrame", "protobuf"),
        Topics.TF: ("foxglove.FrameTransforms", "protobuf"),
        Topics.ROBOT_POSE: ("foxglove.PoseInFrame", "protobuf"),
        Topics.TREE_STATUS: ("baobab.BehaviourTreeStatus", "jsonschema"),
        Topics.TASK_FEEDBACK: ("baobab.TaskFeedback", "jsonschema"),
        Topics.ROBOT_SCENE: ("foxglove.SceneUpdate", "protobuf"),
        Topics.GLOBAL_COSTMAP: ("foxglove.Grid", "protobuf"),
        Topics.FOLLOWED_PATH: ("foxglove.PosesInFrame", "protobuf"),
        Topics.SCAN: ("foxglove.LaserScan", "protobuf"),
    }
    counts = {topic: len(entries) for topic, entries in messages.items()}
    # 2 s from t = 0: callbacks due in [0, 2), the lidar (5 Hz) started with the robot.
    assert counts == {
        Topics.WORLD_SCENE: 1,
        Topics.PLAN: 1,
        Topics.TF: 40,
        Topics.ROBOT_POSE: 40,
        Topics.TREE_STATUS: 20,
        Topics.TASK_FEEDBACK: 20,
        Topics.ROBOT_SCENE: 10,
        Topics.GLOBAL_COSTMAP: 2,
        Topics.FOLLOWED_PATH: 2,
        Topics.SCAN: len(scans),
    }
    assert len(scans) == 10
    for topic, entries in messages.items():
        times = [log_time for log_time, _ in entries]
        assert times == sorted(times), topic

    # TF: the chain map -> odom -> base_link, stamped like the message, equal to the truth.
    for (log_time, tf), (t, _) in zip(messages[Topics.TF], truth, strict=True):
        assert log_time == round(t * 1e9)
        assert [(x.parent_frame_id, x.child_frame_id) for x in tf.transforms] == [
            ("map", "odom"),
            ("odom", "base_link"),
        ]
        assert all(stamp_ns(x.timestamp) == log_time for x in tf.transforms)
    _, last_pose = messages[Topics.ROBOT_POSE][-1]
    assert last_pose.frame_id == "map"
    assert last_pose.pose.position.x == pytest.approx(truth[-1][1].x)
    yaw = Rotation.from_quat(
        [getattr(last_pose.pose.orientation, axis) for axis in "xyzw"]
    ).as_euler("xyz")[2]
    assert yaw == pytest.approx(truth[-1][1].yaw)
    assert truth[-1][1].yaw > 0.5  # the robot really turned

    # Scans: every beam, misses kept as inf, placed at the sensor pose.
    for (log_time, decoded), scan in zip(messages[Topics.SCAN], scans, strict=True):
        assert log_time == round(scan.stamp * 1e9)
        np.testing.assert_array_equal(np.array(decoded.ranges), scan.ranges)
        assert decoded.pose.position.x == pytest.approx(scan.sensor_pose.x)
        assert decoded.pose.position.z == pytest.approx(0.182)
        assert decoded.end_angle == pytest.approx(scan.angle_max)
    assert np.isfinite(scans[0].ranges).sum() > 100  # the walls are seen

    # Grid: the costmap bytes, row-major from the lower-left corner.
    _, grid = messages[Topics.GLOBAL_COSTMAP][0]
    assert grid.column_count == costmap.data.shape[1]
    assert grid.row_stride == costmap.data.shape[1]
    assert grid.cell_size.x == pytest.approx(costmap.resolution)
    assert grid.pose.position.x == pytest.approx(costmap.origin[0])
    assert [(f.name, f.type) for f in grid.fields] == [("cost", 1)]  # 1: UINT8
    assert bytes(grid.data) == costmap.data.tobytes()

    # Plan: positions and headings as given.
    _, plan_message = messages[Topics.PLAN][0]
    plan_poses = [
        [p.position.x, p.position.y]
        + [Rotation.from_quat([getattr(p.orientation, a) for a in "xyzw"]).as_euler("xyz")[2]]
        for p in plan_message.poses
    ]
    np.testing.assert_allclose(plan_poses, plan, atol=1e-12)

    # Followed path: thinned trail, growing.
    first_path, last_path = (decoded for _, decoded in messages[Topics.FOLLOWED_PATH])
    assert [len(first_path.poses), len(last_path.poses)] == trail_lengths
    assert 1 == trail_lengths[0] < trail_lengths[1]

    # Scenes: walls as cubes, locations with arrows and labels, robot geoms in group 3.
    _, world_update = messages[Topics.WORLD_SCENE][0]
    by_id = {entity.id: entity for entity in world_update.entities}
    assert len(by_id["world"].cubes) == len(world.boxes)
    assert {f"location/{name}" for name in world.locations} <= set(by_id)
    goal = by_id["location/goal_open"]
    assert [text.text for text in goal.texts] == ["goal_open"]
    assert goal.arrows[0].pose.position.x == pytest.approx(2.0)
    _, robot_update = messages[Topics.ROBOT_SCENE][-1]
    assert "tb3/base_link" in {entity.id for entity in robot_update.entities}

    # JSON: the tree status and the feedback, non-finite floats as null.
    assert [m["tick"] for _, m in messages[Topics.TREE_STATUS]] == list(range(20))
    _, feedback = messages[Topics.TASK_FEEDBACK][0]
    assert feedback == {"task": "NavigateToPose", "distance_remaining": None, "eta": 1.5}


def test_panda_streams_poses_joints_and_geom_scene(tmp_path: Path) -> None:
    sim, arm = build_panda_sim(seed=1, cube_xy=(0.5, -0.1))
    scene = GeomScene(sim.model, frame_id="world")
    names = [arm.prefix + name for name in ARM_JOINTS]
    path = tmp_path / "panda.mcap"
    logged: dict[str, list[np.ndarray]] = defaultdict(list)
    with Recorder([McapSink(path)]) as recorder:
        base = Transform(
            "world", "panda/link0", tuple(arm.base_position), tuple(arm.base_rotation.as_quat())
        )
        recorder.log_transforms(Topics.TF, 0.0, [base])

        def at_100_hz(t: float) -> None:
            controller = arm.controller
            position, rotation = controller.tcp
            poses = {
                Topics.CURRENT_POSE: (position, Rotation.from_matrix(rotation).as_quat()),
                Topics.DESIRED_POSE: controller.target,
                Topics.FILT_REF_POSE: controller.reference,
            }
            for topic, (xyz, quaternion) in poses.items():
                recorder.log_pose(topic, t, xyz, quaternion, frame_id="panda/link0")
                logged[topic].append(np.concatenate([xyz, quaternion]))
            positions = [float(sim.data.joint(n).qpos[0]) for n in names]
            velocities = [float(sim.data.joint(n).qvel[0]) for n in names]
            recorder.log_joint_states(Topics.JOINT_STATES, t, names, positions, velocities)
            logged[Topics.JOINT_STATES].append(np.array(positions))

        sim.every(0.01, at_100_hz, name="arm poses")
        sim.every(
            0.05,
            lambda t: recorder.log_scene(Topics.ARM_SCENE, t, scene.entities(sim.data)),
            name="scene",
        )
        arm.move_to(arm.tcp_pose().translated(dz=0.05), 0.5)
        sim.step_for(0.1)

    schemas, messages = read_mcap(path)
    for topic in (Topics.CURRENT_POSE, Topics.DESIRED_POSE, Topics.FILT_REF_POSE):
        assert schemas[topic] == ("foxglove.PoseInFrame", "protobuf")
        decoded = [
            [getattr(m.pose.position, a) for a in "xyz"]
            + [getattr(m.pose.orientation, a) for a in "xyzw"]
            for _, m in messages[topic]
        ]
        np.testing.assert_allclose(decoded, logged[topic], rtol=0, atol=1e-12)
        assert {m.frame_id for _, m in messages[topic]} == {"panda/link0"}
    # The set-point rises; the filtered reference lags behind it.
    desired_z = np.array(logged[Topics.DESIRED_POSE])[:, 2]
    reference_z = np.array(logged[Topics.FILT_REF_POSE])[:, 2]
    assert desired_z[-1] > desired_z[0] and reference_z[-1] < desired_z[-1]
    assert schemas[Topics.JOINT_STATES] == ("foxglove.JointStates", "protobuf")
    assert len(messages[Topics.JOINT_STATES]) == 10
    _, joints = messages[Topics.JOINT_STATES][-1]
    assert [j.name for j in joints.joints] == names
    np.testing.assert_array_equal(
        [j.position for j in joints.joints], logged[Topics.JOINT_STATES][-1]
    )

    _, update = messages[Topics.ARM_SCENE][0]
    entities = {entity.id: entity for entity in update.entities}
    assert {"world", "cube", "panda/link0", "panda/hand", "panda/left_finger"} <= set(entities)
    # A capsule is a cylinder and two spheres; the table keeps its material colour.
    assert (len(entities["panda/link1"].cylinders), len(entities["panda/link1"].spheres)) == (1, 2)
    table = entities["world"].cubes[0]
    assert (table.size.x, table.size.y, table.size.z) == pytest.approx((1.2, 1.2, 0.5))
    assert (table.color.r, table.color.g) == pytest.approx((0.62, 0.47))
    cube = entities["cube"].cubes[0]
    assert cube.pose.position.x == pytest.approx(0.5, abs=1e-3)


CAPSULE_XML = """
<mujoco>
  <asset><material name="blue" rgba="0 0 1 1"/></asset>
  <worldbody>
    <geom name="floor" type="plane" size="2 3 0.1" group="0"/>
    <geom name="wall" type="box" pos="1 0 0.5" size="0.1 0.5 0.5" material="blue" group="1"/>
    <geom name="parked" type="box" pos="1000 0 0.5" size="0.1 0.1 0.1" group="2"/>
    <body name="link" pos="0 0 1" euler="90 0 0">
      <geom name="capsule" type="capsule" size="0.05 0.2" rgba="1 0 0 1" group="3"/>
      <geom name="egg" type="ellipsoid" pos="0.5 0 0" size="0.1 0.2 0.3" group="3"/>
      <geom name="drum" type="cylinder" pos="-0.5 0 0" size="0.1 0.05" group="3"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_geom_scene_maps_mujoco_shapes_to_foxglove_primitives() -> None:
    model = mujoco.MjModel.from_xml_string(CAPSULE_XML)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    entities = {e.id: e for e in GeomScene(model, groups=(0, 1, 2, 3)).entities(data)}
    assert set(entities) == {"world", "link"}  # the parked box is hidden, the plane skipped
    (wall,) = entities["world"].primitives
    assert (wall.shape, wall.size, wall.colour) == ("cube", (0.2, 1.0, 1.0), (0, 0, 1, 1))
    shapes = [(p.shape, p.size) for p in entities["link"].primitives]
    assert shapes == [
        ("cylinder", (0.1, 0.1, 0.4)),
        ("sphere", (0.1, 0.1, 0.1)),
        ("sphere", (0.1, 0.1, 0.1)),
        ("sphere", pytest.approx((0.2, 0.4, 0.6))),
        ("cylinder", (0.2, 0.2, 0.1)),
    ]
    # The body is turned 90 deg about x: the capsule axis (local z) points along world -y.
    cap_ends = sorted(p.position for p in entities["link"].primitives[1:3])
    np.testing.assert_allclose(cap_ends, [(0.0, -0.2, 1.0), (0.0, 0.2, 1.0)], atol=1e-9)
    with_planes = GeomScene(model, groups=(0,), include_planes=True).entities(data)
    (floor,) = with_planes[0].primitives
    assert floor.size == (4.0, 6.0, pytest.approx(0.002))
    assert floor.position[2] == pytest.approx(-0.001)


def test_recorder_rejects_time_going_backwards_and_mixed_types(tmp_path: Path) -> None:
    with Recorder([McapSink(tmp_path / "x.mcap")]) as recorder:
        recorder.log_planar_pose(Topics.ROBOT_POSE, 1.0, Pose2D(x=0, y=0))
        recorder.log_planar_pose(Topics.ROBOT_POSE, 1.0, Pose2D(x=0, y=0))  # equal is fine
        with pytest.raises(RecordingError, match="backwards"):
            recorder.log_planar_pose(Topics.ROBOT_POSE, 0.5, Pose2D(x=0, y=0))
        with pytest.raises(RecordingError, match="PoseInFrame"):
            recorder.log_json(Topics.ROBOT_POSE, 2.0, {"a": 1})
        with pytest.raises(ValueError, match="uint8"):
            recorder.log_grid("/g", 0.0, np.zeros((3, 3)), resolution=0.1, origin=(0, 0))
        with pytest.raises(ValueError, match="joints"):
            recorder.log_joint_states(Topics.JOINT_STATES, 0.0, ["a", "b"], [0.0])
    with pytest.raises(RecordingError, match="folder"):
        Recorder([McapSink(tmp_path / "missing" / "x.mcap")])


def test_trail_keeps_poses_only_after_enough_motion() -> None:
    trail = Trail(min_distance=0.1, min_angle=0.5)
    kept = [
        trail.add(Pose2D(x=x, y=0.0, yaw=yaw))
        for x, yaw in [(0, 0), (0.05, 0), (0.12, 0), (0.12, 0.6), (0.12, 0.7)]
    ]
    assert kept == [True, False, True, True, False]
    np.testing.assert_allclose(trail.poses[:, 2], [0.0, 0.0, 0.6])


def test_live_sink_advertises_channels_and_streams_to_a_websocket_client() -> None:
    sink = LiveSink(host="127.0.0.1", port=0)
    with Recorder([sink]) as recorder:
        recorder.log_transforms(Topics.TF, 0.0, [Transform.planar("map", "odom", Pose2D(x=0, y=0))])
        recorder.log_json(Topics.TREE_STATUS, 0.0, {"tick": 0}, schema=TREE_STATUS_SCHEMA)
        assert sink.port > 0
        with pytest.raises(RecordingError, match="cannot serve Foxglove"):
            Recorder([LiveSink(port=sink.port)])  # the port is taken
        with connect(sink.url, subprotocols=["foxglove.sdk.v1"], open_timeout=HANG_GUARD) as ws:
            info = json.loads(ws.recv(timeout=HANG_GUARD))
            assert info["op"] == "serverInfo" and "time" in info["capabilities"]
            advertised: dict[str, dict[str, Any]] = {}
            while len(advertised) < 2:
                message = json.loads(ws.recv(timeout=HANG_GUARD))
                if message["op"] == "advertise":
                    advertised.update({c["topic"]: c for c in message["channels"]})
            assert advertised[Topics.TF]["schemaName"] == "foxglove.FrameTransforms"
            assert advertised[Topics.TF]["encoding"] == "protobuf"
            assert advertised[Topics.TREE_STATUS]["schemaName"] == "baobab.BehaviourTreeStatus"
            assert advertised[Topics.TREE_STATUS]["encoding"] == "json"

            subscription = {"id": 7, "channelId": advertised[Topics.TF]["id"]}
            ws.send(json.dumps({"op": "subscribe", "subscriptions": [subscription]}))
            assert sink.wait_for_subscription(Topics.TF, HANG_GUARD)
            recorder.log_transforms(
                Topics.TF, 0.5, [Transform.planar("map", "odom", Pose2D(x=1, y=2))]
            )
            while True:
                frame = ws.recv(timeout=HANG_GUARD)
                if isinstance(frame, bytes) and frame[0] == 1:  # 1: message data
                    break
            _, subscription_id, log_time = struct.unpack_from("<BIQ", frame)
            assert (subscription_id, log_time) == (7, 500_000_000)
            assert len(frame) > 13  # a payload follows the header
    with pytest.raises(RecordingError, match="not started"):
        _ = sink.port


TREE_XML = (
    '<root BTCPP_format="4" main_tree_to_execute="Main">'
    '<BehaviorTree ID="Main" _fullpath="">'
    '<Sequence name="root" _uid="1" _fullpath="root">'
    '<Wait name="wait" _uid="2" _fullpath="root/wait"/>'
    '<Go name="go" _uid="3" _fullpath="root/go"/>'
    "</Sequence></BehaviorTree>"
    '<TreeNodesModel><Action ID="Wait"/><Action ID="Go"/></TreeNodesModel></root>'
)


def test_btlog_has_the_file_logger2_layout_and_records_only_changes(tmp_path: Path) -> None:
    idle, running, success = BtStatus.IDLE, BtStatus.RUNNING, BtStatus.SUCCESS
    ticks = [
        (0.0, {1: running, 2: running, 3: idle}),
        (0.1, {1: running, 2: running, 3: idle}),  # nothing changed
        (0.2, {1: running, 2: success, 3: running}),
        (0.3, {1: success, 2: success, 3: success}),
    ]
    path = tmp_path / "run.btlog"
    with BtLogWriter(path, TREE_XML, start_time_us=1_700_000_000_000_000) as log:
        assert [log.update(t, statuses) for t, statuses in ticks] == [2, 0, 2, 2]
    raw = path.read_bytes()
    assert raw[:18] == b"BTCPP4-FileLogger2" and raw[18] == 1
    (xml_length,) = struct.unpack_from("<i", raw, 19)
    assert raw[23 : 23 + xml_length].decode() == TREE_XML
    (start,) = struct.unpack_from("<q", raw, 23 + xml_length)
    assert start == 1_700_000_000_000_000
    body = raw[31 + xml_length :]
    assert len(body) == 9 * 6
    records = [
        (int.from_bytes(body[i : i + 6], "little"), *struct.unpack_from("<HB", body, i + 6))
        for i in range(0, len(body), 9)
    ]
    assert records == [  # at one instant in tick order, as BT.CPP's FileLogger2 writes them:
        (0, 1, 1),  # the parent starts RUNNING before it ticks its child,
        (0, 2, 1),
        (200_000, 2, 2),  # siblings in order,
        (200_000, 3, 1),
        (300_000, 3, 2),  # a child finishes before its parent does
        (300_000, 1, 2),
    ]
    with pytest.raises(RecordingError, match=r"suffix \.btlog"):
        BtLogWriter(tmp_path / "run.log", TREE_XML)
    with BtLogWriter(tmp_path / "b.btlog", TREE_XML) as log:
        log.transition(1.0, 1, running)
        with pytest.raises(RecordingError, match="out of order"):
            log.transition(0.5, 1, success)
        with pytest.raises(RecordingError, match="uid"):
            log.transition(2.0, 0, success)
