"""Offscreen rendering of a run: a camera that tracks a body or stays fixed, and an H.264 video.

MuJoCo picks its OpenGL backend when ``mujoco`` is first imported, from ``MUJOCO_GL``. Without
a display this module sets ``MUJOCO_GL=egl`` by default before importing mujoco, which is enough
when it is imported first; when mujoco was imported earlier with no backend chosen and there is no
display, :class:`OffscreenRenderer` switches MuJoCo's classic renderer to EGL itself
(``MUJOCO_GL=egl`` works headless via Mesa's llvmpipe, about 83 ms per 640x480 frame).

Videos are encoded with PyAV (FFmpeg libraries bundled in its wheel; the ``video`` extra).
"""

from __future__ import annotations

import os

# mujoco reads MUJOCO_GL once, when first imported; headless, only EGL (or OSMesa) can render.
if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
    os.environ.setdefault("MUJOCO_GL", "egl")

from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from baobab.sim.closable import Closable
from baobab.sim.errors import BaobabError
from baobab.sim.simulation import PeriodicHandle, Simulation


class RenderingError(BaobabError):
    """A frame could not be rendered or a video could not be written."""


@dataclass(frozen=True)
class TrackingCamera:
    """A camera that follows a body (the centre of mass of its subtree) from a fixed offset.

    Attributes:
        body: name of the body to follow (e.g. ``tb3/base_link``).
        distance: from the look-at point (m).
        azimuth: heading of the camera around the vertical (deg).
        elevation: angle above (negative: looking down at) the look-at point (deg).
    """

    body: str
    distance: float = 2.0
    azimuth: float = 135.0
    elevation: float = -35.0


@dataclass(frozen=True)
class FixedCamera:
    """A free camera looking at a point (m) from a distance (m), azimuth and elevation (deg)."""

    lookat: tuple[float, float, float]
    distance: float
    azimuth: float
    elevation: float


Camera = TrackingCamera | FixedCamera

PANDA_VIEW = FixedCamera(lookat=(0.3, 0.0, 0.75), distance=2.1, azimuth=140.0, elevation=-22.0)
"""A 3/4 view of the Panda scene: arm, table top, cube and place target."""


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
    """Render RGB frames of a model from a :data:`Camera`, robot geoms (group 3) included.

    Args:
        model: the compiled model; its offscreen buffer is enlarged if smaller than the frame.
        camera: a tracking or fixed camera.
        width: frame width (pixels).
        height: frame height (pixels).
        geom_groups: geom groups to draw (default: all six, so robots in group 3 show).

    Raises:
        RenderingError: for a body the model does not have, a non-positive size, or when no
            OpenGL context can be created.
    """

    def __init__(
        self,
        model: mujoco.MjModel,
        camera: Camera,
        *,
        width: int = 640,
        height: int = 480,
        geom_groups: tuple[int, ...] = (0, 1, 2, 3, 4, 5),
    ) -> None:
        if width <= 0 or height <= 0:
            raise RenderingError(f"frame size must be positive, got {width}x{height}")
        self.width, self.height = width, height
        self.camera = self._make_camera(model, camera)
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

    @staticmethod
    def _make_camera(model: mujoco.MjModel, spec: Camera) -> mujoco.MjvCamera:
        camera = mujoco.MjvCamera()
        if isinstance(spec, TrackingCamera):
            body_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, spec.body)
            if body_id < 0:
                raise RenderingError(f"no body named '{spec.body}' to track")
            camera.type = mujoco.mjtCamera.mjCAMERA_TRACKING
            camera.trackbodyid = body_id
        else:
            camera.type = mujoco.mjtCamera.mjCAMERA_FREE
            camera.lookat[:] = spec.lookat
        camera.distance = spec.distance
        camera.azimuth = spec.azimuth
        camera.elevation = spec.elevation
        return camera

    def render(self, data: mujoco.MjData) -> np.ndarray:
        """An RGB frame (height, width, 3) uint8 of ``data``'s current state."""
        self._renderer.update_scene(data, camera=self.camera, scene_option=self.option)
        return self._renderer.render()

    def close(self) -> None:
        """Free the OpenGL context (idempotent)."""
        self._renderer.close()


class VideoWriter:
    """Encode RGB frames as H.264 (yuv420p) in an MP4 file, at a constant frame rate.

    Args:
        path: the .mp4 file to write (replaced if present).
        fps: frames per second.
        width: frame width (pixels, even: yuv420p halves the chroma resolution).
        height: frame height (pixels, even).
        crf: x264 constant rate factor: 18 near lossless, 23 default, higher is smaller.

    Raises:
        RenderingError: for odd or non-positive sizes, a non-positive fps, a missing folder or
            a missing PyAV (install ``baobab[video]``).
    """

    def __init__(
        self, path: str | Path, *, fps: int = 30, width: int = 640, height: int = 480, crf: int = 23
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
        self._container: Any = av.open(str(self.path), mode="w")
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


class VideoRecorder:
    """Film a simulation: one frame every ``1 / fps`` s of sim time, from now until closed.

    Frame ``k`` shows the state at the physics step nearest ``t0 + k / fps`` (within half a
    physics step), so the video plays at real time whatever the step. Frames are rendered
    inside the simulation's callbacks; nothing else needs calling.

    Args:
        sim: the simulation to film.
        path: the .mp4 file.
        camera: a tracking or fixed camera.
        fps: frames per second of sim time.
        width: frame width (pixels, even).
        height: frame height (pixels, even).
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
    ) -> None:
        self._sim = sim
        self._writer = VideoWriter(path, fps=fps, width=width, height=height)
        try:
            self._renderer = OffscreenRenderer(sim.model, camera, width=width, height=height)
        except BaseException:
            self._writer.close()
            raise
        self._steps_per_frame = 1.0 / (fps * sim.physics_dt)
        self._first_step = sim.step_count
        self._handle: PeriodicHandle | None = None
        self.frame_times: list[float] = []
        """Sim time (s) of every frame written."""
        self._capture(sim.time)

    @property
    def frames_written(self) -> int:
        """Frames encoded so far."""
        return self._writer.frames_written

    def _capture(self, _time: float) -> None:
        if self._handle is not None:
            self._handle.cancel()
        self._writer.write(self._renderer.render(self._sim.data))
        self.frame_times.append(self._sim.time)
        # One-shot schedule of the next frame: 1/fps is rarely a whole number of steps.
        next_step = self._first_step + round(self.frames_written * self._steps_per_frame)
        wait = max(1, next_step - self._sim.step_count) * self._sim.physics_dt
        self._handle = self._sim.every(
            wait, self._capture, name="video frame", first_call=self._sim.time + wait
        )

    def close(self) -> None:
        """Stop filming and finish the file (idempotent)."""
        if self._handle is not None:
            self._handle.cancel()
            self._handle = None
        self._renderer.close()
        self._writer.close()
