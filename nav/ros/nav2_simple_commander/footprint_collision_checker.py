"""``nav2_simple_commander.footprint_collision_checker``: the cost of a footprint on a costmap.

A footprint is a ``geometry_msgs/Polygon`` (anything whose ``points`` have ``x`` and ``y``,
in metres). Its cost is the highest cost of the cells its edges cross, the edges walked in map
cells by :class:`~.line_iterator.LineIterator` (half-cell steps); the walk stops at the first
lethal cell (254) and a vertex off the map counts as lethal. Two differences from Nav2, where
its code would raise or read the wrong cell: an edge whose two ends fall in the same cell costs
that cell, and a one-point footprint costs its own cell.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Protocol

from baobab.nav.ros.nav2_simple_commander.costmap_2d import PyCostmap2D
from baobab.nav.ros.nav2_simple_commander.line_iterator import LineIterator

__all__ = [
    "FREE_SPACE",
    "INSCRIBED_INFLATED_OBSTACLE",
    "LETHAL_OBSTACLE",
    "MAX_NON_OBSTACLE",
    "NO_INFORMATION",
    "FootprintCollisionChecker",
]

NO_INFORMATION = 255
LETHAL_OBSTACLE = 254
INSCRIBED_INFLATED_OBSTACLE = 253
MAX_NON_OBSTACLE = 252
FREE_SPACE = 0


class _Polygon(Protocol):
    @property
    def points(self) -> Sequence[Any]: ...


class FootprintCollisionChecker:
    """Costs of points, lines and footprints on the costmap given by :meth:`setCostmap`."""

    def __init__(self) -> None:
        self.costmap_: PyCostmap2D | None = None

    def _costmap(self) -> PyCostmap2D:
        if self.costmap_ is None:
            raise ValueError("Costmap not specified, use setCostmap to specify the costmap first")
        return self.costmap_

    def setCostmap(self, costmap: PyCostmap2D) -> None:
        """Use ``costmap`` from now on."""
        self.costmap_ = costmap

    def worldToMapValidated(self, wx: float, wy: float) -> tuple[int, int] | tuple[None, None]:
        """The costmap's cell of map point ``(wx, wy)`` (m), ``(None, None)`` off the map.

        Raises:
            ValueError: no costmap was set.
        """
        return self._costmap().worldToMapValidated(wx, wy)

    def pointCost(self, x: int, y: int) -> int:
        """Cost of map cell ``(x, y)``.

        Raises:
            ValueError: no costmap was set.
        """
        return int(self._costmap().getCostXY(x, y))

    def lineCost(self, x0: int, x1: int, y0: int, y1: int, step_size: float = 0.5) -> float:
        """Highest cost along the line from map cell ``(x0, y0)`` to ``(x1, y1)``.

        Returns 254 as soon as a lethal cell is met.
        """
        if x0 == x1 and y0 == y1:
            return float(self.pointCost(int(x0), int(y0)))
        line_cost = 0.0
        line = LineIterator(x0, y0, x1, y1, step_size)
        while line.isValid():
            point_cost = self.pointCost(int(line.getX()), int(line.getY()))
            if point_cost == LETHAL_OBSTACLE:
                return float(point_cost)
            line_cost = max(line_cost, float(point_cost))
            line.advance()
        return line_cost

    def footprintCost(self, footprint: _Polygon) -> float:
        """Highest cost along the closed outline of ``footprint`` (map-frame points, m).

        Returns 254 when a vertex is off the map or an edge meets a lethal cell.
        """
        cells: list[tuple[int, int]] = []
        for point in footprint.points:
            mx, my = self.worldToMapValidated(point.x, point.y)
            if mx is None or my is None:
                return float(LETHAL_OBSTACLE)
            cells.append((mx, my))
        if not cells:
            return 0.0
        cost = 0.0
        for (x0, y0), (x1, y1) in zip(cells, [*cells[1:], cells[0]], strict=True):
            cost = max(cost, self.lineCost(x0, x1, y0, y1))
            if cost == LETHAL_OBSTACLE:
                break
        return cost

    def footprintCostAtPose(self, x: float, y: float, theta: float, footprint: _Polygon) -> float:
        """:meth:`footprintCost` of ``footprint`` (robot frame) placed at ``(x, y, theta)``.

        Args:
            x: map-frame x (m) of the robot.
            y: map-frame y (m) of the robot.
            theta: heading (rad).
            footprint: the outline in the robot frame (m).
        """
        cos_th, sin_th = math.cos(theta), math.sin(theta)
        placed = [
            _Point(x + p.x * cos_th - p.y * sin_th, y + p.x * sin_th + p.y * cos_th)
            for p in footprint.points
        ]
        return self.footprintCost(_Outline(placed))


class _Point:
    __slots__ = ("x", "y")

    def __init__(self, x: float, y: float) -> None:
        self.x, self.y = x, y


class _Outline:
    __slots__ = ("points",)

    def __init__(self, points: list[_Point]) -> None:
        self.points = points
