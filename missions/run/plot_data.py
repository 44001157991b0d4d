"""What a run's plot shows, gathered by its rig: the map view's layers, or the arm's tool path.

Plain data (no matplotlib): :func:`~baobab.missions.run.plotting.save_plot` draws it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from baobab.sim.world import World

Point = tuple[float, float]
"""A map-frame position (m)."""


@dataclass(frozen=True)
class PlacedObstacle:
    """A run-time obstacle where it stands now: centre (m), yaw (rad), full size (m), slot."""

    name: str
    slot: str
    x: float
    y: float
    yaw: float
    size: tuple[float, float, float]


@dataclass(frozen=True)
class CostmapImage:
    """A costmap raster: ``data[iy, ix]`` (0-255 Nav2 costs), lower-left origin (m), cell (m)."""

    data: np.ndarray
    origin: Point
    resolution: float


@dataclass(frozen=True)
class ZoneImage:
    """A costmap filter zone: ``cells[iy, ix]`` (bool), lower-left origin (m), cell side (m).

    ``label`` names it in the legend (``keepout zone``, ``speed limit 0.11 m/s``).
    """

    label: str
    cells: np.ndarray
    origin: Point
    resolution: float
    keepout: bool


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
    footprints: list[list[Point]] = field(default_factory=list)
    """The robot's footprint (its outline, map frame) at the start and at the end."""
    zones: list[ZoneImage] = field(default_factory=list)


@dataclass
class ArmPlot:
    """What an arm run's plot shows (world frame, m).

    Attributes:
        title: the figure title.
        tcp_path: the tool centre point, densely sampled.
        object_paths: each free object's path.
        targets: labelled target positions.
        tracking_times: sim times (s) of the tracking samples.
        tracking_tcp: the tool at those times.
        setpoint_path: the impedance controller's set-point at those times.
        tracking_errors: tool to set-point distance (m) at those times.
    """

    title: str
    tcp_path: Sequence[tuple[float, float, float]]
    object_paths: dict[str, Sequence[tuple[float, float, float]]] = field(default_factory=dict)
    targets: list[tuple[str, tuple[float, float, float]]] = field(default_factory=list)
    tracking_times: Sequence[float] = field(default_factory=list)
    tracking_tcp: Sequence[tuple[float, float, float]] = field(default_factory=list)
    setpoint_path: Sequence[tuple[float, float, float]] = field(default_factory=list)
    tracking_errors: Sequence[float] = field(default_factory=list)


PlotData = MobilePlot | ArmPlot
