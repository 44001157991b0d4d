"""Seeing what happened: record a run, serve it live, film it, show it, log its tree for Groot2.

A :class:`RecordingHook` gathers everything that watches a run in one object, so the run loop
knows only one callable. Built after the rig and the compiled tree, it starts what the
:class:`RecordingOptions` ask for:

- ``record`` (MCAP file) and ``live`` (Foxglove WebSocket server, both subprotocol names):
  one :class:`~baobab.sim.recording.Recorder` with a sink for each, fed by the robot's sim
  callbacks (:mod:`baobab.missions.run.recording_streams`) and, after the tree ticks, its status
  (``/behavior_tree/status``: every node's status, whenever one changed and at least once a
  second) and once a second the running tasks' feedback (``/task/feedback``). Live runs are
  stamped with the wall clock and paced to it; a client the server refuses is reported
  through ``warn`` once per address.
- ``video``: an H.264 MP4, one frame every ``1 / fps`` s of sim time, filmed by a chase
  camera behind the mobile robot that rises over walls so the robot shows in every frame, or
  from a fixed 3/4 view that the arm and its table fill; each frame says the sim time, the
  running tasks and their goals (:mod:`baobab.missions.run.video_caption`).
- ``btlog``: a Groot2 replay log (BehaviorTree.CPP ``FileLogger2``) of the tree's status
  changes; its node uids are those of :func:`~baobab.missions.language.tree_export.to_btcpp_log`.
- ``viewer``: MuJoCo's passive viewer, synced after every tick (paced to the wall clock);
  without a display the run warns and goes on headless.

Every observer only reads the simulation: the trace digest is the same with or without them.
:meth:`RecordingHook.close` finishes the files; the runner calls it in a ``finally``, so an
interrupted run (SIGINT) still leaves a valid MCAP and MP4. Nothing here costs anything
unless asked: foxglove, PyAV and the renderer are imported only by runs that use them.
"""

from __future__ import annotations

import math
import queue
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import py_trees

from baobab.missions.language.compiler import CompiledMission
from baobab.missions.language.tree_export import preorder, to_btcpp_log
from baobab.sim.errors import BaobabError

if TYPE_CHECKING:
    from baobab.missions.language.btcpp_log import BtLogWriter
    from baobab.missions.run.recording_streams import Streams
    from baobab.missions.run.rig import Rig
    from baobab.sim.recording import Recorder
    from baobab.sim.rendering import Camera, VideoRecorder

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8765
DEFAULT_FPS = 30
DEFAULT_VIDEO_SIZE = (640, 480)
FEEDBACK_PERIOD = 1.0
"""Running tasks' feedback goes to ``/task/feedback`` this often (s of sim time)."""
NO_DISPLAY_WARNING = (
    "--viewer: no display (neither DISPLAY nor WAYLAND_DISPLAY is set); running headless, "
    "the run folder's plot.png shows the run"
)


@dataclass(frozen=True)
class RecordingOptions:
    """What watches a run (all off by default).

    Attributes:
        record: MCAP file to write.
        live: serve the run to Foxglove over WebSocket at ``host``:``port`` (0: any free
            port), paced to the wall clock.
        host: address the live server binds.
        port: TCP port of the live server.
        video: MP4 file to film the run into.
        fps: video frames per second of sim time.
        video_size: video (width, height) in pixels, both even.
        btlog: Groot2 ``.btlog`` file for the tree's status changes.
        viewer: show MuJoCo's viewer (needs a display).
    """

    record: Path | None = None
    live: bool = False
    host: str = DEFAULT_HOST
    port: int = DEFAULT_PORT
    video: Path | None = None
    fps: int = DEFAULT_FPS
    video_size: tuple[int, int] = DEFAULT_VIDEO_SIZE
    btlog: Path | None = None
    viewer: bool = False

    @property
    def enabled(self) -> bool:
        """True when anything is asked for."""
        return bool(self.record or self.live or self.video or self.btlog or self.viewer)


@dataclass(frozen=True)
class _TreeNode:
    uid: int
    behaviour: py_trees.behaviour.Behaviour
    path: str
    type: str


class RecordingHook:
    """Starts the observers ``options`` asks for; call :meth:`after_tick` and :meth:`close`.

    Args:
        options: what to start.
        rig: the robot, its sim and servers.
        compiled: the compiled tree.
        warn: receives messages for people (the live URL, no display).

    Raises:
        BaobabError: a file cannot be written, the port is taken, no OpenGL context.
    """

    def __init__(
        self,
        options: RecordingOptions,
        rig: Rig,
        compiled: CompiledMission,
        *,
        warn: Callable[[str], None],
    ) -> None:
        self.options = options
        self.sim = rig.sim
        self.compiled = compiled
        self._nodes = _tree_nodes(compiled)
        self._goal_leaves = compiled.goal_leaves()
        self._recorder: Recorder | None = None
        self._live_url: str | None = None
        self._warn = warn
        self._live_reports: queue.SimpleQueue[str] = queue.SimpleQueue()
        """What the live server reports from its own thread, passed to ``warn`` at each tick."""
        self._streams: Streams | None = None
        self._video: VideoRecorder | None = None
        self._btlog: BtLogWriter | None = None
        self._viewer: Any = None
        self._ticks = 0
        self._last_feedback = -math.inf
        self._last_status_log = -math.inf
        self._last_statuses: list[py_trees.common.Status] = []
        self._closed = False
        self._failures: dict[str, str] = {}  # output -> why it stopped early
        self._warn = warn
        try:
            if options.record is not None or options.live:
                self._start_recorder(rig, warn)
            if options.btlog is not None:
                self._start_btlog(options.btlog)
            if options.video is not None:
                self._start_video(rig, options.video)
            if options.viewer:
                self._start_viewer(warn)
        except BaseException:
            self.close()
            raise

    def _stopper(self, output: str, flag: str) -> Callable[[str], None]:
        """What to call when the disk refuses ``output``: one line, and the run goes on."""
        path = getattr(self.options, {"mcap": "record"}.get(output, output))

        def stopped(reason: str) -> None:
            self._failures[output] = reason
            self._warn(f"{flag} {path}: {reason}; stopped, no file kept, the run goes on")

        return stopped

    @property
    def needs_pacing(self) -> bool:
        """True when the run must follow the wall clock (live view, open viewer)."""
        return self.options.live or self._viewer is not None

    # -- starting ----------------------------------------------------------------------------

    def _start_recorder(self, rig: Rig, warn: Callable[[str], None]) -> None:
        from baobab.missions.run.recording_streams import ArmStreams, MobileStreams
        from baobab.missions.run.rig import ArmRig, MobileRig
        from baobab.sim.recording import LiveSink, McapSink, Recorder, Sink

        options = self.options
        # The server first: a port in use then fails before the file is created.
        live = (
            LiveSink(options.host, options.port, report=self._live_reports.put)
            if options.live
            else None
        )
        sinks: list[Sink] = [] if live is None else [live]
        if options.record is not None:
            sinks.append(McapSink(options.record, on_failure=self._stopper("mcap", "--record")))
        origin = time.time_ns() if options.live else 0
        self._recorder = recorder = Recorder(sinks, time_origin_ns=origin)
        if live is not None:
            self._live_url = live.url
            warn(f"live: open Foxglove and connect to {live.url}")
        if isinstance(rig, MobileRig):
            self._streams = MobileStreams(recorder, rig)
        elif isinstance(rig, ArmRig):
            self._streams = ArmStreams(recorder, rig)

    def _start_btlog(self, path: Path) -> None:
        from baobab.missions.language.btcpp_log import BtLogWriter

        xml = to_btcpp_log(self.compiled.mission)
        if xml.count(' _uid="') != len(self._nodes):  # one behaviour per mission node
            raise BaobabError(f"{path}: the tree XML does not match the compiled tree")
        self._btlog = BtLogWriter(
            path,
            xml,
            start_time_us=time.time_ns() // 1000,
            on_failure=self._stopper("btlog", "--btlog"),
        )

    def _start_video(self, rig: Rig, path: Path) -> None:
        from baobab.missions.run.video_caption import VideoCaption
        from baobab.sim.rendering import VideoRecorder

        width, height = self.options.video_size
        self._video = VideoRecorder(
            self.sim,
            path,
            video_camera(rig, width / height),
            fps=self.options.fps,
            width=width,
            height=height,
            caption=VideoCaption(self.compiled),
            on_failure=self._stopper("video", "--video"),
        )

    def _start_viewer(self, warn: Callable[[str], None]) -> None:
        from baobab.sim.viewer import open_viewer

        self._viewer = open_viewer(
            self.sim.model, self.sim.data, report=lambda _: warn(NO_DISPLAY_WARNING)
        )

    # -- every tick --------------------------------------------------------------------------

    def after_tick(self) -> None:
        """Log the tree (and the tasks' feedback each second); sync the viewer."""
        now = self.sim.time
        self._ticks += 1
        self._pass_live_reports()
        self._log_tree(now)
        recorder = self._recorder
        if recorder is not None and now - self._last_feedback >= FEEDBACK_PERIOD - 1e-9:
            self._last_feedback = now
            self._log_feedback(recorder, now)
        if self._viewer is not None:
            self._viewer.sync()

    def _pass_live_reports(self) -> None:
        """Pass what the live server reported to ``warn``, from the run's thread.

        ``warn`` need not be thread-safe: a forked run sends warnings down a pipe.
        """
        while not self._live_reports.empty():
            self._warn(self._live_reports.get())

    def _log_tree(self, now: float, *, final: bool = False) -> None:
        statuses = [node.behaviour.status for node in self._nodes]
        recorder = self._recorder
        # Statuses change only at ticks: log on change, and once a second for live clients.
        changed = statuses != self._last_statuses
        if recorder is not None and (changed or final or now - self._last_status_log >= 1.0):
            from baobab.missions.run.recording_topics import TREE_STATUS_SCHEMA, Topics

            self._last_status_log = now
            payload = {
                "tick": self._ticks,
                "root_status": self.compiled.root.status.name,
                "nodes": [
                    {
                        "uid": node.uid,
                        "path": node.path,
                        "name": node.behaviour.name,
                        "type": node.type,
                        "status": status.name,
                        "message": node.behaviour.feedback_message,
                    }
                    for node, status in zip(self._nodes, statuses, strict=True)
                ],
            }
            recorder.log_json(Topics.TREE_STATUS, now, payload, schema=TREE_STATUS_SCHEMA)
        if self._btlog is not None and changed:
            from baobab.missions.language.btcpp_log import PY_TREES_STATUS

            self._btlog.update(
                now,
                {
                    node.uid: PY_TREES_STATUS[status.name]
                    for node, status in zip(self._nodes, statuses, strict=True)
                },
            )
        self._last_statuses = statuses

    def _log_feedback(self, recorder: Recorder, now: float) -> None:
        from baobab.missions.run.recording_topics import TASK_FEEDBACK_SCHEMA, Topics

        for leaf in self._goal_leaves:
            handle = leaf.handle
            if leaf.status is py_trees.common.Status.RUNNING and handle is not None:
                payload = {"task": handle.name, "node": leaf.name, **_plain(handle.feedback)}
                recorder.log_json(Topics.TASK_FEEDBACK, now, payload, schema=TASK_FEEDBACK_SCHEMA)

    # -- the end -----------------------------------------------------------------------------

    def close(self) -> None:
        """Log the final tree state and finish every file (idempotent, also after errors)."""
        if self._closed:
            return
        self._closed = True
        closers: list[Callable[[], None]] = []
        if self._ticks:
            closers.append(lambda: self._log_tree(self.sim.time, final=True))
        for part in (self._streams, self._recorder, self._video, self._btlog, self._viewer):
            if part is not None:
                closers.append(part.close)
        closers.append(self._pass_live_reports)
        _run_all(closers)

    def outputs(self) -> dict[str, Any]:
        """What was written or served, for the result object (paths, URL, frames)."""
        options = self.options
        outputs: dict[str, Any] = {}
        if options.record is not None and "mcap" not in self._failures:
            outputs["mcap"] = str(options.record)
        if self._live_url is not None:
            outputs["live"] = self._live_url
        if options.video is not None and self._video is not None and "video" not in self._failures:
            outputs["video"] = str(options.video)
            outputs["video_frames"] = self._video.frames_written
        if options.btlog is not None and "btlog" not in self._failures:
            outputs["btlog"] = str(options.btlog)
        if self._failures:
            outputs["stopped"] = dict(self._failures)
        return outputs


def video_camera(rig: Rig, aspect: float) -> Camera:
    """What films ``rig``'s run: a chase camera behind a mobile robot, an arm's scene view.

    Args:
        rig: the robot, in its start state.
        aspect: the video's width over its height.
    """
    from baobab.missions.run.rig import ArmRig, MobileRig
    from baobab.sim.chase_camera import ChaseCamera

    if isinstance(rig, MobileRig):
        return ChaseCamera(rig.robot.names.body)
    if not isinstance(rig, ArmRig):  # pragma: no cover - every rig is one of the two
        raise TypeError(f"no camera for {type(rig).__name__}")
    return rig.runtime.video_view(rig.sim, aspect)


def _tree_nodes(compiled: CompiledMission) -> list[_TreeNode]:
    """Every behaviour in pre-order with its uid (from 1), slash path and mission node type."""
    paths: dict[Any, str] = {}
    nodes = []
    for uid, behaviour in enumerate(preorder(compiled.root), start=1):
        parent = behaviour.parent
        prefix = paths.get(parent.id, "") if parent is not None else ""
        paths[behaviour.id] = path = f"{prefix}/{behaviour.name}"
        node = compiled.nodes.get(behaviour.id)
        nodes.append(
            _TreeNode(uid, behaviour, path, node.type if node else type(behaviour).__name__)
        )
    return nodes


def _plain(feedback: Mapping[str, Any]) -> dict[str, Any]:
    """Task feedback as JSON data; non-finite numbers become null (Foxglove plots gaps)."""
    from baobab.missions.run.trace import jsonable  # numpy: not needed by the `baobab` parser

    def convert(value: Any) -> Any:
        if isinstance(value, float) and not math.isfinite(value):
            return None
        if isinstance(value, Mapping):
            return {str(k): convert(v) for k, v in value.items()}
        if isinstance(value, list | tuple):
            return [convert(v) for v in value]
        return jsonable(value, None)

    return {str(key): convert(value) for key, value in feedback.items()}


def _run_all(calls: list[Callable[[], None]]) -> None:
    """Call each in turn even if some raise; re-raise the first error."""
    error: BaseException | None = None
    for call in calls:
        try:
            call()
        except BaseException as exc:  # finish the other files first
            error = error or exc
    if error is not None:
        raise error
