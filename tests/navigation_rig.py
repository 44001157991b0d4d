"""Shared set-up for the navigation tests: a TurtleBot3 wired to a NavigationServer.

The rig is what a mission runner builds: ``build_turtlebot3_sim`` for the robot, then
``build_navigation`` with the robot's base and lidar. A contact watch checks every 10 ms of
sim time whether any robot geom touches an obstacle (static or movable geom).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from baobab.nav import BasicNavigator, NavigationServer, build_navigation
from baobab.nav.robot_params import navigation_params
from baobab.robots.catalog import ROBOTS
from baobab.robots.diff_drive import MobileRobot
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.builder import MOVABLE_GROUP, STATIC_GROUP, movable_slot_name
from baobab.sim.docks import Dock
from baobab.sim.moving_objects import MovingObject, Waypoint
from baobab.sim.simulation import Simulation
from baobab.sim.tasks import TaskHandle, TaskStatus
from baobab.sim.world import Box, Floor, Pose2D, World, load_world

CONTACT_PERIOD = 0.01
"""How often (s of sim time) the contact watch looks."""


class ContactWatch:
    """Names of the obstacle geoms a robot touched, checked every 10 ms of sim time."""

    def __init__(self, sim: Simulation, robot_body: str) -> None:
        model = sim.model
        root = model.body(robot_body).id
        robot = np.flatnonzero(model.body_rootid[model.geom_bodyid] == root)
        obstacles = np.flatnonzero(
            (model.geom_group == STATIC_GROUP) | (model.geom_group == MOVABLE_GROUP)
        )
        self._robot = set(robot.tolist())
        self._obstacles = set(obstacles.tolist())
        self._sim = sim
        self.touched: set[str] = set()
        self.checks = 0
        sim.every(CONTACT_PERIOD, self._check, name="contact watch")

    def _check(self, _now: float) -> None:
        self.checks += 1
        data = self._sim.data
        for a, b in data.contact.geom[: data.ncon].tolist():
            if (a in self._robot and b in self._obstacles) or (
                b in self._robot and a in self._obstacles
            ):
                other = b if a in self._robot else a
                self.touched.add(self._sim.model.geom(other).name)


@dataclass
class NavRig:
    """A robot in a world with its navigation server and contact watch."""

    world: World
    sim: Simulation
    robot: MobileRobot
    server: NavigationServer
    contacts: ContactWatch

    def run(self, handle: TaskHandle, limit: float) -> float:
        """Step until ``handle`` ends; the sim seconds it took. Fails past ``limit`` s."""
        start = self.sim.time
        while handle.status is TaskStatus.RUNNING:
            if self.sim.time - start > limit:
                raise AssertionError(f"{handle.name} still running after {limit} s of sim time")
            self.sim.step_for(0.05)
        return self.sim.time - start

    def pose(self) -> Pose2D:
        """The robot's ground-truth pose."""
        return self.robot.base.pose()

    def place_box(self, slot: int, x: float, y: float) -> None:
        """Move movable obstacle slot ``slot`` (a 0.3 m cube) to ``(x, y)`` (m)."""
        body = self.sim.model.body(movable_slot_name(slot))
        self.sim.data.mocap_pos[body.mocapid[0]] = [x, y, 0.25]
        mujoco.mj_forward(self.sim.model, self.sim.data)

    def wheel_speeds(self) -> tuple[float, float]:
        """Left and right wheel joint speeds (rad/s)."""
        data, names = self.sim.data, self.robot.names
        left, right = (float(data.joint(name).qvel[0]) for name in names.wheel_joints)
        return left, right


def make_rig(
    world: World | str, start: Pose2D | None = None, robot_name: str | None = None
) -> NavRig:
    """Build the robot in ``world`` at ``start`` (default spawn) and wire navigation to it:
    the Burger, or the registry's ``robot_name`` with its own navigation settings."""
    if not isinstance(world, World):
        world = load_world(world)
    if robot_name is None:
        sim, robot = build_turtlebot3_sim(world, start)
        server = build_navigation(sim, robot.base, robot.lidar, world)
    else:
        info = ROBOTS[robot_name]
        sim, robot = info.build_sim(world, start)
        params = navigation_params(info)
        server = build_navigation(sim, robot.base, robot.lidar, world, params=params)
    return NavRig(world, sim, robot, server, ContactWatch(sim, robot.names.body))


def feedback_states(navigator: BasicNavigator) -> set[int]:
    """Poll ``isTaskComplete`` as a script does until the task ends; the ``state`` of every
    feedback read on the way."""
    states: set[int] = set()
    while not navigator.isTaskComplete():
        feedback = navigator.getFeedback()
        if feedback is not None:
            states.add(feedback.state)
    return states


def distance(a: Pose2D, b: Pose2D) -> float:
    """Planar distance (m) between two poses."""
    return math.hypot(a.x - b.x, a.y - b.y)


def yaw_error(a: Pose2D, b: Pose2D) -> float:
    """Absolute heading difference (rad) between two poses."""
    return abs(math.remainder(a.yaw - b.yaw, 2 * math.pi))


def sealed_room() -> World:
    """A 2 m x 2 m room without a door east of the spawn: goals inside fail, slowly."""
    walls = [
        Box(name="room_north", center=(1.5, 2.0), size=(2.1, 0.1)),
        Box(name="room_south", center=(1.5, 0.0), size=(2.1, 0.1)),
        Box(name="room_east", center=(2.5, 1.0), size=(0.1, 2.1)),
        Box(name="room_west", center=(0.5, 1.0), size=(0.1, 2.1)),
    ]
    return World(
        name="sealed",
        floor=Floor(size=(6.0, 6.0)),
        boxes=walls,
        spawns={"default": Pose2D(x=-1.5, y=-1.5)},
    )


def alcove() -> World:
    """A 0.6 m wide dead end open to the east, the robot inside it."""
    walls = [
        Box(name="alcove_north", center=(0.0, 0.35), size=(2.4, 0.1)),
        Box(name="alcove_south", center=(0.0, -0.35), size=(2.4, 0.1)),
        Box(name="alcove_end", center=(-1.15, 0.0), size=(0.1, 0.6)),
    ]
    return World(
        name="alcove",
        floor=Floor(size=(6.0, 4.0)),
        boxes=walls,
        spawns={"default": Pose2D(x=-0.6, y=0.0)},
    )


ROOM_DOCK = Dock(pose=(1.5, 0.5, 0.3))
"""The charging dock of :func:`dock_room`: docked base at (1.5, 0.5), facing 0.3 rad."""


def dock_room(start: Pose2D | None = None, *, boxes: list[Box] | None = None) -> World:
    """A 6 m x 5 m room with the charging dock ``home`` (:data:`ROOM_DOCK`) and ``boxes``; the
    robot starts at ``start``, by default on the dock's staging pose (0.7 m before it)."""
    if start is None:
        x, y = ROOM_DOCK.to_map(-0.7, 0.0)
        start = Pose2D(x=x, y=y, yaw=ROOM_DOCK.yaw)
    return World(
        name="dock_room",
        floor=Floor(size=(6.0, 5.0)),
        boxes=boxes or [],
        spawns={"default": start},
        docks={"home": ROOM_DOCK},
    )


WALKER = MovingObject(
    name="person",
    start_time=1.0,
    speed=0.15,
    waypoints=[Waypoint(x=-1.5, y=0.0), Waypoint(x=2.0, y=0.0, wait=1.0)],
)
"""A person who walks 3.5 m east along y = 0 at 0.15 m/s from 1 s on, then stands."""


def walker_room() -> World:
    """An 8 m x 6 m room with :data:`WALKER`; the robot starts 1 m behind the person."""
    return World(
        name="walker_room",
        floor=Floor(size=(8.0, 6.0)),
        spawns={"default": Pose2D(x=-2.5, y=0.0)},
        moving_objects=[WALKER],
    )
