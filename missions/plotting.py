"""The run's ``plot.png``: the world from above with the driven path, or the arm's tool path.

A mobile run shows the floor, static and spawned obstacles, the inflated global costmap when
navigation ran, planned paths, the driven trajectory coloured by sim time, where the clearance
was smallest, Bug2's hit and leave points, goals and named locations. An arm run shows the
tool path and the objects' paths in 3D. matplotlib (Agg) is imported only when a plot is
drawn, so runs that write no folder never pay for it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from baobab.missions.events import PlacedObstacle
from baobab.sim.world import World

if TYPE_CHECKING:
    from matplotlib.axes import Axes

Point = tuple[float, float]
MANY_GOALS = 12
"""With more goals than this, goal markers and labels are drawn smaller."""
MAX_TRAJECTORY_POINTS = 2000
"""The driven path is thinned to about this many points for drawing."""


@dataclass(frozen=True)
class CostmapImage:
    """A costmap raster: ``data[iy, ix]`` (0-255 Nav2 costs), lower-left origin (m), cell (m)."""

    data: np.ndarray
    origin: Point
    resolution: float


@dataclass
class MobilePlot:
    """What a mobile run's plot shows (map frame, m)."""

    title: str
    world: World
    times: Sequence[float]
    xs: Sequence[float]
    ys: Sequence[float]
    locations: dict[str, Point] = field(default_factory=dict)
    goals: list[tuple[str, Point]] = field(default_factory=list)
    obstacles: list[PlacedObstacle] = field(default_factory=list)
    costmap: CostmapImage | None = None
    planned_paths: list[np.ndarray] = field(default_factory=list)
    hit_points: list[Point] = field(default_factory=list)
    leave_points: list[Point] = field(default_factory=list)
    min_clearance_at: Point | None = None


@dataclass
class ArmPlot:
    """What an arm run's plot shows (world frame, m)."""

    title: str
    tcp_path: Sequence[tuple[float, float, float]]
    object_paths: dict[str, Sequence[tuple[float, float, float]]] = field(default_factory=dict)
    targets: list[tuple[str, tuple[float, float, float]]] = field(default_factory=list)


PlotData = MobilePlot | ArmPlot


def save_plot(data: PlotData, path: Path) -> None:
    """Draw ``data`` and write it as a PNG to ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    size = (8.0, 8.0)
    if isinstance(data, MobilePlot):
        x_min, y_min, x_max, y_max = data.world.bounds
        aspect = (y_max - y_min) / max(x_max - x_min, 1e-9)
        size = (8.0, min(12.0, max(5.0, 6.5 * aspect + 1.5)))
    figure = Figure(figsize=size, dpi=110, layout="constrained")
    if isinstance(data, MobilePlot):
        _mobile(figure.add_subplot(), data)
    else:
        _arm(figure.add_subplot(projection="3d"), data)
    figure.savefig(path)


def _mobile(axes: Axes, data: MobilePlot) -> None:
    from matplotlib.collections import LineCollection
    from matplotlib.patches import Circle, Polygon, Rectangle

    world = data.world
    x_min, y_min, x_max, y_max = world.bounds
    floor_colour = world.floor.colour[:3]
    axes.add_patch(
        Rectangle((x_min, y_min), x_max - x_min, y_max - y_min, color=floor_colour, zorder=0)
    )
    if data.costmap is not None:
        image = data.costmap
        height, width = image.data.shape
        masked = np.ma.masked_equal(image.data, 0)
        axes.imshow(
            masked,
            origin="lower",
            extent=(
                image.origin[0],
                image.origin[0] + width * image.resolution,
                image.origin[1],
                image.origin[1] + height * image.resolution,
            ),
            cmap="Purples",
            vmin=0,
            vmax=255,
            alpha=0.35,
            zorder=1,
            interpolation="nearest",
        )
    for box in world.boxes:
        axes.add_patch(
            Polygon(_box_corners(box.center, box.size, box.yaw), color=box.colour[:3], zorder=2)
        )
    for cylinder in world.cylinders:
        axes.add_patch(
            Circle(cylinder.center, cylinder.radius, color=cylinder.colour[:3], zorder=2)
        )
    for obstacle in data.obstacles:
        corners = _box_corners((obstacle.x, obstacle.y), obstacle.size[:2], obstacle.yaw)
        axes.add_patch(Polygon(corners, color=(0.85, 0.35, 0.2), hatch="//", zorder=2))
        axes.annotate(obstacle.name, (obstacle.x, obstacle.y), ha="center", fontsize=7, zorder=6)
    for index, path in enumerate(data.planned_paths):
        if len(path):
            axes.plot(
                path[:, 0],
                path[:, 1],
                "--",
                color="tab:blue",
                lw=1.0,
                alpha=0.8 if index == 0 else 0.25,
                zorder=3,
                label="planned paths" if index == 0 else None,
            )
    if len(data.xs) > 1:
        count = len(data.xs)
        kept = np.unique(np.r_[0 : count : max(1, count // MAX_TRAJECTORY_POINTS), count - 1])
        xs, ys = np.asarray(data.xs)[kept], np.asarray(data.ys)[kept]
        times = np.asarray(data.times, dtype=float)[kept]
        points = np.column_stack((xs, ys)).reshape(-1, 1, 2)
        segments = np.concatenate((points[:-1], points[1:]), axis=1)
        line = LineCollection(list(segments), cmap="viridis", linewidths=2.0, zorder=4)
        line.set_array(times[1:])
        axes.add_collection(line)
        figure: Any = axes.figure
        colourbar = figure.colorbar(line, ax=axes, shrink=0.7)
        colourbar.set_label("sim time (s)")
        axes.plot(data.xs[0], data.ys[0], "o", color="black", ms=6, zorder=5, label="start")
        axes.plot(data.xs[-1], data.ys[-1], "s", color="black", ms=6, zorder=5, label="end")
    for label, points_list, marker in (
        ("hit point", data.hit_points, "x"),
        ("leave point", data.leave_points, "+"),
    ):
        if points_list:
            xs, ys = zip(*points_list, strict=True)
            axes.plot(xs, ys, marker, color="crimson", ms=9, mew=2, ls="", zorder=5, label=label)
    if data.min_clearance_at is not None:
        axes.plot(
            *data.min_clearance_at,
            "o",
            mfc="none",
            mec="red",
            ms=12,
            zorder=5,
            label="min clearance",
        )
    goal_names = {label for label, _ in data.goals}
    for name, (x, y) in data.locations.items():
        if name in goal_names:
            continue
        axes.plot(x, y, ".", color="dimgray", ms=5, zorder=5)
        axes.annotate(
            name,
            (x, y),
            xytext=(3, 3),
            textcoords="offset points",
            fontsize=7,
            color="dimgray",
            zorder=6,
        )
    many = len(data.goals) > MANY_GOALS
    for index, (label, (x, y)) in enumerate(data.goals):
        axes.plot(
            x,
            y,
            "*",
            color="gold",
            mec="black",
            ms=7 if many else 12,
            zorder=5,
            label="goal" if index == 0 else None,
        )
        # Named goals carry their name; unnamed ones only their order (coordinates clutter).
        text = f"{index + 1}" if label.startswith("(") else f"{index + 1}: {label}"
        axes.annotate(
            text,
            (x, y),
            xytext=(3, -9),
            textcoords="offset points",
            fontsize=6 if many else 8,
            fontweight="bold",
            zorder=6,
        )
    axes.set_xlim(x_min - 0.2, x_max + 0.2)
    axes.set_ylim(y_min - 0.2, y_max + 0.2)
    axes.set_aspect("equal")
    axes.set_xlabel("x (m)")
    axes.set_ylabel("y (m)")
    axes.set_title(data.title, fontsize=10)
    axes.figure.legend(loc="outside lower center", ncol=7, fontsize=7)


def _box_corners(center: Sequence[float], size: Sequence[float], yaw: float) -> np.ndarray:
    half_x, half_y = size[0] / 2, size[1] / 2
    local = np.array([[-half_x, -half_y], [half_x, -half_y], [half_x, half_y], [-half_x, half_y]])
    cos, sin = math.cos(yaw), math.sin(yaw)
    rotation = np.array([[cos, -sin], [sin, cos]])
    return local @ rotation.T + np.asarray(center[:2], dtype=float)


def _arm(axes: Any, data: ArmPlot) -> None:
    if data.tcp_path:
        path = np.asarray(data.tcp_path)
        axes.plot(path[:, 0], path[:, 1], path[:, 2], color="tab:blue", lw=1.5, label="tool")
        axes.scatter(*path[0], color="black", marker="o", label="start")
    for name, points in data.object_paths.items():
        if points:
            path = np.asarray(points)
            axes.plot(path[:, 0], path[:, 1], path[:, 2], color="tab:orange", lw=2.0, label=name)
    for label, position in data.targets:
        axes.scatter(*position, color="gold", edgecolor="black", marker="*", s=120)
        axes.text(*position, f" {label}", fontsize=8)
    axes.set_xlabel("x (m)")
    axes.set_ylabel("y (m)")
    axes.set_zlabel("z (m)")
    axes.set_title(data.title, fontsize=10)
    axes.legend(loc="upper right", fontsize=7)
