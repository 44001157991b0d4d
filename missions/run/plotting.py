"""The run's ``plot.png``: the world from above with the driven path, or the arm's tool path.

A mobile run shows the floor (a map_server map's image on it), static and spawned obstacles,
the inflated global costmap when navigation ran, the costmap filter zones (keepout, speed
limits), planned paths, the driven trajectory coloured by sim time, where the clearance
was smallest, Bug2's hit and leave points, goals and named locations. An arm run shows the
tool path coloured by sim time with the impedance set-point it followed and the objects' paths
in 3D, next to the tracking error (tool to set-point) over time. matplotlib (Agg) is imported
only when a plot is drawn, so runs that write no folder never pay for it. What a plot shows is
gathered during the run into :mod:`baobab.missions.run.plot_data`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from baobab.missions.run.plot_data import (
    ArmPlot,
    CostmapImage,
    MobilePlot,
    PlotData,
    ZoneImage,
)
from baobab.sim.world import World

if TYPE_CHECKING:
    from matplotlib.axes import Axes

MANY_GOALS = 12
"""With more goals than this, goal markers and labels are drawn smaller."""
MAX_TRAJECTORY_POINTS = 600
"""The driven path is thinned to about this many points for drawing."""
FLOOR_TINT = 0.35
"""How much of the world's floor colour the map background keeps (the rest is white)."""
DPI = 110
MAP_MARGINS = {"left": 0.8, "right": 0.1, "bottom": 0.95, "top": 0.35}
"""Around the map view (inches): the axis labels, the legend below, the title above."""
PNG_COMPRESSION = 3
"""zlib level of plot.png: level 3 writes in a third of the default's time, ~10 % larger."""
COSTMAP_CMAP = "Purples"
COSTMAP_ALPHA = 0.45
OBSTACLE_EDGE = (0.2, 0.2, 0.2)
MAP_UNKNOWN_SHADE = 0.8
"""Grey of a map's unknown cells (0 black, 1 white), as map_server saves them (205 of 255)."""
KEEPOUT_COLOUR = "crimson"
ZONE_ALPHA = 0.35


def load_plotting() -> None:
    """Import matplotlib (Agg) and the parts the plot draws with: about half a second.

    ``baobab run`` calls it in the process that writes the run folder while the run's own
    process simulates, so that the import is off the path from the run's end to its result.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.collections
    import matplotlib.figure
    import matplotlib.patches
    import matplotlib.patheffects


def save_plot(data: PlotData, path: Path) -> None:
    """Draw ``data`` and write it as a PNG to ``path``.

    The figure is laid out by hand (fixed margins in inches): matplotlib's constrained layout
    draws the figure twice and cost as much as the drawing itself.
    """
    load_plotting()
    from matplotlib.figure import Figure

    if isinstance(data, MobilePlot):
        figure = Figure(figsize=_map_size(data.world), dpi=DPI)
        _margins(figure, **MAP_MARGINS)
        _mobile(figure.add_subplot(), data)
    elif data.tracking_errors:
        figure = Figure(figsize=(12.5, 5.5), dpi=DPI)
        _margins(figure, left=0.3, right=0.3, bottom=0.6, top=0.6, wspace=0.35)
        figure.suptitle(data.title, fontsize=10)
        _arm(figure.add_subplot(1, 2, 1, projection="3d"), data)
        _tracking_error(figure.add_subplot(1, 2, 2), data)
    else:
        figure = Figure(figsize=(8.0, 8.0), dpi=DPI)
        _margins(figure, left=0.3, right=0.3, bottom=0.3, top=0.6)
        _arm(figure.add_subplot(projection="3d"), data)
        figure.suptitle(data.title, fontsize=10)
    figure.savefig(path, pil_kwargs={"compress_level": PNG_COMPRESSION})


def _map_size(world: World) -> tuple[float, float]:
    """The figure size (inches) at which the map fills its axes: 8 wide, 5 to 12 high."""
    x_min, y_min, x_max, y_max = world.bounds
    aspect = (y_max - y_min + 0.4) / max(x_max - x_min + 0.4, 1e-9)
    # The colour bar takes its fraction and pad of the width left between the margins.
    axes_width = (8.0 - MAP_MARGINS["left"] - MAP_MARGINS["right"]) * (1 - 0.15 - 0.05)
    height = axes_width * aspect + MAP_MARGINS["bottom"] + MAP_MARGINS["top"]
    return 8.0, min(12.0, max(5.0, height))


def _margins(
    figure: Any, *, left: float, right: float, bottom: float, top: float, **more: Any
) -> None:
    """Leave these margins (inches) around the subplots."""
    width, height = figure.get_size_inches()
    figure.subplots_adjust(
        left=left / width,
        right=1 - right / width,
        bottom=bottom / height,
        top=1 - top / height,
        **more,
    )


def _mobile(axes: Axes, data: MobilePlot) -> None:
    """The map view, layer by layer from the floor up."""
    from matplotlib import patheffects

    halo = [patheffects.withStroke(linewidth=2.5, foreground="white")]
    x_min, y_min, x_max, y_max = data.world.bounds
    _floor(axes, data.world)
    _map_image(axes, data.world)
    if data.costmap is not None:
        _costmap(axes, data.costmap, (x_min, y_min))
    _zones(axes, data.zones)
    _obstacles(axes, data, halo)
    _planned_paths(axes, data.planned_paths)
    if len(data.xs) > 1:
        _trajectory(axes, data)
    _footprints(axes, data.footprints)
    _markers(axes, data)
    _locations(axes, data, halo)
    _goals(axes, data, halo)
    axes.set_xlim(x_min - 0.2, x_max + 0.2)
    axes.set_ylim(y_min - 0.2, y_max + 0.2)
    axes.set_aspect("equal")
    axes.set_xlabel("x (m)")
    axes.set_ylabel("y (m)")
    axes.set_title(data.title, fontsize=10)
    axes.figure.legend(loc="lower center", ncol=7, fontsize=7)


def _floor(axes: Axes, world: World) -> None:
    from matplotlib.patches import Rectangle

    x_min, y_min, x_max, y_max = world.bounds
    # A pale floor lets the costmap, the paths and light-coloured obstacles stand out.
    floor_colour = FLOOR_TINT * np.asarray(world.floor.colour[:3]) + (1 - FLOOR_TINT)
    axes.add_patch(
        Rectangle((x_min, y_min), x_max - x_min, y_max - y_min, color=floor_colour, zorder=0)
    )


def _map_image(axes: Axes, world: World) -> None:
    """The map_server map under everything, grey as its image: free white, occupied black,
    unknown grey."""
    grid = world.grid
    if grid is None:
        return
    values = grid.data.astype(np.float32)
    shade = np.where(values < 0, MAP_UNKNOWN_SHADE, 1.0 - values / 100.0)
    x0, y0, x1, y1 = grid.bounds
    axes.imshow(
        shade,
        origin="lower",
        extent=(x0, x1, y0, y1),
        cmap="gray",
        vmin=0.0,
        vmax=1.0,
        zorder=0.5,
        interpolation="nearest",
        interpolation_stage="data",
    )


def _zones(axes: Axes, zones: Sequence[ZoneImage]) -> None:
    """Costmap filter zones: keepout zones hatched red, speed limits orange (darker: slower)."""
    import matplotlib
    from matplotlib.patches import Rectangle

    limits = sum(not zone.keepout for zone in zones)
    slower = 0  # the speed zones come slowest first
    for zone in zones:
        if zone.keepout:
            colour: Any = KEEPOUT_COLOUR
        else:
            colour = matplotlib.colormaps["Oranges"](0.65 - 0.4 * slower / max(limits - 1, 1))
            slower += 1
        table = np.zeros((2, 4))
        table[1] = matplotlib.colors.to_rgba(colour, ZONE_ALPHA)
        x0, y0 = zone.origin
        _indexed_cells(axes, zone.cells.astype(np.uint8), zone.origin, zone.resolution, table, 1.5)
        rows, cols = np.nonzero(zone.cells)
        if len(rows):
            corner = (x0 + cols.min() * zone.resolution, y0 + rows.min() * zone.resolution)
            legend_only = Rectangle(corner, 0, 0, color=colour, alpha=ZONE_ALPHA)
            if zone.keepout:
                legend_only.set_hatch("//")
            legend_only.set_label(zone.label)
            axes.add_patch(legend_only)


def _indexed_cells(
    axes: Axes,
    cells: np.ndarray,
    origin: tuple[float, float],
    resolution: float,
    colours: np.ndarray,
    zorder: float,
) -> None:
    """A grid of cells (``resolution`` m, lower-left corner at ``origin``) whose values index
    the RGBA table ``colours``. Resampled as data, such an image costs ~15 MB at the figure's
    pixel size, where a masked array resampled as RGBA colours (matplotlib's choice below 3
    pixels a cell) cost ~70 MB."""
    from matplotlib.colors import ListedColormap, NoNorm

    height, width = cells.shape
    x0, y0 = origin
    axes.imshow(
        cells,
        origin="lower",
        extent=(x0, x0 + width * resolution, y0, y0 + height * resolution),
        cmap=ListedColormap(colours),
        norm=NoNorm(),
        zorder=zorder,
        interpolation="nearest",
        interpolation_stage="data",
    )


def _costmap(axes: Axes, image: CostmapImage, corner: tuple[float, float]) -> None:
    import matplotlib
    from matplotlib.patches import Rectangle

    # The costs index a colour table whose alpha makes free cells transparent.
    colours = matplotlib.colormaps[COSTMAP_CMAP](np.arange(256))
    colours[:, 3] = np.where(np.arange(256) > 0, COSTMAP_ALPHA, 0.0)
    _indexed_cells(axes, image.data, image.origin, image.resolution, colours, 1)
    colour = matplotlib.colormaps[COSTMAP_CMAP](0.8)
    legend_only = Rectangle(corner, 0, 0, color=colour, alpha=COSTMAP_ALPHA)
    legend_only.set_label("inflated costmap")
    axes.add_patch(legend_only)


def _obstacles(axes: Axes, data: MobilePlot, halo: list[Any]) -> None:
    """The world's boxes and cylinders, and the obstacles events placed (hatched, named)."""
    from matplotlib.patches import Circle, Polygon

    edge: dict[str, Any] = {"ec": OBSTACLE_EDGE, "lw": 0.6, "zorder": 2}
    for box in [*data.world.boxes, *data.world.dock_boxes]:
        corners = _box_corners(box.center, box.size, box.yaw)
        axes.add_patch(Polygon(corners, fc=box.colour[:3], **edge))
    for cylinder in data.world.cylinders:
        axes.add_patch(Circle(cylinder.center, cylinder.radius, fc=cylinder.colour[:3], **edge))
    for obstacle in data.obstacles:
        corners = _box_corners((obstacle.x, obstacle.y), obstacle.size[:2], obstacle.yaw)
        axes.add_patch(Polygon(corners, color=(0.85, 0.35, 0.2), hatch="//", zorder=2))
        axes.annotate(
            obstacle.name,
            (obstacle.x, obstacle.y),
            ha="center",
            fontsize=7,
            zorder=6,
            path_effects=halo,
        )


def _planned_paths(axes: Axes, paths: Sequence[np.ndarray]) -> None:
    """Every distinct plan, the first one strongest (the others as one collection)."""
    from matplotlib.collections import LineCollection

    drawn = [path for path in paths if len(path)]
    if not drawn:
        return
    first = drawn[0]
    style: dict[str, Any] = {"color": "tab:blue", "lw": 1.0, "zorder": 3}
    axes.plot(first[:, 0], first[:, 1], "--", alpha=0.8, label="planned paths", **style)
    if len(drawn) > 1:
        axes.add_collection(
            LineCollection(
                [path[:, :2] for path in drawn[1:]],
                colors=style["color"],
                linewidths=style["lw"],
                linestyles="--",
                alpha=0.25,
                zorder=style["zorder"],
            ),
            autolim=False,
        )


def _trajectory(axes: Axes, data: MobilePlot) -> None:
    """The driven path coloured by sim time (thinned), with its start and end."""
    from matplotlib.collections import LineCollection

    count = len(data.xs)
    kept = np.unique(np.r_[0 : count : max(1, count // MAX_TRAJECTORY_POINTS), count - 1])
    xs, ys = np.asarray(data.xs)[kept], np.asarray(data.ys)[kept]
    times = np.asarray(data.times, dtype=float)[kept]
    points = np.column_stack((xs, ys)).reshape(-1, 1, 2)
    segments = np.concatenate((points[:-1], points[1:]), axis=1)
    line = LineCollection(list(segments), cmap="viridis", linewidths=2.6, zorder=4)
    line.set_array(times[1:])
    axes.add_collection(line)
    figure: Any = axes.figure
    colourbar = figure.colorbar(line, ax=axes, shrink=0.7)
    colourbar.set_label("sim time (s)")
    start, end = (data.xs[0], data.ys[0]), (data.xs[-1], data.ys[-1])
    # A ring, above the goal markers: missions often start where they end.
    ring: dict[str, Any] = {"mfc": "none", "mec": "black", "mew": 1.8, "ms": 12}
    axes.plot(*start, "o", **ring, zorder=5.5, label="start")
    axes.plot(*end, "s", color="black", ms=5, zorder=5.5, label="end")


def _footprints(axes: Axes, outlines: list[list[tuple[float, float]]]) -> None:
    """The robot's footprint, as the navigation stack sees it, where it started and ended."""
    from matplotlib.patches import Polygon

    for index, outline in enumerate(outlines):
        axes.add_patch(
            Polygon(
                outline,
                closed=True,
                fill=False,
                edgecolor="black",
                linestyle="--",
                linewidth=1.0,
                zorder=5.2,
                label="footprint" if index == 0 else None,
            )
        )


def _markers(axes: Axes, data: MobilePlot) -> None:
    """Bug2's hit and leave points, and where the clearance was smallest."""
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


def _locations(axes: Axes, data: MobilePlot, halo: list[Any]) -> None:
    """Named locations that are not goals: a dot and the name."""
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
            path_effects=halo,
        )


def _goals(axes: Axes, data: MobilePlot, halo: list[Any]) -> None:
    """The tree's goals as stars, numbered in tree order."""
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
            path_effects=halo,
        )


def _box_corners(center: Sequence[float], size: Sequence[float], yaw: float) -> np.ndarray:
    half_x, half_y = size[0] / 2, size[1] / 2
    local = np.array([[-half_x, -half_y], [half_x, -half_y], [half_x, half_y], [-half_x, half_y]])
    cos, sin = math.cos(yaw), math.sin(yaw)
    rotation = np.array([[cos, -sin], [sin, cos]])
    return local @ rotation.T + np.asarray(center[:2], dtype=float)


def _arm(axes: Any, data: ArmPlot) -> None:
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    # A carried object moves with the tool: draw it as a wide halo under the tool's path.
    axes.computed_zorder = False
    for name, points in data.object_paths.items():
        if points:
            path = np.asarray(points)
            axes.plot(*path.T, color="tab:orange", lw=6, alpha=0.45, label=name, zorder=1)
    if len(data.tracking_tcp) > 1:
        tcp = np.asarray(data.tracking_tcp)
        segments = np.stack((tcp[:-1], tcp[1:]), axis=1)
        line = Line3DCollection(
            list(segments), cmap="viridis", linewidths=2.0, label="tool", zorder=2
        )
        line.set_array(np.asarray(data.tracking_times, dtype=float)[1:])
        axes.add_collection(line)
        figure: Any = axes.figure
        figure.colorbar(line, ax=axes, shrink=0.6, pad=0.1).set_label("sim time (s)")
        axes.scatter(*tcp[0], color="black", marker="o", label="start", zorder=4)
    elif data.tcp_path:
        path = np.asarray(data.tcp_path)
        axes.plot(*path.T, color="tab:blue", lw=1.5, label="tool", zorder=2)
        axes.scatter(*path[0], color="black", marker="o", label="start", zorder=4)
    if data.setpoint_path:
        setpoint = np.asarray(data.setpoint_path)
        axes.plot(*setpoint.T, "--", color="black", lw=0.8, label="set-point", zorder=1.5)
    labelled: list[tuple[float, float, float]] = []
    for label, position in data.targets:
        axes.scatter(*position, color="gold", edgecolor="black", marker="*", s=120, zorder=4)
        if all(math.dist(position, other) > 0.03 for other in labelled):
            axes.text(*position, f"  {label}", fontsize=8, zorder=5)
            labelled.append(position)
    _fit_3d(axes, data)
    axes.set_xlabel("x (m)")
    axes.set_ylabel("y (m)")
    axes.set_zlabel("z (m)")
    axes.set_title("tool path", fontsize=9)
    axes.legend(loc="upper left", fontsize=7)


def _fit_3d(axes: Any, data: ArmPlot) -> None:
    """Equal scales on the three axes, around everything drawn."""
    groups = [data.tcp_path, data.tracking_tcp, data.setpoint_path, *data.object_paths.values()]
    points = [np.asarray(group, dtype=float).reshape(-1, 3) for group in groups if len(group)]
    points += [np.asarray([position for _, position in data.targets], dtype=float).reshape(-1, 3)]
    every = np.concatenate(points)
    if not len(every):
        return
    low, high = every.min(axis=0), every.max(axis=0)
    centre, half = (low + high) / 2, max(float((high - low).max()) / 2, 0.05) * 1.1
    axes.set_xlim(centre[0] - half, centre[0] + half)
    axes.set_ylim(centre[1] - half, centre[1] + half)
    axes.set_zlim(centre[2] - half, centre[2] + half)
    axes.set_box_aspect((1.0, 1.0, 1.0))


def _tracking_error(axes: Axes, data: ArmPlot) -> None:
    times = np.asarray(data.tracking_times, dtype=float)
    errors = np.asarray(data.tracking_errors, dtype=float) * 1000.0
    axes.plot(times, errors, color="tab:blue", lw=1.2)
    axes.fill_between(times, errors, color="tab:blue", alpha=0.15)
    worst = int(np.argmax(errors))
    axes.plot(times[worst], errors[worst], "v", color="crimson", ms=7)
    axes.annotate(
        f"max {errors[worst]:.1f} mm at {times[worst]:.2f} s",
        (times[worst], errors[worst]),
        xytext=(6, 4),
        textcoords="offset points",
        fontsize=8,
        color="crimson",
    )
    axes.set_xlim(times[0], times[-1] if times[-1] > times[0] else times[0] + 1.0)
    axes.set_ylim(0.0, max(1.0, float(errors.max()) * 1.2))
    axes.set_xlabel("sim time (s)")
    axes.set_ylabel("tool to set-point (mm)")
    axes.set_title("tracking error of the Cartesian impedance controller", fontsize=9)
    axes.grid(alpha=0.3)
