"""The live view (``--live``): both Foxglove subprotocols, refused clients, latched transforms.

Every client here is :mod:`foxglove_client`, written from the protocol's public spec.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from foxglove_client import spec_client
from test_recording import read_mcap
from websockets.exceptions import ConnectionClosedError, InvalidStatus
from websockets.sync.client import connect
from websockets.typing import Subprotocol

from baobab.missions.language.loader import load_mission
from baobab.missions.run.recording_streams import ArmStreams
from baobab.missions.run.recording_topics import TREE_STATUS_SCHEMA, Topics
from baobab.missions.run.rig import ArmRig
from baobab.missions.run.runner import RecordingOptions, run_mission
from baobab.sim.recording import LiveSink, McapSink, Recorder, Transform
from baobab.sim.world import Pose2D

HANG_GUARD = 20.0
"""Seconds a socket read may block before a test gives up (a guard, not a check)."""
SUBPROTOCOLS = ["foxglove.websocket.v1", "foxglove.sdk.v1"]
REFUSAL = (
    "refused a client at {host} (HTTP 400: invalid subprotocol; expected one of "
    "foxglove.sdk.v1, foxglove.websocket.v1); further failures from {host} are not shown"
)
HEADER = "# yaml-language-server: $schema=mission.schema.json\n"
PANDA = """
mission: hold
robot: panda
world: panda_table
seed: 3
tree:
  wait: 1.0
"""
PAUSE = "mission: pause\nworld: walls\nrobot: turtlebot3\ntree:\n  wait: 0.3\n"


@pytest.mark.parametrize("subprotocol", SUBPROTOCOLS)
def test_a_client_of_either_subprotocol_receives_every_channel(subprotocol: str) -> None:
    sink = LiveSink(port=0)
    # 1.1 MB: more than websockets' default frame limit (1 MiB), as a large costmap would be.
    costmap = (np.arange(1000 * 1100) % 251).astype(np.uint8).reshape(1000, 1100)
    topics = {Topics.TF, Topics.TF_STATIC, Topics.TREE_STATUS, Topics.GLOBAL_COSTMAP}
    with Recorder([sink]) as recorder:

        def log_every_topic(t: float) -> None:
            odom = Transform.planar("map", "odom", Pose2D(x=1.0, y=2.0, yaw=0.5))
            recorder.log_transforms(Topics.TF, t, [odom])
            recorder.log_static_transforms(
                Topics.TF_STATIC, t, [Transform("world", "panda/link0", (0.1, 0, 0))]
            )
            recorder.log_json(
                Topics.TREE_STATUS, t, {"tick": round(t * 10)}, schema=TREE_STATUS_SCHEMA
            )
            recorder.log_grid(Topics.GLOBAL_COSTMAP, t, costmap, resolution=0.05, origin=(-1, 0))

        log_every_topic(0.0)
        with spec_client(sink.url, subprotocol, timeout=HANG_GUARD) as client:
            assert client.connection.subprotocol == subprotocol
            assert client.server_info["name"] == "baobab"
            assert "time" in client.server_info["capabilities"]
            client.wait_for_topics(topics)
            assert client.topics() == topics
            client.subscribe(client.topics())
            for topic in topics:
                assert sink.wait_for_subscription(topic, HANG_GUARD)
            log_every_topic(0.1)
            received = client.receive_until(
                lambda got: {r.topic for r in got if r.log_time == 100_000_000} == topics
            )

    latest = {r.topic: r.message for r in received if r.log_time == 100_000_000}
    (odom,) = latest[Topics.TF].transforms
    assert (odom.parent_frame_id, odom.child_frame_id) == ("map", "odom")
    assert (odom.translation.x, odom.translation.y) == (1.0, 2.0)
    assert latest[Topics.TF_STATIC].transforms[0].child_frame_id == "panda/link0"
    assert latest[Topics.TREE_STATUS] == {"tick": 1}
    grid = latest[Topics.GLOBAL_COSTMAP]
    assert grid.column_count == 1100 and bytes(grid.data) == costmap.tobytes()


def test_a_refused_handshake_is_reported_once_per_client_address() -> None:
    reports: list[str] = []
    sink = LiveSink(port=0, report=reports.append)
    with Recorder([sink]):
        port = sink.port
        attempts = [("127.0.0.1", "foxglove.websocket.v2")] * 3
        attempts += [("127.0.0.2", "foxglove.websocket.v2")] * 2
        for source, subprotocol in attempts:
            with (
                pytest.raises(InvalidStatus) as refused,
                connect(
                    sink.url,
                    subprotocols=[Subprotocol(subprotocol)],
                    open_timeout=HANG_GUARD,
                    source_address=(source, 0),
                ),
            ):
                pass
            assert refused.value.response.status_code == 400
            assert b"expected one of foxglove.sdk.v1, foxglove.websocket.v1" in (
                refused.value.response.body or b""
            )
        with (
            pytest.raises(InvalidStatus) as refused,  # no subprotocol at all
            connect(sink.url, open_timeout=HANG_GUARD, source_address=("127.0.0.3", 0)),
        ):
            pass
        assert refused.value.response.status_code == 400
    # Each refusal is reported before it is sent, so all are in by now.
    assert reports == [
        "live: " + REFUSAL.format(host="127.0.0.1"),
        "live: " + REFUSAL.format(host="127.0.0.2"),
        "live: refused a client at 127.0.0.3 (HTTP 400: missing subprotocol); "
        "further failures from 127.0.0.3 are not shown",
    ]
    with Recorder([LiveSink(port=port)]):  # closing freed the port
        pass


def test_a_client_the_relay_cannot_pass_on_is_closed_and_reported_once() -> None:
    reports: list[str] = []
    sink = LiveSink(port=0, report=reports.append)
    with Recorder([sink]):
        assert sink._server is not None
        sink._server.stop()  # nothing left behind the relay: foxglove-sdk is gone
        for _ in range(2):
            with connect(
                sink.url, subprotocols=[Subprotocol("foxglove.sdk.v1")], open_timeout=HANG_GUARD
            ) as client:
                with pytest.raises(ConnectionClosedError) as closed:
                    client.recv(timeout=HANG_GUARD)
                assert closed.value.rcvd is not None and closed.value.rcvd.code == 1011
    assert len(reports) == 1
    assert reports[0].startswith("live: cannot relay 127.0.0.1 to foxglove-sdk's server: ")


def test_a_live_run_passes_a_refusal_to_warn_once(tmp_path: Path) -> None:
    mission = tmp_path / "pause.yaml"
    mission.write_text(HEADER + PAUSE, encoding="utf-8")
    warnings: list[str] = []

    def warn(message: str) -> None:
        warnings.append(message)
        if message.startswith("live: open Foxglove and connect to "):
            for _ in range(3):  # a viewer retrying with the wrong subprotocol
                with (
                    pytest.raises(InvalidStatus),
                    connect(
                        message.rsplit(" ", 1)[1],
                        subprotocols=[Subprotocol("foxglove.websocket.v2")],
                        open_timeout=HANG_GUARD,
                    ),
                ):
                    pass

    options = RecordingOptions(live=True, port=0)
    record = run_mission(load_mission(mission), recording=options, warn=warn)
    assert record.outcome.result == "SUCCEEDED"
    assert [w for w in warnings if "refused" in w] == ["live: " + REFUSAL.format(host="127.0.0.1")]


def test_the_panda_base_transform_is_latched_live_and_repeated_in_the_file(
    tmp_path: Path,
) -> None:
    mission = tmp_path / "hold.yaml"
    mission.write_text(HEADER + PANDA, encoding="utf-8")
    rig = ArmRig(load_mission(mission), seed=3)
    path = tmp_path / "panda.mcap"
    sink = LiveSink(port=0)
    with Recorder([McapSink(path), sink]) as recorder:
        streams = ArmStreams(recorder, rig)
        rig.sim.step_for(1.5)  # /tf_static logged at 0 and 1 s
        with spec_client(sink.url, SUBPROTOCOLS[0], timeout=HANG_GUARD) as client:
            client.wait_for_topics({Topics.TF_STATIC})
            client.subscribe({Topics.TF_STATIC})
            assert sink.wait_for_subscription(Topics.TF_STATIC, HANG_GUARD)
            rig.sim.step_for(0.02)  # other topics only: the next /tf_static is due at 2 s
            (latched,) = client.receive_until(lambda got: len(got) == 1)
        rig.sim.step_for(1.0)
        streams.close()
        end_ns = round(rig.sim.time * 1e9)

    assert latched.log_time == 1_000_000_000  # the latest, as it was logged
    (base,) = latched.message.transforms
    assert (base.parent_frame_id, base.child_frame_id) == ("world", "panda/link0")
    position = rig.server.base_position
    assert [base.translation.x, base.translation.y, base.translation.z] == pytest.approx(position)

    schemas, messages = read_mcap(path)
    assert Topics.TF not in schemas
    assert schemas[Topics.TF_STATIC] == ("foxglove.FrameTransforms", "protobuf")
    times = sorted({log_time for log_time, _ in messages[Topics.TF_STATIC]})
    assert times == [0, 1_000_000_000, 2_000_000_000]
    # A viewer opening the file at any instant finds the transform less than 1 s before it.
    assert max(np.diff([*times, end_ns])) <= 1_000_000_000
    for _, message in messages[Topics.TF_STATIC]:
        (transform,) = message.transforms
        assert transform.child_frame_id == "panda/link0"
