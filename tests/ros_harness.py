"""Running node files in a ROS runtime, for the tests of baobab.nav.ros."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from baobab.nav.ros.node_files import node_file_main, node_file_paths
from baobab.nav.ros.runtime import RosRuntime, RunEnd

ROS_NODES = Path(__file__).resolve().parent / "ros_nodes"
BUNDLED_NODES = Path(__file__).resolve().parents[1] / "missions" / "ros"
"""The reference nodes bundled with the ros_node example mission."""


def write_nodes(folder: Path, sources: dict[str, str]) -> list[Path]:
    """Write each ``name: source`` as ``folder/name`` and return the paths in order."""
    paths = []
    for name, source in sources.items():
        path = folder / name
        path.write_text(source)
        paths.append(path)
    return paths


def run_node_files(
    runtime: RosRuntime,
    paths: Sequence[Path],
    duration: float,
    *,
    args: Sequence[str] = (),
    before: Callable[[RosRuntime], None] | None = None,
) -> RunEnd:
    """Run ``paths`` (each with ``args``) in ``runtime`` for ``duration`` s of sim time;
    ``before(runtime)`` schedules events once the ROS modules are served."""
    with runtime.active(), node_file_paths(list(paths)):
        for path in paths:
            runtime.start(
                node_file_main(path), name=path.stem, argv=[str(path), *args], origin=str(path)
            )
        if before is not None:
            before(runtime)
        return runtime.run(duration)
