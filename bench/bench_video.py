"""What a video frame costs: the camera's pose, the render, the caption and the encoding.

Run: ``MUJOCO_GL=egl python bench/bench_video.py [MISSION ...] [--fps N] [--size WxH]``
(default ``walls_go_to_goal`` and ``panda_pick`` at 30 fps, 640x480). Each mission runs once
plain and once filmed, both in this process after a warm-up run; the table gives each stage's
CPU time per frame and how much longer the filmed run took than the plain one.
"""

from __future__ import annotations

import argparse
import collections
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from baobab.missions.language.bundled_missions import resolve_mission
from baobab.missions.language.loader import load_mission
from baobab.missions.run.runner import RecordingOptions, run_mission
from baobab.sim import camera, chase_camera, rendering

_costs: collections.defaultdict[str, float] = collections.defaultdict(float)


def _timed(name: str, work: Callable[..., Any]) -> Callable[..., Any]:
    def run(*args: Any, **kwargs: Any) -> Any:
        began = time.process_time()
        try:
            return work(*args, **kwargs)
        finally:
            _costs[name] += time.process_time() - began

    return run


def _install_timers() -> None:
    chase_camera.ChaseOperator.pose = _timed(  # type: ignore[method-assign]
        "camera pose", chase_camera.ChaseOperator.pose
    )
    camera.StillOperator.pose = _timed("camera pose", camera.StillOperator.pose)  # type: ignore[method-assign]
    rendering.OffscreenRenderer.render = _timed(  # type: ignore[method-assign]
        "render", rendering.OffscreenRenderer.render
    )
    rendering.draw_caption = _timed("caption", rendering.draw_caption)
    rendering.VideoWriter.write = _timed("encode", rendering.VideoWriter.write)  # type: ignore[method-assign]


def measure(name: str, fps: int, size: tuple[int, int]) -> None:
    """Run ``name`` plain and filmed; print each stage's CPU time per frame."""
    mission = load_mission(resolve_mission(name))
    run_mission(mission)  # warm the kernels' caches
    began = time.process_time()
    run_mission(mission)
    plain = time.process_time() - began
    _costs.clear()
    with tempfile.TemporaryDirectory() as folder:
        options = RecordingOptions(video=Path(folder) / "v.mp4", fps=fps, video_size=size)
        began = time.process_time()
        record = run_mission(mission, recording=options)
        filmed = time.process_time() - began
    frames = record.extra["recording"]["video_frames"]
    print(f"{name}: {frames} frames at {fps} fps, {size[0]}x{size[1]}")
    for stage in ("camera pose", "render", "caption", "encode"):
        print(f"  {stage:<12} {1000 * _costs[stage] / frames:8.3f} ms a frame")
    print(f"  run          {plain:8.2f} s plain, {filmed:.2f} s filmed ({filmed / plain:.1f}x)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("missions", nargs="*", default=["walls_go_to_goal", "panda_pick"])
    parser.add_argument("--fps", type=int, default=30)
    parser.add_argument("--size", default="640x480")
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.split("x"))
    _install_timers()
    for name in args.missions:
        measure(name, args.fps, (width, height))


if __name__ == "__main__":
    main()
