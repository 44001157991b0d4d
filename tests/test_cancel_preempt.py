"""Cancel and preempt at any moment, in every task type (issue 12).

One property test per task type: start the task, let a stretch of sim time pass, drawn by
hypothesis in physics steps from 0 to past the task's natural end (so every phase against the
10 ms base and 50 ms navigation periods comes up), then cancel the task, send a new goal of
the same type, or (navigation and base controllers) send a goal of another type. Task types:
the BasicNavigator facade's goToPose (also one sealed off by walls, so that the moments fall
in its recoveries), goThroughPoses, followWaypoints, followPath, spin, backup, driveOnHeading,
assistedTeleop, dockRobotByID (from the staging pose), undockRobot (from the dock) and
followObjectByFrame (a walking person); the navigation server's wait; the base controllers'
go_to_goal and bug2;
the arm server's move_to and gripper. (The pick of robots/panda/pick.py is a blocking
sequence of these move_to and gripper tasks, with no handle of its own to cancel.)

"Consistent", precisely:

- cancel: a task still running ends CANCELED with error code 0 by the time ``cancel`` returns;
  a task that had already ended keeps the outcome it had (the very same object) and the
  cancel raises nothing. The server is left with no task.
- preempt: a first task still running ends at once the way its server documents: the
  navigation server aborts it (FAILED, error code 0, "preempted ...", Nav2's abort with an
  empty result); the base controllers and the arm cancel it (CANCELED, "preempted ...").
  A goal of another type cancels the running task (CANCELED), as a Nav2 script must before
  sending it. One that had ended keeps its outcome. The new task then ends as it would
  alone: SUCCEEDED, with the robot where its goal says, and the server idle afterwards.
- a first task that ended on its own before the cancel or preempt ended as it does alone
  (SUCCEEDED where its goal says; assisted teleop: FAILED with TIMEOUT; the sealed-off goal:
  FAILED with NO_VALID_PATH).

At rest after a cancel (the TurtleBot3 base: 100 Hz, 2.5 m/s^2, 3.2 rad/s^2). A base moving
at 0.22 m/s cannot stop in one 10 ms period, so the claim is split:

- commanded: ``cmd_vel`` is zero the moment the cancel returns and nothing commands the base
  again; the wheel velocity targets (actuator controls) ramp down monotonically within the
  acceleration limits and are zero from ``t_c + max(|v|/a, |w|/alpha) + one period`` on,
  ``(v, w)`` being the velocity sent to the wheels when the cancel came;
- measured: the body's forward speed is below 0.01 m/s and its yaw rate below 0.05 rad/s from
  that same moment on, and the robot travels no farther than its braking distance
  ``v^2 / 2a`` (plus one period at ``v`` and 1 cm; the same for the heading).

The 0.01 m/s and 0.05 rad/s are a tenth of the Burger's slowest commanded speeds (Nav2's 0.10
m/s minimum, the 0.4 rad/s minimum spin rate) and well above the physics' residual jitter
(< 1 mm/s once stopped). The body follows its wheels: it is at rest a few ms before their
targets reach zero (measured with the 2 ms and the 5 ms physics steps). A model that lets the
Burger pitch off its caster when braking at 2.5 m/s^2 and rock on after its wheels stopped
fails here (one tried in session 2 rocked for 0.12 s at up to 0.08 m/s).

The arm after a cancel holds the TCP where it was: the impedance set-point is that pose from
the next control step on and never moves; the TCP swings back from its momentum (at most
``ARM_MAX_SWING``) and is within ``ARM_HOLD_TOLERANCE`` of it, slower than 0.01 m/s, after
``ARM_SETTLE``. A canceled gripper holds its width: the set-point stays at the width of the
cancel and the fingers stop.

Each task type builds its own simulation and reuses it across its examples, so that each
example's history, down to the phase of every periodic callback, is the same in every run,
whatever ran before and on whichever xdist worker. Between examples the robot is only put
back at its start (a teleport, or a move of the arm, which is itself a task that must
succeed); every other piece of server state carries over, so a leftover from one example
(a task still running, a path still current, feedback still changing, a stale teleop
command) shows in the next.
"""

from __future__ import annotations

import copy
import itertools
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import mujoco
import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, example, given, settings
from hypothesis import strategies as st
from navigation_rig import ROOM_DOCK, dock_room, sealed_room, walker_room, yaw_error
from navigation_rig import distance as planar_distance

from baobab.nav import BasicNavigator, TaskResult
from baobab.nav.errors import AssistedTeleopError, ComputePathToPoseError
from baobab.nav.msgs import Header, Quaternion, Twist, Vector3, pose_stamped
from baobab.nav.msgs import Path as PathMessage
from baobab.nav.ros.geographic_msgs.msg import GeoPoint, GeoPose
from baobab.nav.server import NavigationServer
from baobab.robots.diff_drive.base import DiffDriveBase
from baobab.robots.diff_drive.controller_tasks import BaseControllerServer
from baobab.robots.panda.arm_server import ArmServer
from baobab.robots.panda.gripper import MIN_GRASP_WIDTH, STALL_SPEED
from baobab.robots.panda.model import MAX_OPENING, TCP_SITE
from baobab.robots.panda.pose import Pose
from baobab.robots.panda.scene import build_panda_sim
from baobab.robots.turtlebot3 import build_turtlebot3_sim
from baobab.sim.geodesy import MapDatum
from baobab.sim.simulation import Simulation
from baobab.sim.tasks import TaskHandle, TaskOutcome, TaskStatus
from baobab.sim.world import Pose2D, World, load_world

LINEAR_AT_REST = 0.01
"""m/s: a base slower than this is at rest."""
ANGULAR_AT_REST = 0.05
"""rad/s: a base turning slower than this is at rest."""
REST_WATCH = 0.1
"""s the at-rest tolerances are watched for once they apply."""
SETTLE_AFTER_TELEPORT = 0.1
"""s for a teleported robot to settle on its wheels (it lands a little off its contacts)."""
BRAKING_SLACK = (0.01, 0.03)
"""m and rad a stopping base may move beyond its braking distance and angle."""

ARM_MAX_SWING = 0.015
"""m the TCP may swing past the pose it holds after a cancel."""
ARM_SETTLE = 0.6
"""s after a cancel by which the arm is still (measured: 0.4 s from 0.2 m/s)."""
ARM_HOLD_TOLERANCE = 0.003
"""m from the held pose once settled."""
TCP_AT_REST = 0.01
"""m/s: a TCP slower than this is at rest."""
GRIPPER_SETTLE = 0.2
"""s after a cancel by which the fingers have stopped."""
GRIPPER_HOLD_TOLERANCE = 0.002
"""m the hand's width may differ from the width it holds, once stopped."""

NAV_POSE_TOLERANCE = (0.25, 0.25)
"""m and rad: Nav2's goal checker (the robot may drift a little while braking: + 3 cm)."""
POINT_TOLERANCE = 0.06
"""m: the base controllers' 5 cm goal tolerance plus one 50 ms monitor period at 0.2 m/s."""


def property_settings(examples: int) -> settings:
    """Deterministic hypothesis settings: fixed derivation, no deadline, ``examples`` runs."""
    return settings(
        max_examples=examples,
        derandomize=True,
        deadline=None,
        # Examples take seconds of sim time: report a failure as found, without shrinking it.
        phases=(Phase.explicit, Phase.generate),
        # The fixtures are the simulations, one per test item (task type) and shared by its
        # examples on purpose: the sequence of examples, and so each one's history, is fixed
        # whatever other tests run first, or on which xdist worker.
        suppress_health_check=[
            HealthCheck.too_slow,
            HealthCheck.data_too_large,
            HealthCheck.function_scoped_fixture,
        ],
    )


Action = str
ACTIONS = st.sampled_from(["cancel", "preempt"])
"""Cancel the task, or send a new goal of the same type."""
NAV_ACTIONS = st.sampled_from(["cancel", "preempt", "switch"])
"""... or a goal of another type."""
PERMILLE = st.integers(min_value=0, max_value=1000)
"""Where in the horizon the cancel or new goal comes, in thousandths.

Each test also runs explicit examples at 0, mid-task (300) and past the end (1000) for every
action, whatever hypothesis draws (its derandomized draws follow the test's source).
"""


# -- shared checks ---------------------------------------------------------------------------


def advance(sim: Simulation, seconds: float) -> None:
    """Step ``seconds`` of sim time, rounded to whole physics steps."""
    sim.step_to(sim.step_count + round(seconds / sim.physics_dt))


def delay_steps(sim: Simulation, horizon: float, permille: int) -> int:
    """Physics steps for ``permille`` thousandths of ``horizon`` seconds."""
    return round(permille / 1000 * horizon / sim.physics_dt)


def assert_cancel_consistent(handle: TaskHandle, before: TaskOutcome | None) -> None:
    """CANCELED (code 0) if it was running; else the outcome it had, untouched."""
    outcome = handle.outcome
    if before is None:
        assert outcome is not None, f"{handle.name} still running after cancel()"
        assert outcome.status is TaskStatus.CANCELED, outcome
        assert outcome.error_code == 0, outcome
    else:
        assert outcome is before


def assert_preempted(handle: TaskHandle, before: TaskOutcome | None, status: TaskStatus) -> None:
    """Ended with ``status`` (code 0, "preempted") at once if it was running; else untouched."""
    outcome = handle.outcome
    if before is None:
        assert outcome is not None, f"{handle.name} still running after a new goal"
        assert outcome.status is status, outcome
        assert outcome.error_code == 0, outcome
        assert outcome.error_msg.startswith("preempted"), outcome
    else:
        assert outcome is before


def assert_ended_as_alone(before: TaskOutcome | None, status: TaskStatus, code: int = 0) -> None:
    """A first task that ended on its own ended as it does alone."""
    if before is not None:
        assert before.status is status, before
        assert before.error_code == code, before


def assert_base_comes_to_rest(sim: Simulation, base: DiffDriveBase) -> None:
    """Step until the base is at rest, checking every physics step (see the module notes)."""
    assert base.target == (0.0, 0.0), f"commanded {base.target} when told to stop"
    facts, period = base.facts, base.period
    v0, w0 = base.commanded
    start, t0 = base.pose(), sim.time
    decel = max(abs(v0) / facts.max_linear_accel, abs(w0) / facts.max_angular_accel)
    at_rest = t0 + decel + period
    actuators = [sim.data.actuator(name) for name in base.names.wheel_actuators]
    previous = (abs(v0), abs(w0))
    yaw, last_yaw = 0.0, start.yaw
    while sim.time < at_rest + REST_WATCH - 1e-9:
        sim.step_to(sim.step_count + 1)
        now = sim.time
        assert base.target == (0.0, 0.0), f"commanded {base.target} {now - t0:.3f} s after"
        commanded = (abs(base.commanded[0]), abs(base.commanded[1]))
        assert all(c <= p + 1e-12 for c, p in zip(commanded, previous, strict=True)), (
            f"commanded velocity rose while stopping: {previous} -> {commanded}"
        )
        previous = commanded
        wheels = [float(actuator.ctrl[0]) for actuator in actuators]
        assert wheels == pytest.approx(base.wheel_speeds(*base.commanded), abs=1e-12)
        pose = base.pose()
        yaw += math.remainder(pose.yaw - last_yaw, 2 * math.pi)
        last_yaw = pose.yaw
        if now >= at_rest - 1e-9:
            assert max(map(abs, wheels)) < 1e-9, f"wheel targets {wheels} {now - t0:.3f} s after"
            v, w = base.body_velocity()
            assert abs(v) < LINEAR_AT_REST and abs(w) < ANGULAR_AT_REST, (
                f"moving at ({v:.4f} m/s, {w:.4f} rad/s) {now - t0:.3f} s after"
            )
    end = base.pose()
    travelled = math.hypot(end.x - start.x, end.y - start.y)
    braking = v0**2 / (2 * facts.max_linear_accel) + abs(v0) * period + BRAKING_SLACK[0]
    turning = w0**2 / (2 * facts.max_angular_accel) + abs(w0) * period + BRAKING_SLACK[1]
    assert travelled <= braking, f"travelled {travelled:.4f} m from {v0:.3f} m/s"
    assert abs(yaw) <= turning, f"turned {yaw:.4f} rad from {w0:.3f} rad/s"


def run_until_done(sim: Simulation, handle: TaskHandle, limit: float, poll: int = 10) -> float:
    """Step ``poll`` physics steps at a time until ``handle`` ends; the sim time it ended by.

    Fails past ``limit`` s of sim time.
    """
    end = sim.time + limit
    while not handle.status.done:
        assert sim.time < end, f"{handle.name} still running after {limit} s"
        sim.step_to(sim.step_count + poll)
    return sim.time


# -- the navigation facade -------------------------------------------------------------------

RESULTS = {
    TaskStatus.SUCCEEDED: TaskResult.SUCCEEDED,
    TaskStatus.FAILED: TaskResult.FAILED,
    TaskStatus.CANCELED: TaskResult.CANCELED,
}
"""The facade's result for each outcome."""

Finish = Callable[[], None]
"""Runs a new goal to its end and checks it ended as it would alone."""


@dataclass(frozen=True)
class NavCase:
    """One facade task type: its first goal, its horizon and its preempting goals."""

    name: str
    horizon: float
    """s of sim time the cancel or new goal is drawn from (past the first goal's end)."""
    send: Callable[[BasicNavigator], object]
    preempt: Callable[[BasicNavigator, int], Finish]
    """Sends new goal ``variant`` (0 or 1); returns what finishes and checks it."""
    end: Pose2D | None = None
    """Where the first goal leaves the robot when it succeeds, if that is known."""
    end_tolerance: tuple[float, float] = (NAV_POSE_TOLERANCE[0] + 0.03, NAV_POSE_TOLERANCE[1])
    """m and rad around ``end``."""
    switch: Callable[[BasicNavigator], Finish] | None = None
    """Sends a goal of another type (default: a goToPose); returns what finishes it."""
    world: str = "cafe"
    natural: TaskStatus = TaskStatus.SUCCEEDED
    natural_code: int = 0


def wait_nav(navigator: BasicNavigator, limit: float) -> None:
    """Poll ``isTaskComplete`` as a script does; fails past ``limit`` s of sim time."""
    sim = navigator.server.sim
    end = sim.time + limit
    while not navigator.isTaskComplete():
        assert sim.time < end, f"task still running after {limit} s"


def diff_drive(navigator: BasicNavigator) -> DiffDriveBase:
    base = navigator.server.base
    assert isinstance(base, DiffDriveBase)
    return base


def reaches(navigator: BasicNavigator, goal: Pose2D, limit: float) -> Finish:
    """Finish: the task succeeds with the robot at ``goal`` (Nav2's tolerances + 3 cm)."""

    def finish() -> None:
        wait_nav(navigator, limit)
        assert navigator.getResult() is TaskResult.SUCCEEDED, navigator.getTaskError()
        pose = navigator.robot_pose()
        assert planar_distance(pose, goal) < NAV_POSE_TOLERANCE[0] + 0.03, (pose, goal)
        assert yaw_error(pose, goal) < NAV_POSE_TOLERANCE[1], (pose, goal)

    return finish


def go_to_pose(navigator: BasicNavigator, goal: Pose2D) -> Finish:
    navigator.goToPose(pose_stamped(goal.x, goal.y, goal.yaw))
    return reaches(navigator, goal, 30.0)


def go_through_poses(navigator: BasicNavigator, goals: list[Pose2D]) -> Finish:
    navigator.goThroughPoses([pose_stamped(g.x, g.y, g.yaw) for g in goals])
    return reaches(navigator, goals[-1], 40.0)


def follow_waypoints(navigator: BasicNavigator, goals: list[Pose2D]) -> Finish:
    navigator.followWaypoints([pose_stamped(g.x, g.y, g.yaw) for g in goals])
    handle = navigator.server.active_task
    assert handle is not None
    reach = reaches(navigator, goals[-1], 50.0)

    def finish() -> None:
        reach()
        assert handle.feedback["missed_waypoints"] == []

    return finish


def polyline(corners: list[tuple[float, float]], spacing: float = 0.05) -> PathMessage:
    """A ``nav_msgs/Path`` along ``corners`` every ``spacing`` m, yaw along each leg."""
    poses = []
    for (x0, y0), (x1, y1) in itertools.pairwise(corners):
        count = max(1, math.ceil(math.hypot(x1 - x0, y1 - y0) / spacing))
        yaw = math.atan2(y1 - y0, x1 - x0)
        poses += [
            pose_stamped(x0 + (x1 - x0) * i / count, y0 + (y1 - y0) * i / count, yaw)
            for i in range(count)
        ]
    poses.append(pose_stamped(*corners[-1], yaw))
    return PathMessage(header=Header(frame_id="map"), poses=poses)


def follow_path(navigator: BasicNavigator, corners: list[tuple[float, float]]) -> Finish:
    navigator.followPath(polyline(corners))
    (x0, y0), (x1, y1) = corners[-2:]
    return reaches(navigator, Pose2D(x=x1, y=y1, yaw=math.atan2(y1 - y0, x1 - x0)), 30.0)


LANES = Path(__file__).parent / "missions" / "worlds" / "lanes.yaml"
"""The route graph and GPS test world: a loop of lanes round an island, with a datum."""


def follow_gps_waypoints(navigator: BasicNavigator, goals: list[Pose2D]) -> Finish:
    """GPS waypoints at the map poses ``goals`` (through the world's datum)."""
    assert navigator.world.datum is not None
    plane = MapDatum(navigator.world.datum)
    poses = []
    for goal in goals:
        latitude, longitude, _ = plane.to_geodetic(goal.x, goal.y)
        orientation = Quaternion(z=math.sin(goal.yaw / 2), w=math.cos(goal.yaw / 2))
        poses.append(
            GeoPose(
                position=GeoPoint(latitude=latitude, longitude=longitude), orientation=orientation
            )
        )
    navigator.followGpsWaypoints(poses)
    return reaches(navigator, goals[-1], 50.0)


NAV_TICK = 0.05
"""s: the navigation server's control period; a new task's first tick comes within it."""


def residual_motion(base: DiffDriveBase) -> tuple[float, float]:
    """How far (m) and how much (rad) the base may still move once a new task takes over.

    The old command runs on for up to one navigation tick, then the base brakes from it.
    """
    (v, w), facts = base.commanded, base.facts
    return (
        abs(v) * NAV_TICK + v**2 / (2 * facts.max_linear_accel),
        abs(w) * NAV_TICK + w**2 / (2 * facts.max_angular_accel),
    )


class YawTracker:
    """Unwrapped heading change of the robot, sampled every physics step."""

    def __init__(self, navigator: BasicNavigator) -> None:
        self._base = navigator.server.base
        self._last = self._base.pose().yaw
        self.turned = 0.0
        self._handle = navigator.server.sim.every(
            navigator.server.sim.physics_dt, self._sample, name="yaw tracker"
        )

    def _sample(self, _now: float) -> None:
        yaw = self._base.pose().yaw
        self.turned += math.remainder(yaw - self._last, 2 * math.pi)
        self._last = yaw

    def close(self) -> None:
        self._handle.cancel()


def spin(navigator: BasicNavigator, angle: float) -> Finish:
    """The robot ends turned by ``angle`` from where the new spin started.

    The spin overshoots by up to one 10 Hz cycle at the 0.4 rad/s minimum and the braking
    (0.1 rad); before it starts counting, the robot may still turn with the old command
    (:func:`residual_motion`).
    """
    tracker = YawTracker(navigator)
    turn = residual_motion(diff_drive(navigator))[1]
    navigator.spin(angle)
    handle = navigator.server.active_task
    assert handle is not None

    def finish() -> None:
        try:
            wait_nav(navigator, 15.0)
        finally:
            tracker.close()
        assert navigator.getResult() is TaskResult.SUCCEEDED, navigator.getTaskError()
        counted = handle.feedback["angular_distance_traveled"]
        assert abs(counted) >= abs(angle) and abs(counted - angle) < 0.1, counted
        assert abs(tracker.turned - angle) < 0.1 + turn, (tracker.turned, angle)

    return finish


def drive(navigator: BasicNavigator, distance: float, speed: float, *, backwards: bool) -> Finish:
    """The robot ends ``distance`` m ahead of (or behind) where the new goal came.

    It overshoots by up to one 10 Hz cycle at the 0.10 m/s minimum (3 cm), and it may still
    move with the old command (:func:`residual_motion`) before the new drive measures from
    its start: it drives straight on whatever heading it then has.
    """
    start = navigator.robot_pose()
    slack, turn = residual_motion(diff_drive(navigator))
    if backwards:
        navigator.backup(distance, speed)
    else:
        navigator.driveOnHeading(distance, speed)

    def finish() -> None:
        wait_nav(navigator, 15.0)
        assert navigator.getResult() is TaskResult.SUCCEEDED, navigator.getTaskError()
        end = navigator.robot_pose()
        assert abs(planar_distance(start, end) - distance) < 0.03 + slack, (start, end)
        along = (end.x - start.x) * math.cos(start.yaw) + (end.y - start.y) * math.sin(start.yaw)
        assert (along < 0) == backwards, (start, end)
        assert yaw_error(end, start) < 0.05 + turn, (start, end)

    return finish


def teleop(linear: float, angular: float) -> Twist:
    return Twist(linear=Vector3(x=linear), angular=Vector3(z=angular))


TELEOP_FIRST = (0.15, 0.4)
TELEOP_SECOND = ((0.10, -0.3), (0.2, 0.0))


def start_teleop(navigator: BasicNavigator) -> None:
    navigator.publishTeleop(teleop(*TELEOP_FIRST))
    navigator.assistedTeleop(time_allowance=2.0)


def assisted_teleop(navigator: BasicNavigator, variant: int) -> Finish:
    """The new session passes its own twist on, then ends SUCCEEDED on ``preemptTeleop``."""
    twist = TELEOP_SECOND[variant]
    navigator.publishTeleop(teleop(*twist))
    navigator.assistedTeleop(time_allowance=3.0)

    def finish() -> None:
        sim = navigator.server.sim
        advance(sim, 1.0)
        assert navigator.isTaskComplete() is False
        v, w = navigator.server.base.body_velocity()
        assert abs(v - twist[0]) < 0.02 and abs(w - twist[1]) < 0.1, (v, w)
        navigator.preemptTeleop()
        wait_nav(navigator, 0.5)
        assert navigator.getResult() is TaskResult.SUCCEEDED, navigator.getTaskError()

    return finish


DOCKED = Pose2D(x=ROOM_DOCK.x, y=ROOM_DOCK.y, yaw=ROOM_DOCK.yaw)
DOCK_END = (0.07, 0.1)
"""m and rad around the dock pose: Nav2's 5 cm docking threshold, and the braking."""
STAGING = Pose2D(x=ROOM_DOCK.to_map(-0.7, 0.0)[0], y=ROOM_DOCK.to_map(-0.7, 0.0)[1], yaw=0.3)
UNDOCK_END = (0.08, 0.1)
"""m and rad around the staging pose after undocking: the 5 cm tolerance, and the braking."""


def dock(navigator: BasicNavigator, variant: int) -> Finish:
    """The new docking goal (by id, or by pose) docks the robot and it charges."""
    if variant == 0:
        navigator.dockRobotByID("home", nav_to_dock=False)
    else:
        navigator.dockRobotByPose(pose_stamped(DOCKED.x, DOCKED.y, DOCKED.yaw), nav_to_dock=False)

    def finish() -> None:
        wait_nav(navigator, 40.0)
        assert navigator.getResult() is TaskResult.SUCCEEDED, navigator.getTaskError()
        pose = navigator.robot_pose()
        assert planar_distance(pose, DOCKED) < DOCK_END[0], pose
        assert navigator.server.docking.is_charging()

    return finish


def dock_then_undock(navigator: BasicNavigator) -> None:
    """Dock from the staging pose (to its end), then send the undocking goal."""
    navigator.dockRobotByID("home", nav_to_dock=False)
    wait_nav(navigator, 40.0)
    assert navigator.getResult() is TaskResult.SUCCEEDED, navigator.getTaskError()
    navigator.undockRobot()


def undock(navigator: BasicNavigator) -> Finish:
    """The new undocking goal ends SUCCEEDED off the charger (backed out, or not docked)."""
    navigator.undockRobot("charging_dock")

    def finish() -> None:
        wait_nav(navigator, 40.0)
        assert navigator.getResult() is TaskResult.SUCCEEDED, navigator.getTaskError()
        assert not navigator.server.docking.is_charging()

    return finish


def follow(navigator: BasicNavigator, variant: int) -> Finish:
    """The new following goal (by TF frame) succeeds once its max_duration has passed."""
    navigator.followObjectByFrame("person", max_duration=(2, 3)[variant])

    def finish() -> None:
        wait_nav(navigator, 10.0)
        assert navigator.getResult() is TaskResult.SUCCEEDED, navigator.getTaskError()

    return finish


SPIN_END = (0.02, 0.1)
"""m and rad around a behaviour's end pose: it turns (or drives) in place."""
DRIVE_END = (0.04, 0.05)
"""m and rad: one 10 Hz cycle at 0.10 m/s past the distance, and the braking."""

NAV_CASES = [
    NavCase(
        "goToPose",
        7.0,
        lambda nav: go_to_pose(nav, Pose2D(x=1.0, y=0.4, yaw=0.5)),
        lambda nav, variant: go_to_pose(
            nav, [Pose2D(x=0.2, y=-0.7, yaw=-1.57), Pose2D(x=-0.6, y=0.5, yaw=3.0)][variant]
        ),
        end=Pose2D(x=1.0, y=0.4, yaw=0.5),
        switch=lambda nav: spin(nav, 1.0),
    ),
    NavCase(
        "goThroughPoses",
        8.0,
        lambda nav: go_through_poses(
            nav, [Pose2D(x=0.6, y=0.4, yaw=0.5), Pose2D(x=1.1, y=0.2, yaw=0.0)]
        ),
        lambda nav, variant: go_through_poses(
            nav,
            [
                [Pose2D(x=0.3, y=-0.4, yaw=-1.0), Pose2D(x=0.0, y=-0.8, yaw=3.1)],
                [Pose2D(x=-0.4, y=0.3, yaw=2.5), Pose2D(x=-0.8, y=0.0, yaw=3.1)],
            ][variant],
        ),
        end=Pose2D(x=1.1, y=0.2, yaw=0.0),
    ),
    NavCase(
        "followWaypoints",
        9.0,
        lambda nav: follow_waypoints(
            nav, [Pose2D(x=0.6, y=0.0, yaw=0.0), Pose2D(x=0.6, y=0.5, yaw=1.57)]
        ),
        lambda nav, variant: follow_waypoints(
            nav,
            [
                [Pose2D(x=0.0, y=0.5, yaw=3.1), Pose2D(x=-0.4, y=0.0, yaw=-1.57)],
                [Pose2D(x=0.3, y=-0.6, yaw=-1.57)],
            ][variant],
        ),
        end=Pose2D(x=0.6, y=0.5, yaw=1.57),
    ),
    NavCase(
        "followPath",
        7.0,
        lambda nav: follow_path(nav, [(0.0, 0.0), (1.0, 0.0)]),
        lambda nav, variant: follow_path(
            nav, [[(0.2, 0.0), (0.8, 0.0), (0.8, 0.6)], [(0.5, 0.0), (0.5, -0.6)]][variant]
        ),
        end=Pose2D(x=1.0, y=0.0, yaw=0.0),
    ),
    NavCase(
        "spin",
        3.0,
        lambda nav: nav.spin(1.57),
        lambda nav, variant: spin(nav, [-1.0, 2.0][variant]),
        end=Pose2D(x=0.0, y=0.0, yaw=1.57),
        end_tolerance=SPIN_END,
        switch=lambda nav: drive(nav, 0.2, 0.1, backwards=False),
    ),
    NavCase(
        "backup",
        3.5,
        lambda nav: nav.backup(0.3, 0.15),
        lambda nav, variant: drive(nav, *[(0.15, 0.10), (0.25, 0.2)][variant], backwards=True),
        end=Pose2D(x=-0.3, y=0.0, yaw=0.0),
        end_tolerance=DRIVE_END,
    ),
    NavCase(
        "driveOnHeading",
        3.5,
        lambda nav: nav.driveOnHeading(0.4, 0.2),
        lambda nav, variant: drive(nav, *[(0.2, 0.10), (0.3, 0.15)][variant], backwards=False),
        end=Pose2D(x=0.4, y=0.0, yaw=0.0),
        end_tolerance=DRIVE_END,
    ),
    NavCase(
        "assistedTeleop",
        3.0,
        start_teleop,
        assisted_teleop,
        natural=TaskStatus.FAILED,
        natural_code=AssistedTeleopError.TIMEOUT,
    ),
    # Docking from the staging pose: perception, the graceful approach, charging (~4.5 s).
    NavCase(
        "dockRobot",
        6.0,
        lambda nav: nav.dockRobotByID("home", nav_to_dock=False),
        dock,
        end=DOCKED,
        end_tolerance=DOCK_END,
        world="dock_room",
    ),
    # Undocking (once docked): charging off, backing out 0.7 m to the staging pose (~5 s).
    NavCase(
        "undockRobot",
        6.5,
        dock_then_undock,
        lambda nav, variant: undock(nav),
        end=STAGING,
        end_tolerance=UNDOCK_END,
        world="dock_room",
    ),
    # Following a walking person by its frame, for 4 s (then it succeeds).
    NavCase(
        "followObject",
        5.0,
        lambda nav: nav.followObjectByFrame("person", max_duration=4),
        follow,
        world="walker",
        switch=lambda nav: spin(nav, 1.0),
    ),
    NavCase(
        "followGpsWaypoints",
        9.0,
        lambda nav: follow_gps_waypoints(
            nav, [Pose2D(x=-2.5, y=0.6, yaw=1.57), Pose2D(x=-2.0, y=1.2, yaw=0.8)]
        ),
        lambda nav, variant: follow_gps_waypoints(
            nav,
            [
                [Pose2D(x=-2.8, y=-0.8, yaw=-1.57)],
                [Pose2D(x=-2.2, y=0.9, yaw=1.0), Pose2D(x=-2.6, y=-0.5, yaw=-2.0)],
            ][variant],
        ),
        end=Pose2D(x=-2.0, y=1.2, yaw=0.8),
        switch=lambda nav: go_to_pose(nav, Pose2D(x=-2.6, y=-1.0, yaw=-1.57)),
        world="lanes",
    ),
    # A goal sealed off by walls: replanning fails, and the cancels and new goals land in the
    # recoveries (clearing, Spin, Wait, BackUp) until NO_VALID_PATH ends it after ~17 s.
    NavCase(
        "goToPose_recovering",
        20.0,
        lambda nav: nav.goToPose(pose_stamped(1.5, 1.0, 0.0)),
        lambda nav, variant: go_to_pose(
            nav, [Pose2D(x=-0.8, y=-1.0, yaw=0.8), Pose2D(x=-1.5, y=-0.6, yaw=1.57)][variant]
        ),
        world="sealed",
        natural=TaskStatus.FAILED,
        natural_code=ComputePathToPoseError.NO_VALID_PATH,
        switch=lambda nav: spin(nav, 1.0),
    ),
]

WORLDS: dict[str, Callable[[], World | str]] = {
    "cafe": lambda: "cafe",
    "sealed": sealed_room,
    "dock_room": dock_room,
    "walker": walker_room,
    "lanes": lambda: load_world(LANES),
}
"""The worlds the cases run in; each robot starts at its world's spawn."""


class Navigators:
    """The navigators of one task type, one per world, built on first use."""

    def __init__(self) -> None:
        self._built: dict[str, BasicNavigator] = {}

    def get(self, world: str) -> BasicNavigator:
        if world not in self._built:
            self._built[world] = BasicNavigator(world=WORLDS[world](), seed=0)
        return self._built[world]

    def close(self) -> None:
        for navigator in self._built.values():
            navigator.destroy_node()


@pytest.fixture
def navigators() -> Iterator[Navigators]:
    built = Navigators()
    yield built
    built.close()


def reset_navigator(navigator: BasicNavigator) -> DiffDriveBase:
    """Check nothing is left of the last example, then put the robot back at its start."""
    server, base = navigator.server, diff_drive(navigator)
    assert server.active_task is None, "a task is still running"
    assert base.target == (0.0, 0.0)
    spawn = navigator.world.spawn
    navigator.setInitialPose(pose_stamped(spawn.x, spawn.y, spawn.yaw))
    advance(server.sim, SETTLE_AFTER_TELEPORT)
    return base


def cleanup_after_failure(server: NavigationServer) -> None:
    """Leave the server idle when an example failed, so the test's next example starts clean."""
    server.cancel()
    server.sim.step_for(1.0)


SWITCH_GOAL = Pose2D(x=0.5, y=-0.5, yaw=-0.8)
"""Where the default goal of another type (a goToPose) goes."""


@pytest.mark.parametrize("case", NAV_CASES, ids=[case.name for case in NAV_CASES])
@property_settings(5)
@given(permille=PERMILLE, action=NAV_ACTIONS, variant=st.integers(0, 1))
@example(permille=0, action="cancel", variant=0)
@example(permille=0, action="preempt", variant=0)
@example(permille=300, action="cancel", variant=0)
@example(permille=300, action="preempt", variant=1)
@example(permille=500, action="switch", variant=0)
@example(permille=1000, action="cancel", variant=0)
def test_navigator_tasks_cancel_and_preempt_at_any_moment(
    navigators: Navigators, case: NavCase, permille: int, action: Action, variant: int
) -> None:
    """Cancel, a new goal of the same type, or one of another type, at a random moment.

    A goal of another type cancels the running task (CANCELED) before it starts, as a Nav2
    script must (the facade does it for the script).
    """
    navigator = navigators.get(case.world)
    server, sim = navigator.server, navigator.server.sim
    base = reset_navigator(navigator)
    try:
        case.send(navigator)
        first = server.active_task
        assert first is not None
        sim.step_to(sim.step_count + delay_steps(sim, case.horizon, permille))
        before = first.outcome
        assert_ended_as_alone(before, case.natural, case.natural_code)
        if before is not None and before.status is TaskStatus.SUCCEEDED and case.end:
            pose = navigator.robot_pose()
            assert planar_distance(pose, case.end) < case.end_tolerance[0], pose
            assert yaw_error(pose, case.end) < case.end_tolerance[1], pose
        if action == "cancel":
            navigator.cancelTask()
            assert_cancel_consistent(first, before)
            assert server.current_path is None
            expected = TaskResult.CANCELED if before is None else RESULTS[before.status]
            assert navigator.getResult() is expected
            assert navigator.isTaskComplete()
            assert navigator.getFeedback() is None
        else:
            if action == "preempt":
                finish = case.preempt(navigator, variant)
                assert_preempted(first, before, TaskStatus.FAILED)
            else:
                switch = case.switch or (lambda nav: go_to_pose(nav, SWITCH_GOAL))
                finish = switch(navigator)
                assert_cancel_consistent(first, before)
                assert server.current_path is None, "the canceled task's path is still current"
            second = server.active_task
            assert second is not None and second is not first
            assert second.feedback is not first.feedback
            assert navigator.getResult() is TaskResult.UNKNOWN
            last_feedback = copy.deepcopy(first.feedback)
            finish()
            assert second.status is TaskStatus.SUCCEEDED
            assert first.feedback == last_feedback, "an ended task's feedback changed"
        assert server.active_task is None
        assert_base_comes_to_rest(sim, base)
    except BaseException:
        cleanup_after_failure(server)
        raise


@property_settings(5)
@given(permille=PERMILLE, action=ACTIONS, variant=st.integers(0, 1))
@example(permille=0, action="cancel", variant=0)
@example(permille=300, action="cancel", variant=0)
@example(permille=300, action="preempt", variant=1)
@example(permille=1000, action="preempt", variant=0)
def test_the_navigation_servers_wait_cancels_and_preempts_at_any_moment(
    navigators: Navigators, permille: int, action: Action, variant: int
) -> None:
    """Nav2's Wait, which the facade does not offer: the server's ``wait`` and ``cancel``.

    A new wait ends ``duration`` after its first tick, which comes within one 50 ms control
    period; the behaviour then cycles at 10 Hz.
    """
    navigator = navigators.get("cafe")
    server, sim = navigator.server, navigator.server.sim
    base = reset_navigator(navigator)
    try:
        first = server.wait(1.0)
        sim.step_to(sim.step_count + delay_steps(sim, 1.5, permille))
        before = first.outcome
        assert_ended_as_alone(before, TaskStatus.SUCCEEDED)
        if action == "cancel":
            server.cancel()
            assert_cancel_consistent(first, before)
        else:
            duration = (0.5, 0.3)[variant]
            sent = sim.time
            second = server.wait(duration)
            assert_preempted(first, before, TaskStatus.FAILED)
            ended = run_until_done(sim, second, 2.0, poll=1)
            assert second.status is TaskStatus.SUCCEEDED
            assert duration - 1e-9 <= ended - sent <= duration + 0.15 + 1e-9, ended - sent
        assert server.active_task is None
        assert_base_comes_to_rest(sim, base)
    except BaseException:
        cleanup_after_failure(server)
        raise


ROUTE_GOALS = {2: Pose2D(x=-1.5, y=1.5), 6: Pose2D(x=-1.5, y=-2.0), 3: Pose2D(x=1.5, y=1.5)}
"""The lanes world's nodes the route cases drive to (m)."""


@property_settings(5)
@given(permille=PERMILLE, action=ACTIONS, variant=st.integers(0, 1))
@example(permille=0, action="cancel", variant=0)
@example(permille=300, action="cancel", variant=0)
@example(permille=300, action="preempt", variant=1)
@example(permille=1000, action="preempt", variant=0)
def test_a_driven_route_cancels_and_preempts_at_any_moment(
    navigators: Navigators, permille: int, action: Action, variant: int
) -> None:
    """The mission leaf's follow_route: node 1 to node 2 of the lanes' route graph; a new goal
    takes over in place (the old one ends FAILED, "preempted") and its route is planned
    from the robot's pose; a cancel ends the route's tracking too."""
    navigator = navigators.get("lanes")
    server, sim = navigator.server, navigator.server.sim
    routes = navigator.world_servers.routes
    assert routes is not None
    base = reset_navigator(navigator)
    try:
        first = server.follow_route(1, 2)
        sim.step_to(sim.step_count + delay_steps(sim, 14.0, permille))
        before = first.outcome
        assert_ended_as_alone(before, TaskStatus.SUCCEEDED)
        if before is not None:
            assert planar_distance(navigator.robot_pose(), ROUTE_GOALS[2]) < 0.3
        if action == "cancel":
            server.cancel()
            assert_cancel_consistent(first, before)
        else:
            goal = (6, 3)[variant]
            second = server.follow_route(None, goal)
            assert_preempted(first, before, TaskStatus.FAILED)
            run_until_done(sim, second, 80.0)
            assert second.status is TaskStatus.SUCCEEDED, second.outcome
            assert planar_distance(navigator.robot_pose(), ROUTE_GOALS[goal]) < 0.3
            assert second.feedback["last_node_id"] == goal
        assert server.active_task is None
        assert routes.tracking is None
        assert_base_comes_to_rest(sim, base)
    except BaseException:
        cleanup_after_failure(server)
        raise


# -- the base controllers: go-to-goal and Bug2 -----------------------------------------------


@pytest.fixture
def controllers() -> Iterator[BaseControllerServer]:
    sim, robot = build_turtlebot3_sim("walls", seed=0)
    server = BaseControllerServer(sim, robot.base, robot.lidar)
    yield server
    server.close()


@dataclass(frozen=True)
class PointCase:
    """A base-controller task type: its first goals, each with the goals that may preempt it."""

    name: str
    other: str
    """The other task type of the server (for a goal of another type)."""
    horizon: float
    goals: tuple[tuple[Pose2D, tuple[Pose2D, Pose2D]], ...]
    limit: float
    """s of sim time the new goal may take."""


WALLS_SPAWN = Pose2D(x=0.0, y=0.0, yaw=0.0)
"""The walls world's spawn."""
OPEN_GOALS = (Pose2D(x=0.2, y=-0.6), Pose2D(x=-0.5, y=0.3))
"""Goals in the open west of wall_east, reached straight from anywhere near the spawn."""

POINT_CASES = [
    PointCase("go_to_goal", "bug2", 6.0, ((Pose2D(x=0.6, y=0.5), OPEN_GOALS),), 20.0),
    # The second first goal lies behind wall_east: the moments fall in GO_TO_GOAL and in
    # WALL_FOLLOW. A robot caught facing the wall hits it again whatever the new goal, so
    # the new goals there lie behind the wall too: Bug2 alone then gets round it (within its
    # 30 s progress timeout), where for a goal behind the robot it may tour the whole wall.
    PointCase(
        "bug2",
        "go_to_goal",
        10.0,
        (
            (Pose2D(x=0.6, y=0.5), OPEN_GOALS),
            (Pose2D(x=1.8, y=-0.3), (Pose2D(x=2.2, y=0.0), Pose2D(x=1.8, y=-0.3))),
        ),
        45.0,
    ),
]


def start_point_task(server: BaseControllerServer, name: str, goal: Pose2D) -> TaskHandle:
    return server.go_to_goal(goal) if name == "go_to_goal" else server.bug2(goal)


@pytest.mark.parametrize("case", POINT_CASES, ids=[case.name for case in POINT_CASES])
@property_settings(5)
@given(permille=PERMILLE, action=NAV_ACTIONS, first=st.integers(0, 1), second=st.integers(0, 1))
@example(permille=0, action="cancel", first=0, second=0)
@example(permille=0, action="preempt", first=0, second=0)
@example(permille=300, action="cancel", first=0, second=0)
@example(permille=300, action="preempt", first=0, second=1)
@example(permille=500, action="switch", first=0, second=0)
@example(permille=700, action="cancel", first=1, second=0)  # Bug2: following wall_east
@example(permille=1000, action="cancel", first=0, second=0)
def test_base_controller_tasks_cancel_and_preempt_at_any_moment(
    controllers: BaseControllerServer,
    case: PointCase,
    permille: int,
    action: Action,
    first: int,
    second: int,
) -> None:
    """Cancel, a new goal of the same type, or a goal of the other type (which preempts too).

    A goal of the other type goes to an open goal: from where the first task left the robot
    (by a wall at worst) the straight line to it is clear.
    """
    server, sim, base = controllers, controllers.sim, controllers.base
    assert server.active is None, "a task is still running"
    assert base.target == (0.0, 0.0)
    base.teleport(WALLS_SPAWN)
    advance(sim, 0.25)  # settled, and a fresh scan from the start pose for Bug2
    try:
        first_goal, new_goals = case.goals[first % len(case.goals)]
        handle = start_point_task(server, case.name, first_goal)
        sim.step_to(sim.step_count + delay_steps(sim, case.horizon, permille))
        before = handle.outcome
        assert_ended_as_alone(before, TaskStatus.SUCCEEDED)
        if before is not None:
            assert planar_distance(base.pose(), first_goal) < POINT_TOLERANCE
        if action == "cancel":
            handle.cancel()
            assert_cancel_consistent(handle, before)
        else:
            name, goal = (
                (case.name, new_goals[second])
                if action == "preempt"
                else (case.other, OPEN_GOALS[1])
            )
            new = start_point_task(server, name, goal)
            assert_preempted(handle, before, TaskStatus.CANCELED)
            assert server.active is new
            run_until_done(sim, new, case.limit)
            assert new.status is TaskStatus.SUCCEEDED, new.outcome
            assert planar_distance(base.pose(), goal) < POINT_TOLERANCE
        assert server.active is None
        assert_base_comes_to_rest(sim, base)
    except BaseException:
        if server.active is not None:
            server.active.cancel()
        advance(sim, 1.0)
        raise


# -- the arm: move_to and gripper --------------------------------------------------------------


@dataclass
class ArmRig:
    """The arm server and the TCP pose of its ready configuration (world frame)."""

    arm: ArmServer
    home: Pose


@pytest.fixture
def arm_rig() -> ArmRig:
    _, arm = build_panda_sim(seed=0, cube_xy=(0.5, -0.2))
    return ArmRig(arm, arm.tcp_pose())


def tcp_speed(arm: ArmServer) -> float:
    """Linear speed (m/s) of the TCP site, from the physics."""
    model, data = arm.sim.model, arm.sim.data
    velocity = np.zeros(6)
    site = model.site(arm.prefix + TCP_SITE).id
    mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_SITE, site, velocity, 0)
    return float(np.linalg.norm(velocity[3:]))


def assert_arm_holds(arm: ArmServer) -> None:
    """The set-point stays where the cancel left it; the TCP swings back and is still."""
    sim = arm.sim
    target, reference = arm.controller.target, arm.controller.reference
    held = arm.tcp_pose().position_array
    t0 = sim.time
    while sim.time < t0 + ARM_SETTLE + REST_WATCH - 1e-9:
        sim.step_to(sim.step_count + 1)
        for now, then in zip(
            (*arm.controller.target, *arm.controller.reference), (*target, *reference), strict=True
        ):
            np.testing.assert_allclose(now, then, rtol=0.0, atol=1e-12)
        offset = float(np.linalg.norm(arm.tcp_pose().position_array - held))
        assert offset <= ARM_MAX_SWING, f"TCP {offset * 1000:.1f} mm from the held pose"
        if sim.time >= t0 + ARM_SETTLE - 1e-9:
            assert offset <= ARM_HOLD_TOLERANCE, f"TCP {offset * 1000:.1f} mm off, settled"
            assert tcp_speed(arm) < TCP_AT_REST, f"TCP at {tcp_speed(arm):.4f} m/s, settled"


def move_home(rig: ArmRig) -> None:
    """Bring the TCP back to its ready pose with a move task (which must succeed)."""
    arm = rig.arm
    assert not arm.busy, "a motion is still running"
    if arm.tcp_pose().distance_to(rig.home)[0] > 0.001:
        handle = arm.move_to(rig.home, 0.8)
        run_until_done(arm.sim, handle, 3.0)
        assert handle.status is TaskStatus.SUCCEEDED, handle.outcome
        advance(arm.sim, 0.3)


MOVE_FIRST = ((0.12, 0.06, -0.08), 1.0)
"""TCP offset (m) from home and duration (s) of the first motion."""
MOVE_SECOND = (((-0.06, -0.08, 0.05), 0.8), ((0.0, 0.1, -0.12), 0.8))


@property_settings(5)
@given(permille=PERMILLE, action=ACTIONS, variant=st.integers(0, 1))
@example(permille=0, action="cancel", variant=0)
@example(permille=300, action="cancel", variant=0)
@example(permille=300, action="preempt", variant=1)
@example(permille=1000, action="cancel", variant=0)
def test_arm_motions_cancel_and_preempt_at_any_moment(
    arm_rig: ArmRig, permille: int, action: Action, variant: int
) -> None:
    """A motion canceled holds the TCP where it was; a new one preempts it (CANCELED)."""
    arm, sim = arm_rig.arm, arm_rig.arm.sim
    move_home(arm_rig)
    try:
        offset, duration = MOVE_FIRST
        first_goal = arm_rig.home.translated(*offset)
        handle = arm.move_to(first_goal, duration)
        sim.step_to(sim.step_count + delay_steps(sim, 1.6, permille))
        before = handle.outcome
        assert_ended_as_alone(before, TaskStatus.SUCCEEDED)
        if before is not None:
            assert arm.tcp_pose().distance_to(first_goal)[0] <= arm.config.position_tolerance
        if action == "cancel":
            handle.cancel()
            assert_cancel_consistent(handle, before)
            assert not arm.busy
            if before is None:  # the set-point is the TCP measured at the cancel
                np.testing.assert_allclose(arm.controller.target[0], arm.controller.tcp[0])
            assert_arm_holds(arm)
        else:
            offset, duration = MOVE_SECOND[variant]
            goal = arm_rig.home.translated(*offset)
            new = arm.move_to(goal, duration)
            assert_preempted(handle, before, TaskStatus.CANCELED)
            run_until_done(sim, new, duration + arm.config.settle_timeout + 0.5)
            assert new.status is TaskStatus.SUCCEEDED, new.outcome
            distance, angle = arm.tcp_pose().distance_to(goal)
            assert distance <= arm.config.position_tolerance
            assert angle <= arm.config.orientation_tolerance
            assert not arm.busy
    except BaseException:
        arm.hold()
        advance(sim, 1.0)
        raise


def open_hand(arm: ArmServer) -> None:
    """Open the hand fully with a gripper task (which must succeed)."""
    if arm.hand.width < MAX_OPENING - 0.002:
        handle = arm.gripper("open")
        run_until_done(arm.sim, handle, 3.0)
        assert handle.status is TaskStatus.SUCCEEDED, handle.outcome


def assert_gripper_holds(arm: ArmServer) -> None:
    """The hand's goal stays at the width of the cancel and the fingers stop there."""
    sim, hand = arm.sim, arm.hand
    goal, t0 = hand.goal_width, sim.time
    while sim.time < t0 + GRIPPER_SETTLE + REST_WATCH - 1e-9:
        sim.step_to(sim.step_count + 1)
        assert hand.goal_width == goal and hand.setpoint_settled
        if sim.time >= t0 + GRIPPER_SETTLE - 1e-9:
            assert abs(hand.width_rate) < STALL_SPEED, f"fingers at {hand.width_rate} m/s"
            assert abs(hand.width - goal) < GRIPPER_HOLD_TOLERANCE, hand.width - goal


@property_settings(6)
@given(permille=PERMILLE, action=ACTIONS, variant=st.sampled_from(["open", "close"]))
@example(permille=0, action="cancel", variant="open")
@example(permille=300, action="cancel", variant="open")
@example(permille=300, action="preempt", variant="close")
@example(permille=1000, action="cancel", variant="open")
def test_gripper_commands_cancel_and_preempt_at_any_moment(
    arm_rig: ArmRig, permille: int, action: Action, variant: Literal["open", "close"]
) -> None:
    """A close canceled holds the width it reached; a new command preempts it (CANCELED)."""
    arm, sim = arm_rig.arm, arm_rig.arm.sim
    open_hand(arm)
    try:
        handle = arm.gripper("close")
        sim.step_to(sim.step_count + delay_steps(sim, 1.5, permille))
        before = handle.outcome
        assert_ended_as_alone(before, TaskStatus.SUCCEEDED)
        if action == "cancel":
            handle.cancel()
            assert_cancel_consistent(handle, before)
            if before is None:
                assert arm.hand.goal_width == arm.hand.width
            assert_gripper_holds(arm)
        else:
            new = arm.gripper(variant)
            assert_preempted(handle, before, TaskStatus.CANCELED)
            run_until_done(sim, new, arm.config.gripper_timeout + 0.5)
            assert new.status is TaskStatus.SUCCEEDED, new.outcome
            if variant == "open":
                assert arm.hand.width >= MAX_OPENING - 0.001
            else:
                assert arm.hand.width < MIN_GRASP_WIDTH
                assert new.feedback["grasped_object"] is None
    except BaseException:
        arm.hand.hold_current()
        advance(sim, 1.0)
        raise
