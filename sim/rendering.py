"""Offscreen rendering of a run: frames from a camera pose, a caption, and an H.264 video.

A :class:`VideoRecorder` films a simulation: at every frame time a camera operator decides the
pose (:class:`~baobab.sim.chase_camera.ChaseOperator` follows a body and keeps it in sight, a
:class:`~baobab.sim.camera.CameraPose` computed beforehand stays put), the frame is rendered,
the sim time and a caption are written into it (Pillow), and it is encoded.

MuJoCo picks its OpenGL backend when ``mujoco`` is first imported, from ``MUJOCO_GL``. Without
a display this module sets ``MUJOCO_GL=egl`` by default before importing mujoco, which is enough
when it is imported first; when mujoco was imported earlier with no backend chosen and there is no
display, :class:`OffscreenRenderer` switches MuJoCo's classic renderer to EGL itself
(``MUJOCO_GL=egl`` works headless via Mesa's llvmpipe, about 83 ms per 640x480 frame).

Videos are encoded with PyAV (FFmpeg libraries bundled in its wheel) and captioned with Pillow
(both in the ``video`` extra).
"""

from __future__ import annotations

import os

# mujoco reads MUJOCO_GL once, when first imported; headless, only EGL (or OSMesa) can render.
if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    os.environ.setdefault("MUJOCO_GL", "egl")

import functools
import math
from collections.abc import Callable, Sequence
from fractions import Fraction
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from baobab.sim.camera import ALL_GEOM_GROUPS, CameraOperator, CameraPose, StillOperator
from baobab.sim.chase_camera import ChaseCamera, ChaseOperator
from baobab.sim.closable import Closable
from baobab.sim.errors import RenderingError
from baobab.sim.output_file import OutputFile
from baobab.sim.simulation import PeriodicHandle, Simulation

__all__ = [
    "Camera",
    "FrameClock",
    "OffscreenRenderer",
    "RenderingError",
    "VideoRecorder",
    "VideoWriter",
    "camera_operator",
    "draw_caption",
]

Camera = CameraPose | ChaseCamera
"""What films a run: a fixed pose, or a chase camera that follows a body."""

_BAND_SHADE = 105
"""Brightness (of 255) left to the frame behind a caption."""

Caption = Callable[[], Sequence[str]]
"""Lines of text for the frame being filmed (what the run is doing now)."""


def camera_operator(
    model: mujoco.MjModel, camera: Camera, geom_groups: tuple[int, ...] = ALL_GEOM_GROUPS
) -> CameraOperator:
    """What poses ``camera`` frame after frame.

    Raises:
        RenderingError: a chase camera's body is not in the model.
    """
    if isinstance(camera, ChaseCamera):
        return ChaseOperator(model, camera, geom_groups)
    return StillOperator(camera)


def _use_egl_without_display() -> None:
    """Point MuJoCo's classic renderer at EGL if it chose GLFW and no display exists."""
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return
    from mujoco.rendering.classic import gl_context

    current = getattr(gl_context, "GLContext", None)
    if current is not None and current.__module__.startswith(("mujoco.egl", "mujoco.osmesa")):
        return
    from mujoco.egl import GLContext

    gl_context.GLContext = GLContext


class OffscreenRenderer(Closable):
    """Render RGB frames of a model from camera poses, robot geoms (group 3) included.

    Args:
        model: the compiled model; its offscreen buffer is enlarged if smaller than the frame.
        width: frame width (pixels).
        height: frame height (pixels).
        geom_groups: geom groups to draw (default: all six, so robots in group 3 show).

    Raises:
        RenderingError: for a non-positive size, or when no OpenGL context can be created.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        *,
        width: int = 640,
        height: int = 480,
        geom_groups: tuple[int, ...] = ALL_GEOM_GROUPS,
    ) -> None:
        if width <= 0 or height <= 0:
            raise RenderingError(f"frame size must be positive, got {width}x{height}")
        self.width, self.height = width, height
        self.geom_groups = geom_groups
        self.camera = mujoco.MjvCamera()
        self.camera.type = mujoco.mjtCamera.mjCAMERA_FREE
        self.option = mujoco.MjvOption()
        self.option.geomgroup[:] = 0
        for group in geom_groups:
            self.option.geomgroup[group] = 1
        model.vis.global_.offwidth = max(model.vis.global_.offwidth, width)
        model.vis.global_.offheight = max(model.vis.global_.offheight, height)
        _use_egl_without_display()
        try:
            self._renderer = mujoco.Renderer(model, height=height, width=width)
        except Exception as error:
            raise RenderingError(
                f"cannot create an OpenGL context ({error}); on a machine without a display "
                "set MUJOCO_GL=egl before Python starts"
            ) from error

    def render(self, data: mujoco.MjData, pose: CameraPose) -> np.ndarray:
        """An RGB frame (height, width, 3) uint8 of ``data``'s current state seen from ``pose``."""
        camera = self.camera
        camera.lookat[:] = pose.lookat
        camera.distance, camera.azimuth, camera.elevation = (
            pose.distance,
            pose.azimuth,
            pose.elevation,
        )
        self._renderer.update_scene(data, camera=camera, scene_option=self.option)
        return self._renderer.render()

    def close(self) -> None:
        """Free the OpenGL context (idempotent)."""
        self._renderer.close()


def draw_caption(rgb: np.ndarray, lines: Sequence[str]) -> np.ndarray:
    """A copy of ``rgb`` (height, width, 3) uint8 with ``lines`` written bottom left.

    The text is white on the frame darkened behind it, at the bottom: the ground in front of
    the scene, where text hides least. It is about 1/24 of the frame high; lines too long for
    the frame are cut.
    """
    from PIL import Image, ImageDraw

    if not lines:
        return rgb
    height, width = rgb.shape[:2]
    size = max(8, height // 24)
    font = _font(size)
    pad, line_height = size // 2, size + size // 3
    measure = ImageDraw.Draw(Image.new("L", (1, 1)))
    texts = [_fit(measure, font, line, width - 2 * pad) for line in lines]
    right = min(width, math.ceil(max(measure.textlength(t, font=font) for t in texts)) + 2 * pad)
    top = max(0, height - 2 * pad - len(texts) * line_height + size // 3)
    darkened = (rgb[top:, :right].astype(np.uint16) * _BAND_SHADE // 255).astype(np.uint8)
    band = Image.fromarray(darkened)
    draw = ImageDraw.Draw(band)
    for row, text in enumerate(texts):
        draw.text((pad, pad + row * line_height), text, font=font, fill=(255, 255, 255))
    captioned = rgb.copy()
    captioned[top:, :right] = np.asarray(band)
    return captioned


@functools.lru_cache(maxsize=4)
def _font(size: int) -> Any:
    """Pillow's bundled font at ``size`` pixels (one small bitmap font before Pillow 10.1)."""
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=size)
    except TypeError:
        return ImageFont.load_default()


def _fit(draw: Any, font: Any, text: str, width: float) -> str:
    """``text`` cut with an ellipsis to ``width`` pixels."""
    if draw.textlength(text, font=font) <= width:
        return text
    while text and draw.textlength(text + "…", font=font) > width:
        text = text[:-1]
    return text + "…"


class VideoWriter:
    """Encode RGB frames as H.264 (yuv420p) in an MP4 file, at a constant frame rate.

    Args:
        path: the .mp4 file to write (replaced if present).
        fps: frames per second.
        width: frame width (pixels, even: yuv420p halves the chroma resolution).
        height: frame height (pixels, even).
        crf: x264 constant rate factor: 18 near lossless, 23 default, higher is smaller.
        on_failure: told once why filming stopped when the disk refuses a write (the file is
            then dropped, nothing stays under its name); without it, :meth:`close` raises.

    Raises:
        RenderingError: for odd or non-positive sizes, a non-positive fps, a missing folder or
            a missing PyAV (install ``baobab[video]``).
    """

    def __init__(
        self,
        path: str | Path,
        *,
        fps: int = 30,
        width: int = 640,
        height: int = 480,
        crf: int = 23,
        on_failure: Callable[[str], None] | None = None,
    ) -> None:
        if width <= 0 or height <= 0 or width % 2 or height % 2:
            raise RenderingError(f"video size must be positive and even, got {width}x{height}")
        if fps <= 0:
            raise RenderingError(f"video fps must be positive, got {fps}")
        self.path = Path(path)
        if not self.path.parent.is_dir():
            raise RenderingError(f"{self.path}: cannot write video, folder missing")
        try:
            import av
        except ImportError as error:
            raise RenderingError("video needs PyAV: pip install 'baobab[video]'") from error
        self.width, self.height, self.fps = width, height, fps
        self.frames_written = 0
        self._on_failure = on_failure
        self._file = OutputFile(self.path, on_failure)  # disk full: stops, the run goes on
        try:
            self._container: Any = av.open(self._file, mode="w", format="mp4")
        except BaseException:
            self._file.discard()
            raise
        self._stream: Any = self._container.add_stream("libx264", rate=fps)
        self._stream.width, self._stream.height = width, height
        self._stream.pix_fmt = "yuv420p"
        self._stream.time_base = Fraction(1, fps)
        self._stream.options = {"crf": str(crf), "preset": "veryfast"}
        self._frame_type = av.VideoFrame

    def write(self, rgb: np.ndarray) -> None:
        """Append one frame, an RGB (height, width, 3) uint8 array."""
        if self._container is None:
            raise RenderingError(f"{self.path}: the video is closed")
        if rgb.shape != (self.height, self.width, 3) or rgb.dtype != np.uint8:
            raise RenderingError(
                f"frame must be ({self.height}, {self.width}, 3) uint8, got {rgb.shape} {rgb.dtype}"
            )
        frame = self._frame_type.from_ndarray(rgb, format="rgb24")
        frame.pts = self.frames_written
        self._container.mux(self._stream.encode(frame))
        self.frames_written += 1

    def close(self) -> None:
        """Flush the encoder and finish the file (idempotent)."""
        if self._container is not None:
            self._container.mux(self._stream.encode(None))
            self._container.close()
            self._container = None
            self._file.close()
            if self._file.failure is not None and self._on_failure is None:
                raise RenderingError(f"{self.path}: cannot write video: {self._file.failure}")


class FrameClock:
    """Call ``on_frame(time)`` every ``1 / fps`` s of sim time, from now until closed.

    Frame ``k`` is taken at the physics step nearest ``t0 + k / fps`` (within half a physics
    step), so a video plays at real time whatever the step. Frames are taken inside the
    simulation's callbacks; nothing else needs calling.

    Args:
        sim: the simulation.
        fps: frames per second of sim time.
        on_frame: called with the sim time (s) of each frame.
    """

    def __init__(self, sim: Simulation, fps: int, on_frame: Callable[[float], None]) -> None:
        if fps <= 0:
            raise RenderingError(f"video fps must be positive, got {fps}")
        self._sim = sim
        self._on_frame = on_frame
        self._steps_per_frame = 1.0 / (fps * sim.physics_dt)
        self._first_step = sim.step_count
        self._handle: PeriodicHandle | None = None
        self.frame_times: list[float] = []
        """Sim time (s) of every frame taken."""
        self._frame(sim.time)

    def _frame(self, _time: float) -> None:
        sim = self._sim
        if self._handle is not None:
            self._handle.cancel()
        self._on_frame(sim.time)
        self.frame_times.append(sim.time)
        # One-shot schedule of the next frame: 1/fps is rarely a whole number of steps.
        next_step = self._first_step + round(len(self.frame_times) * self._steps_per_frame)
        wait = max(1, next_step - sim.step_count) * sim.physics_dt
        self._handle = sim.every(wait, self._frame, name="video frame", first_call=sim.time + wait)

    def close(self) -> None:
        """Take no more frames (idempotent)."""
        if self._handle is not None:
            self._handle.cancel()
            self._handle = None


class VideoRecorder:
    """Film a simulation: one captioned frame every ``1 / fps`` s of sim time until closed.

    Each frame shows the sim time and, below it, the lines ``caption`` returns then.

    Args:
        sim: the simulation to film.
        path: the .mp4 file.
        camera: a fixed pose or a chase camera.
        fps: frames per second of sim time.
        width: frame width (pixels, even).
        height: frame height (pixels, even).
        caption: what the run is doing, asked at every frame (e.g. the task and its goal).
        on_failure: told once why filming stopped if the disk refuses a write (see
            :class:`VideoWriter`).
    """

    def __init__(
        self,
        sim: Simulation,
        path: str | Path,
        camera: Camera,
        *,
        fps: int = 30,
        width: int = 640,
        height: int = 480,
        caption: Caption | None = None,
        on_failure: Callable[[str], None] | None = None,
    ) -> None:
        self._sim = sim
        self._operator = camera_operator(sim.model, camera)
        self._caption = caption
        self._writer = VideoWriter(path, fps=fps, width=width, height=height, on_failure=on_failure)
        try:
            self._renderer = OffscreenRenderer(sim.model, width=width, height=height)
        except BaseException:
            self._writer.close()
            raise
        self.poses: list[CameraPose] = []
        """The camera pose of every frame written."""
        try:
            self._clock = FrameClock(sim, fps, self._film)  # films the first frame now
        except BaseException:
            self._renderer.close()
            self._writer.close()
            raise

    @property
    def frames_written(self) -> int:
        """Frames encoded so far."""
        return self._writer.frames_written

    @property
    def frame_times(self) -> list[float]:
        """Sim time (s) of every frame written."""
        return self._clock.frame_times

    def _film(self, time: float) -> None:
        data = self._sim.data
        pose = self._operator.pose(data, time)
        lines = [f"t = {time:.2f} s", *(self._caption() if self._caption else ())]
        self._writer.write(draw_caption(self._renderer.render(data, pose), lines))
        self.poses.append(pose)

    def close(self) -> None:
        """Stop filming and finish the file (idempotent)."""
        self._clock.close()
        self._renderer.close()
        self._writer.close()
