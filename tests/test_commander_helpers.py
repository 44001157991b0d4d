"""nav2_simple_commander's helper modules: line_iterator, costmap_2d, occupancy_grid,
footprint_collision_checker and utils, against cases worked out by hand."""

from __future__ import annotations

import math
import subprocess
import sys
from array import array
from pathlib import Path

import numpy as np
import pytest

from baobab.nav.costmap import Costmap2D
from baobab.nav.msgs import Costmap, CostmapMetaData, Header, OccupancyGrid, Point, Pose, TimeMsg
from baobab.nav.ros.geometry_msgs.msg import Point32, Polygon
from baobab.nav.ros.nav2_simple_commander.costmap_2d import PyCostmap2D
from baobab.nav.ros.nav2_simple_commander.footprint_collision_checker import (
    LETHAL_OBSTACLE,
    FootprintCollisionChecker,
)
from baobab.nav.ros.nav2_simple_commander.line_iterator import LineIterator
from baobab.nav.ros.nav2_simple_commander.occupancy_grid import PyOccupancyGrid
from baobab.nav.ros.nav2_simple_commander.utils import (
    euler_to_quaternion,
    find_os_processes,
    kill_os_processes,
    kill_process,
)
from baobab.nav.script_runner import run_nav2_script


def points(line: LineIterator) -> list[tuple[float, float]]:
    visited = []
    while line.isValid():
        visited.append((line.getX(), line.getY()))
        line.advance()
    return visited


# --- line_iterator ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("segment", "step", "expected"),
    [
        ((0, 0, 3, 0), 1.0, [(0, 0), (1, 0), (2, 0), (3, 0)]),
        ((0, 0, 2, 1), 0.5, [(0, 0), (0.5, 0.25), (1.0, 0.5), (1.5, 0.75), (2.0, 1.0)]),
        ((1, 3, 1, 1), 1.0, [(1, 3), (1, 2), (1, 1)]),
        ((0, 0, 1, 0), 0.4, [(0, 0), (0.4, 0), (0.8, 0), (1, 0)]),
        ((2, 2, 0, 0), 1.0, [(2, 2), (1, 1), (0, 0)]),
        ((0, 0, 3, 1), 1.0, [(0, 0), (1, 0.33333), (2, 0.66667), (3, 1.0)]),
    ],
)
def test_line_iterator_visits_each_step_and_the_end_point(
    segment: tuple[float, float, float, float], step: float, expected: list[tuple[float, float]]
) -> None:
    assert points(LineIterator(*segment, step)) == expected


def test_line_iterator_accessors_and_errors() -> None:
    line = LineIterator(0.0, 0.0, 3.0, 4.0)
    assert (line.getX0(), line.getY0(), line.getX1(), line.getY1()) == (0.0, 0.0, 3.0, 4.0)
    assert line.get_line_length() == 5.0
    assert (line.clamp(5, 0, 3), line.clamp(-1, 0, 3), line.clamp(2, 0, 3)) == (3, 0, 2)
    with pytest.raises(TypeError, match="x0 must be a number"):
        LineIterator("0", 0, 1, 1)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="step_size must be a number"):
        LineIterator(0, 0, 1, 1, None)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="positive"):
        LineIterator(0, 0, 1, 1, 0.0)
    with pytest.raises(ValueError, match="zero length"):
        LineIterator(1, 1, 1, 1)


# --- costmap_2d, occupancy_grid ---------------------------------------------------------------


def costmap_message(
    size_x: int, size_y: int, resolution: float, origin: tuple[float, float], data: list[int]
) -> Costmap:
    return Costmap(
        header=Header(stamp=TimeMsg(sec=7, nanosec=5), frame_id="map"),
        metadata=CostmapMetaData(
            resolution=resolution,
            size_x=size_x,
            size_y=size_y,
            origin=Pose(position=Point(x=origin[0], y=origin[1])),
        ),
        data=array("B", data),
    )


def test_pycostmap2d_sizes_conversions_and_costs() -> None:
    costmap = PyCostmap2D(costmap_message(4, 3, 0.5, (-1.0, 2.0), list(range(12))))
    assert (costmap.getSizeInCellsX(), costmap.getSizeInCellsY()) == (4, 3)
    assert (costmap.getSizeInMetersX(), costmap.getSizeInMetersY()) == (2.0, 1.5)
    assert (costmap.getOriginX(), costmap.getOriginY(), costmap.getResolution()) == (-1, 2, 0.5)
    assert costmap.getGlobalFrameID() == "map"
    assert costmap.getCostmapTimestamp() == TimeMsg(sec=7, nanosec=5)
    assert costmap.getIndex(1, 2) == 9
    cost = costmap.getCostXY(1, 2)
    assert cost == 9 and isinstance(cost, np.uint8)
    assert costmap.getCostIdx(11) == 11
    assert costmap.mapToWorld(1, 2) == (-0.25, 3.25)
    assert costmap.worldToMapValidated(-0.25, 3.25) == (1, 2)
    assert costmap.worldToMapValidated(-1.0, 2.0) == (0, 0)
    assert costmap.worldToMapValidated(0.99, 3.49) == (3, 2)
    assert costmap.worldToMapValidated(-1.01, 2.5) == (None, None)  # below the origin
    assert costmap.worldToMapValidated(1.0, 2.0) == (None, None)  # x cell 4 of 4
    assert costmap.worldToMapValidated(0.0, 3.5) == (None, None)  # y cell 3 of 3
    costmap.setCost(0, 0, 254)
    assert costmap.getCostIdx(0) == 254


def test_pycostmap2d_over_a_baobab_costmap_reads_the_same_cells() -> None:
    grid = Costmap2D(3, 2, 0.25, origin=(1.0, -1.0))
    grid.data[1, 2] = 254  # row iy = 1, column ix = 2
    costmap = PyCostmap2D(grid)
    assert costmap.getCostXY(2, 1) == 254 and costmap.getCostIdx(5) == 254
    assert costmap.worldToMapValidated(1.6, -0.8) == (2, 0)
    assert costmap.getGlobalFrameID() == "map"
    costmap.setCost(0, 0, 9)
    assert grid.data[0, 0] == 0  # a copy


def test_pyoccupancygrid_reads_int8_cells() -> None:
    grid = OccupancyGrid(data=array("b", [0, 100, -1, 50]))
    grid.header.frame_id = "map"
    grid.info.width, grid.info.height, grid.info.resolution = 2, 2, 0.1
    occupancy = PyOccupancyGrid(grid)
    assert occupancy.getCostXY(0, 1) == -1 and isinstance(occupancy.getCostXY(0, 1), np.int8)
    assert occupancy.getCostXY(1, 1) == 50
    assert occupancy.worldToMapValidated(0.15, 0.05) == (1, 0)
    assert occupancy.getSizeInMetersX() == pytest.approx(0.2)


# --- footprint_collision_checker --------------------------------------------------------------


def checker() -> FootprintCollisionChecker:
    """10 x 10 cells of 1 m from the origin: lethal (5, 5), cost 100 at (2, 3)."""
    data = [0] * 100
    data[5 * 10 + 5] = 254
    data[3 * 10 + 2] = 100
    collision_checker = FootprintCollisionChecker()
    collision_checker.setCostmap(PyCostmap2D(costmap_message(10, 10, 1.0, (0.0, 0.0), data)))
    return collision_checker


def polygon(*corners: tuple[float, float]) -> Polygon:
    return Polygon(points=[Point32(x=float(x), y=float(y)) for x, y in corners])


def test_point_and_line_costs() -> None:
    check = checker()
    assert check.pointCost(5, 5) == LETHAL_OBSTACLE and check.pointCost(2, 3) == 100
    assert check.lineCost(0, 9, 0, 0) == 0.0  # along row 0
    assert check.lineCost(2, 2, 0, 9) == 100.0  # up column 2, through (2, 3)
    assert check.lineCost(0, 9, 0, 9) == 254.0  # the diagonal meets (5, 5)
    assert check.lineCost(4, 4, 4, 4) == 0.0  # a one-cell line
    assert check.worldToMapValidated(9.5, 0.2) == (9, 0)
    assert check.worldToMapValidated(10.5, 0.2) == (None, None)


def test_footprint_costs() -> None:
    check = checker()
    square = polygon((1.5, 1.5), (3.5, 1.5), (3.5, 3.5), (1.5, 3.5))  # cells (1..3, 1..3)
    assert check.footprintCost(square) == 100.0  # the top edge crosses (2, 3)
    assert check.footprintCost(polygon((6.5, 6.5), (8.5, 6.5), (8.5, 8.5))) == 0.0
    assert check.footprintCost(polygon((4.5, 4.5), (6.5, 4.5), (6.5, 6.5))) == 254.0
    assert check.footprintCost(polygon((1.5, 1.5), (11.0, 1.5), (1.5, 3.5))) == 254.0  # off map
    # A 3 m x 0.4 m bar from the robot's origin forward, placed at (5.5, 2.2):
    bar = polygon((0.0, -0.2), (3.0, -0.2), (3.0, 0.2), (0.0, 0.2))
    assert check.footprintCostAtPose(5.5, 2.2, math.pi / 2, bar) == 254.0  # up x = 5: (5, 5)
    assert check.footprintCostAtPose(5.5, 2.2, 0.0, bar) == 0.0  # along row 2
    assert check.footprintCostAtPose(1.5, 3.5, 0.0, bar) == 100.0  # along row 3 from x = 1


def test_footprint_checker_needs_a_costmap() -> None:
    with pytest.raises(ValueError, match="setCostmap"):
        FootprintCollisionChecker().pointCost(0, 0)


# --- utils ------------------------------------------------------------------------------------


def test_euler_to_quaternion() -> None:
    q = euler_to_quaternion(yaw=math.pi / 2)
    assert (q.x, q.y) == (0.0, 0.0) and q.z == pytest.approx(math.sqrt(0.5))
    assert q.w == pytest.approx(math.sqrt(0.5))
    assert euler_to_quaternion(roll=math.pi).x == pytest.approx(1.0)
    roll, pitch, yaw = 0.1, 0.2, 0.3
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    q = euler_to_quaternion(roll, pitch, yaw)
    assert (q.x, q.y, q.z, q.w) == pytest.approx(
        (
            sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
            cr * cp * cy + sr * sp * sy,
        )
    )
    assert euler_to_quaternion() == euler_to_quaternion(0.0, 0.0, 0.0)


def test_finding_and_killing_processes(capsys: pytest.CaptureFixture[str]) -> None:
    marker = "baobab_helper_test_marker"
    child = "import sys, time; print('ready', flush=True); time.sleep(60)"
    process = subprocess.Popen(
        [sys.executable, "-c", child, marker], stdout=subprocess.PIPE, text=True
    )
    try:
        assert process.stdout is not None and process.stdout.readline() == "ready\n"
        found = find_os_processes(sys.executable)
        assert any(int(pid) == process.pid and marker in command for pid, command in found)
        kill_process(process.pid)
        assert process.wait(timeout=10) == -9
        assert f"Successfully killed process with PID: {process.pid}" in capsys.readouterr().out
    finally:
        process.kill()
        process.wait(timeout=10)
        if process.stdout is not None:
            process.stdout.close()
    kill_os_processes("no_such_program_baobab")
    assert capsys.readouterr().out == "No processes found starting with no_such_program_baobab\n"


# --- in a Nav2 script -------------------------------------------------------------------------

COSTMAP_SCRIPT = """\
import math

import rclpy
from geometry_msgs.msg import Point32, Polygon
from nav2_simple_commander.costmap_2d import PyCostmap2D
from nav2_simple_commander.footprint_collision_checker import FootprintCollisionChecker
from nav2_simple_commander.robot_navigator import BasicNavigator
from nav2_simple_commander.utils import euler_to_quaternion

rclpy.init()
navigator = BasicNavigator()
costmap = PyCostmap2D(navigator.getGlobalCostmap())
checker = FootprintCollisionChecker()
checker.setCostmap(costmap)
square = Polygon(points=[Point32(x=x, y=y) for x, y in
                         ((-0.1, -0.1), (0.1, -0.1), (0.1, 0.1), (-0.1, 0.1))])
print(costmap.getGlobalFrameID(), costmap.getResolution())
print(checker.footprintCostAtPose(0.0, 0.0, 0.0, square))
print(checker.footprintCostAtPose(-2.0, -0.6, 0.0, square))
mx, my = costmap.worldToMapValidated(-2.0, -0.6)
print(costmap.getCostXY(mx, my))
print(round(euler_to_quaternion(yaw=math.pi).z, 6))
"""


def test_helpers_in_a_nav2_script_read_the_navigators_costmap(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    script = tmp_path / "costmap_queries.py"
    script.write_text(COSTMAP_SCRIPT, encoding="utf-8")
    assert run_nav2_script(script, navigator_defaults={"world": "cafe"}) == 0
    frame, spawn, table, cell, qz = capsys.readouterr().out.splitlines()
    assert frame == "map 0.05"
    assert float(spawn) < 253  # the cafe's spawn is free
    assert float(table) == 254.0 and cell == "254"  # table 1 stands at (-2.0, -0.6)
    assert qz == "1.0"
