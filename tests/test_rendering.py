"""Offscreen rendering, camera poses, captions, H.264 video, and the viewer's no-display path."""

from __future__ import annotations

from itertools import pairwise
from pathlib import Path

import av
import numpy as np
import pytest

from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.camera import CameraPose
from baobab.sim.chase_camera import ChaseCamera
from baobab.sim.rendering import (
    OffscreenRenderer,
    RenderingError,
    VideoRecorder,
    VideoWriter,
    draw_caption,
)
from baobab.sim.viewer import NO_DISPLAY_MESSAGE, RealTimePacer, display_available, open_viewer
from baobab.sim.world import load_world

BASE = "tb3/base_link"


def test_video_of_a_moving_turtlebot3_reads_back_as_h264(tmp_path: Path) -> None:
    sim, robot = build_turtlebot3_sim(load_world("walls"), seed=0)
    robot.base.command(0.2, 0.8)
    path = tmp_path / "run.mp4"
    video = VideoRecorder(sim, path, ChaseCamera(BASE), fps=10, width=160, height=120)
    sim.step_for(1.0)
    video.close()
    video.close()  # idempotent
    assert video.frames_written == 10  # frames at 0.0, 0.1, ..., 0.9 s
    sim.step_for(0.2)  # no frame after close
    assert video.frames_written == 10

    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        assert stream.codec_context.name == "h264"
        assert (stream.width, stream.height) == (160, 120)
        assert stream.average_rate == 10
        frames = [frame.to_ndarray(format="rgb24") for frame in container.decode(stream)]
    assert len(frames) == 10
    assert all(frame.shape == (120, 160, 3) for frame in frames)
    changes = [np.abs(b.astype(int) - a.astype(int)).mean() for a, b in pairwise(frames)]
    assert min(changes) > 0.1  # the robot moves, so the tracked view changes every frame


def test_frames_land_on_the_nearest_step_when_the_period_is_not_whole_steps(
    tmp_path: Path,
) -> None:
    sim, _ = build_turtlebot3_sim(load_world("walls"), seed=0)
    sim.step_for(0.1)
    # 1/30 s is 6.67 physics steps of 5 ms: frame k is due at step 20 + round(k * 200 / 30).
    video = VideoRecorder(sim, tmp_path / "v.mp4", ChaseCamera(BASE), fps=30, width=32, height=24)
    sim.step_for(0.5)
    video.close()
    expected = [(20 + round(k * 200 / 30)) * sim.physics_dt for k in range(15)]
    np.testing.assert_allclose(video.frame_times, expected, atol=1e-12)
    assert video.frames_written == 15


def test_the_renderer_looks_from_the_pose_it_is_given_and_draws_robot_geoms() -> None:
    sim, robot = build_turtlebot3_sim(load_world("walls"), seed=0)
    robot.base.command(0.22, 0.0)
    sim.step_for(1.0)
    x, y, z = (float(v) for v in sim.data.subtree_com[sim.model.body(BASE).id])
    pose = CameraPose((x, y, z), 1.0, 135.0, -35.0)
    with OffscreenRenderer(sim.model, width=80, height=60) as renderer:
        with_robot = renderer.render(sim.data, pose)
        np.testing.assert_allclose(renderer.camera.lookat, (x, y, z))
        assert renderer.option.geomgroup[3] == 1
    with OffscreenRenderer(sim.model, width=80, height=60, geom_groups=(0, 1, 2)) as renderer:
        without_robot = renderer.render(sim.data, pose)
    # The robot sits in the middle of the view: hiding group 3 changes the centre.
    centre = np.s_[20:40, 30:50]
    assert np.abs(with_robot[centre].astype(int) - without_robot[centre].astype(int)).mean() > 5


def test_a_caption_is_written_bottom_left_and_cut_to_the_frame() -> None:
    frame = np.full((240, 320, 3), 200, dtype=np.uint8)
    captioned = draw_caption(frame, ["t = 1.50 s", "task: go_to_goal " + "x" * 200])
    changed = np.abs(captioned.astype(int) - frame.astype(int)).max(axis=2) > 0
    rows, columns = np.nonzero(changed)
    assert rows.min() > 240 // 2 and rows.max() == 239  # a band at the bottom
    assert columns.min() == 0 and 300 < columns.max() < 320  # the long line is cut to fit
    band = captioned[rows.min() :, :]
    assert (band.max(axis=2) > 150).mean() > 0.02  # light text
    assert (band.max(axis=2) < 110).mean() > 0.5  # on a dark band
    assert draw_caption(frame, []) is frame


def test_rendering_rejects_bad_input(tmp_path: Path) -> None:
    sim, _ = build_turtlebot3_sim(load_world("walls"), seed=0)
    with pytest.raises(RenderingError, match="no body named 'ghost'"):
        VideoRecorder(sim, tmp_path / "ghost.mp4", ChaseCamera("ghost"))
    assert not (tmp_path / "ghost.mp4").exists()
    with pytest.raises(RenderingError, match="even"):
        VideoWriter(tmp_path / "odd.mp4", width=161, height=120)
    with pytest.raises(RenderingError, match="fps"):
        VideoWriter(tmp_path / "zero.mp4", fps=0)
    with pytest.raises(RenderingError, match="folder"):
        VideoWriter(tmp_path / "missing" / "v.mp4")
    writer = VideoWriter(tmp_path / "v.mp4", width=32, height=24)
    with pytest.raises(RenderingError, match=r"\(24, 32, 3\) uint8"):
        writer.write(np.zeros((24, 32, 4), dtype=np.uint8))
    writer.close()
    with pytest.raises(RenderingError, match="closed"):
        writer.write(np.zeros((24, 32, 3), dtype=np.uint8))


def test_viewer_without_display_returns_none_and_says_why() -> None:
    sim, _ = build_turtlebot3_sim(load_world("walls"), seed=0)
    messages: list[str] = []
    handle = open_viewer(sim.model, sim.data, report=messages.append, environ={"HOME": "/root"})
    assert handle is None
    assert messages == [NO_DISPLAY_MESSAGE]
    assert "no display" in NO_DISPLAY_MESSAGE
    assert not display_available({"DISPLAY": ""})
    assert display_available({"DISPLAY": ":0"})
    assert display_available({"WAYLAND_DISPLAY": "wayland-0"})


def test_real_time_pacer_sleeps_until_the_wall_clock_catches_up() -> None:
    wall = [100.0]
    sleeps: list[float] = []

    def sleep(seconds: float) -> None:
        sleeps.append(seconds)
        wall[0] += seconds

    pacer = RealTimePacer(2.0, clock=lambda: wall[0], sleep=sleep)
    assert pacer.wait(5.0) == 0.0  # sets the origin
    wall[0] += 0.1
    assert pacer.wait(6.0) == pytest.approx(0.4)  # 1 sim s at 2x is 0.5 wall s
    wall[0] += 3.0  # fell behind by far: no sleep, re-anchored
    assert pacer.wait(6.5) == 0.0
    assert pacer.wait(7.5) == pytest.approx(0.5)
    assert sleeps == pytest.approx([0.4, 0.5])
    with pytest.raises(ValueError, match="positive"):
        RealTimePacer(0.0)
