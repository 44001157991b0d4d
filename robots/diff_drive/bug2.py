"""Bug 2 navigation (seed §7): go to the goal along the M-line, follow walls on the left.

State machine (seed Fig. 10):

- IDLE -> GO_TO_GOAL on :meth:`Bug2Controller.set_goal`; the M-line runs from the robot's
  position then to the goal.
- GO_TO_GOAL -> WALL_FOLLOW when an obstacle ahead is closer than ``wall_dist``: the robot's
  position is stored as the hit point H.
- WALL_FOLLOW -> GO_TO_GOAL at a leave point L: within ``mline_tol`` of the M-line and
  closer to the goal than H, d(L, G) < d(H, G). The robot must also have left the
  ``mline_tol`` band around the M-line since H: right after the hit it is still on the
  M-line, and the first metre along the wall can bring it a little closer to the goal,
  which would otherwise count as a leave point and hand it straight back to the same wall.
- any -> IDLE within ``goal_tolerance`` of the goal.

Wall following keeps the wall on the left with the seed's three rules (:func:`follow_left_wall`).
Distances come from the latest lidar scan through :func:`min_range_in_sector`.

Sector choice. The seed gives the rules but not the sector widths. The front sector is
+-30 deg: on a straight wall the robot then settles about ``wall_dist * sin(30 deg)`` from it,
clear of its 0.105 m footprint. The left sector looks ahead-left, 40-80 deg, not straight left:
with a sector that reaches 90 deg or beyond, each "forward" step around a convex corner
ends only once the corner is level with or behind the robot, so with a 5 Hz scan the robot
spirals outward, passes ``1.25 wall_dist`` and then turns in place forever (measured in the
walls world). Looking ahead-left ends each step while the corner is still ahead, which keeps
the turn tight.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from baobab.robots.diff_drive.base import DiffDriveBase
from baobab.robots.diff_drive.go_to_goal import (
    GoToGoalController,
    GoToGoalParams,
    NavState,
    Point,
    go_to_goal_command,
    goal_distance,
)
from baobab.sim.lidar import LaserScan, Lidar
from baobab.sim.simulation import Simulation


@dataclass(frozen=True)
class Bug2Params(GoToGoalParams):
    """Go-to-goal gains plus the wall-following figures (seed §7 defaults where it has them).

    Raises:
        ValueError: if a distance, tolerance or sector width is not positive.
    """

    wall_dist: float = 0.4
    """Obstacle distance ahead that stops go-to-goal, and wall-following's target (m)."""
    mline_tol: float = 0.1
    """How close to the M-line a leave point must be (m)."""
    front_half_width_deg: float = 30.0
    """Half-width of the front sector, centred on 0 deg (deg)."""
    left_center_deg: float = 60.0
    """Centre of the left sector, counter-clockwise from ahead (deg); see the module notes."""
    left_half_width_deg: float = 20.0
    """Half-width of the left sector (deg)."""

    def __post_init__(self) -> None:
        super().__post_init__()
        for name in (
            "wall_dist",
            "mline_tol",
            "front_half_width_deg",
            "left_half_width_deg",
        ):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive number, got {value}")
        if not math.isfinite(self.left_center_deg):
            raise ValueError(f"left_center_deg must be finite, got {self.left_center_deg}")


def min_range_in_sector(scan: LaserScan, center_deg: float, half_width_deg: float) -> float:
    """Smallest range (m) of ``scan`` within ``center_deg +- half_width_deg`` (deg).

    Angles are in the sensor frame, counter-clockwise from ahead. As the seed's tip says, the
    limits are normalised to a full turn with ``%``, turned into indices with
    ``round(angle / angle_increment)``, and when the sector straddles 0 deg (``i_start >
    i_end``) the two pieces ``[0, i_end]`` and ``[i_start, last]`` are searched. ``inf`` if
    no beam in the sector has a return.
    """
    ranges = scan.ranges
    count = len(ranges)
    if half_width_deg >= 180.0:
        return float(ranges.min())
    full_turn = 2 * math.pi
    start = (math.radians(center_deg - half_width_deg) - scan.angle_min) % full_turn
    end = (math.radians(center_deg + half_width_deg) - scan.angle_min) % full_turn
    # An angle just below a full turn rounds to index ``count``, which is beam 0 again.
    i_start = round(start / scan.angle_increment) % count
    i_end = round(end / scan.angle_increment) % count
    if i_start <= i_end:
        return float(ranges[i_start : i_end + 1].min())
    return float(min(ranges[: i_end + 1].min(), ranges[i_start:].min()))


def dist_to_mline(start: Point, goal: Point, point: Point) -> float:
    """Distance (m) from ``point`` to the infinite line through ``start`` and ``goal``.

    The line is ``a x + b y + c = 0`` with ``(a, b) = (gy - sy, sx - gx)``; the distance is
    ``|a x + b y + c| / hypot(a, b)``. If start and goal coincide, the distance to that point.
    """
    (sx, sy), (gx, gy), (x, y) = start, goal, point
    a, b = gy - sy, sx - gx
    norm = math.hypot(a, b)
    if norm == 0.0:
        return math.hypot(x - sx, y - sy)
    c = -(a * sx + b * sy)
    return abs(a * x + b * y + c) / norm


def follow_left_wall(
    front_dist: float, left_dist: float, params: Bug2Params = Bug2Params()
) -> tuple[float, float]:
    """The seed's wall-following rules: ``(v, w)`` (m/s, rad/s) keeping the wall on the left.

    An obstacle ahead closer than ``wall_dist`` -> turn right in place; the wall farther than
    ``1.25 wall_dist`` on the left -> turn left in place; otherwise go straight ahead.
    """
    if front_dist < params.wall_dist:
        return 0.0, -params.angular_speed
    if left_dist > 1.25 * params.wall_dist:
        return 0.0, params.angular_speed
    return params.linear_speed, 0.0


class Bug2Controller(GoToGoalController):
    """Bug 2 on a base with a lidar, as a periodic sim callback (see the module docstring).

    Every hit point and leave point is recorded in :attr:`hit_points` and :attr:`leave_points`
    (map frame, m), so that a run can be checked afterwards.

    Args:
        sim: the simulation; the controller registers a periodic callback.
        base: the base to command; its ground-truth pose is the robot pose.
        lidar: the scanner whose latest scan gives the front and left distances.
        params: gains, limits, wall-following figures and the control period.
    """

    callback_name = "bug2"

    def __init__(
        self,
        sim: Simulation,
        base: DiffDriveBase,
        lidar: Lidar,
        params: Bug2Params = Bug2Params(),
    ) -> None:
        self.params: Bug2Params = params
        self.lidar = lidar
        self.start: Point | None = None
        self.hit_point: Point | None = None
        self.hit_goal_dist: float | None = None
        self.left_mline = False
        """True once the robot has been farther than ``mline_tol`` from the M-line since H."""
        self.hit_points: list[Point] = []
        self.leave_points: list[Point] = []
        self._sectors_scan: LaserScan | None = None
        self._sector_distances = (math.inf, math.inf)
        super().__init__(sim, base, params)

    def set_goal(self, x: float, y: float) -> None:
        """Head for ``(x, y)`` (m, map frame); the M-line starts where the robot is now."""
        pose = self.base.pose()
        self.goal = (x, y)
        self.start = (pose.x, pose.y)
        self.hit_point = None
        self.hit_goal_dist = None
        self.left_mline = False
        self.hit_points.clear()
        self.leave_points.clear()
        self.reached = False
        self.state = NavState.GO_TO_GOAL

    def front_dist(self) -> float:
        """Nearest return (m) in the front sector of the latest scan; inf before the first."""
        return self._sectors()[0]

    def left_dist(self) -> float:
        """Nearest return (m) in the left sector of the latest scan; inf before the first."""
        return self._sectors()[1]

    def _sectors(self) -> tuple[float, float]:
        """Front and left distances (m) of the latest scan, worked out once per scan."""
        scan = self.lidar.latest
        if scan is None:
            return math.inf, math.inf
        if scan is not self._sectors_scan:  # control runs 4 times per scan
            params = self.params
            self._sectors_scan = scan
            self._sector_distances = (
                min_range_in_sector(scan, 0.0, params.front_half_width_deg),
                min_range_in_sector(scan, params.left_center_deg, params.left_half_width_deg),
            )
        return self._sector_distances

    def step(self, _time: float) -> None:
        """One control step (the periodic callback)."""
        if self.state is NavState.IDLE or self.goal is None or self.start is None:
            return
        params = self.params
        pose = self.base.pose()
        position = (pose.x, pose.y)
        to_goal = goal_distance(pose, self.goal)
        if to_goal < params.goal_tolerance:
            self.base.stop()
            self.state = NavState.IDLE
            self.reached = True
            return
        if self.state is NavState.GO_TO_GOAL and self.front_dist() < params.wall_dist:
            self.hit_point, self.hit_goal_dist = position, to_goal
            self.hit_points.append(position)
            self.left_mline = False
            self.state = NavState.WALL_FOLLOW
        elif self.state is NavState.WALL_FOLLOW and self._at_leave_point(
            self.start, self.goal, position, to_goal
        ):
            self.leave_points.append(position)
            self.state = NavState.GO_TO_GOAL
        if self.state is NavState.GO_TO_GOAL:
            self.base.command(*go_to_goal_command(pose, self.goal, params))
        else:
            self.base.command(*follow_left_wall(self.front_dist(), self.left_dist(), params))

    def _at_leave_point(self, start: Point, goal: Point, position: Point, to_goal: float) -> bool:
        on_mline = dist_to_mline(start, goal, position) < self.params.mline_tol
        if not on_mline:
            self.left_mline = True
            return False
        return self.left_mline and self.hit_goal_dist is not None and to_goal < self.hit_goal_dist
