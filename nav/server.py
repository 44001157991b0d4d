"""The navigation server: Nav2's planner, controller and behaviour servers and BT navigators.

One :class:`NavigationServer` per mobile robot owns the global costmap (the world's static
geometry, lidar obstacles, inflation), the rolling 3 m x 3 m local costmap, the planner and
smoother, the Regulated Pure Pursuit controller with its goal and progress checkers, the
recovery behaviours, and at most one running task. Every task method returns a
:class:`~baobab.sim.tasks.TaskHandle` at once; the work happens inside sim callbacks:

- local costmap update 5 Hz, global costmap update 1 Hz (each takes the latest scan, Nav2's
  ``observation_persistence`` 0);
- a costmap clear (the tree's ClearEntireCostmap recoveries, ``clear_costmaps``) resets the
  obstacle layers and marks the latest scan again at once. Nav2's planner and controller wait
  after a clear until the costmap is current again (``waitForCostmap``), and its next update
  marks the latest observation again, so neither ever plans or drives on a costmap that has
  forgotten what the lidar sees; a clear forgets only what it no longer sees;
- the active task's tick at the controller rate (20 Hz; behaviours cycle at 10 Hz).

Goals while a task runs are preempted, or replace the running task, as Nav2's action servers
do (:mod:`baobab.nav.task_slot`); ``cancel()`` (or the handle's) halts the task and commands
zero velocity at once. Scans reach the costmaps as :mod:`baobab.nav.costmap_updates` says.

The server satisfies ``baobab.behaviours.ports.NavigationPort`` structurally; ``nav`` does
not import ``behaviours`` (dependencies point the other way).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from baobab.nav.assisted_teleop import AssistedTeleop
from baobab.nav.behaviors import (
    AssistedTeleopStats,
    BackUp,
    Behavior,
    BehaviorContext,
    BehaviorParams,
    DriveOnHeading,
    Spin,
    TeleopInput,
    Wait,
)
from baobab.nav.controller_server import ControllerParams, FollowPathTask, PathFollower
from baobab.nav.costmap import Costmap2D
from baobab.nav.costmap_filters import KeepoutParams, speed_filter
from baobab.nav.costmap_updates import CostmapUpdates
from baobab.nav.errors import NavigationError, SmoothPathError
from baobab.nav.footprint import collision_mask
from baobab.nav.interfaces import ActionServer, MobileBase, ScanSource, ServerTask
from baobab.nav.layered_costmap import CostmapParams
from baobab.nav.navigate import NavigateTask, NavigationMetrics, NavigatorParams
from baobab.nav.navigation_costmaps import navigation_costmaps
from baobab.nav.path import Path
from baobab.nav.planner import GlobalPlanner, PlannerParams
from baobab.nav.smoother import SimpleSmoother
from baobab.nav.task_slot import TaskSlot
from baobab.nav.through_poses import ThroughPosesPlanner
from baobab.nav.waypoints import WaypointFollower
from baobab.sim.simulation import PeriodicHandle, Simulation
from baobab.sim.tasks import TaskHandle
from baobab.sim.world import Pose2D, World


@dataclass(frozen=True)
class NavigationParams:
    """Every navigation setting: Nav2's defaults with a robot's figures
    (:func:`~baobab.nav.robot_params.navigation_params`; the default robot's when built bare)."""

    global_costmap: CostmapParams = field(default_factory=CostmapParams)
    local_costmap: CostmapParams = field(default_factory=CostmapParams)
    local_costmap_size: tuple[float, float] = (3.0, 3.0)
    local_costmap_update_hz: float = 5.0
    global_costmap_update_hz: float = 1.0
    planner: PlannerParams = field(default_factory=PlannerParams)
    smoother: SimpleSmoother = field(default_factory=SimpleSmoother)
    controller: ControllerParams = field(default_factory=ControllerParams)
    behaviors: BehaviorParams = field(default_factory=BehaviorParams)
    navigator: NavigatorParams = field(default_factory=NavigatorParams)
    waypoint_loop_rate: float = 20.0
    keepout: KeepoutParams = field(default_factory=KeepoutParams)


class NavigationServer:
    """Nav2-style navigation for one mobile base in a simulation.

    Args:
        sim: the simulation; the server registers its periodic callbacks there.
        base: the robot's base (``pose``, ``body_velocity``, ``command``, ``stop``).
        world: the world whose static geometry makes the static costmap layer.
        lidar: where scans come from (``subscribe``/``unsubscribe``); None leaves the
            obstacle layers empty.
        params: settings; Nav2's defaults for the registry's default robot when omitted
            (:func:`~baobab.nav.robot_params.navigation_params` makes a robot's).
    """

    def __init__(
        self,
        sim: Simulation,
        base: MobileBase,
        world: World,
        *,
        lidar: ScanSource | None = None,
        params: NavigationParams | None = None,
    ) -> None:
        self.params = p = params or NavigationParams()
        self.sim = sim
        self.base = base
        self.world = world
        self.global_layers, self.local_layers = navigation_costmaps(
            world,
            base.pose(),
            p.global_costmap,
            p.local_costmap,
            p.local_costmap_size,
            p.keepout,
        )
        self.speed_filter = speed_filter(world)
        self.planner = GlobalPlanner(p.planner, p.smoother)
        self.through_poses = ThroughPosesPlanner(self.planner)
        self.smoother = p.smoother
        self.follower = PathFollower(base, self.local_costmap, p.controller)
        self.teleop_input = TeleopInput()
        self.teleop_stats = AssistedTeleopStats()
        self.costmap_updates = CostmapUpdates(base, self.local_layers, self.global_layers)
        self.behavior_context = BehaviorContext(
            base,
            self.local_costmap,
            p.behaviors,
            self.teleop_input,
            clear_costmaps=self.clear_costmaps,
            teleop_stats=self.teleop_stats,
        )
        self.metrics = NavigationMetrics()
        self.tasks = TaskSlot(base, self.follower, self._clock)
        self.action_servers: dict[str, ActionServer] = {}
        """Servers of the Nav2 actions this server does not run, by action name (none yet)."""
        self.services: dict[str, Callable[..., Any]] = {}
        """Nav2 services beyond the costmap ones, by name: ``collision_monitor/toggle``
        (``enable`` -> ``(success, message)``) when a collision monitor is plugged in."""
        self._lidar = lidar
        self._last_pose = base.pose()
        if lidar is not None:
            lidar.subscribe(self.costmap_updates.on_scan)
        self._timers: list[PeriodicHandle] = [
            sim.every(1.0 / p.local_costmap_update_hz, self._update_local, name="nav local"),
            sim.every(1.0 / p.global_costmap_update_hz, self._update_global, name="nav global"),
            sim.every(
                1.0 / p.controller.controller_frequency, self._on_control, name="nav control"
            ),
        ]

    # -- tasks (the NavigationPort) -----------------------------------------------------------

    def navigate_to_pose(self, goal: Pose2D) -> TaskHandle:
        """Plan and drive to ``goal`` (map frame), replanning at 1 Hz, with recoveries."""
        return self.tasks.submit(
            "navigate_to_pose",
            lambda: self._navigate_task([goal], through_poses=False),
            lambda task: _preempt_navigation(task, [goal]),
        )

    def navigate_through_poses(self, goals: Sequence[Pose2D]) -> TaskHandle:
        """Drive through ``goals`` in order without stopping at the intermediate ones."""
        goal_list = list(goals)
        return self.tasks.submit(
            "navigate_through_poses",
            lambda: self._navigate_task(goal_list, through_poses=True),
            lambda task: _preempt_navigation(task, goal_list),
        )

    def follow_waypoints(
        self,
        waypoints: Sequence[Pose2D],
        wait_at_waypoint: float = 0.0,
        stop_on_failure: bool = True,
        *,
        number_of_loops: int = 0,
        goal_index: int = 0,
    ) -> TaskHandle:
        """Navigate to each waypoint in turn and pause ``wait_at_waypoint`` s (sim) at each.

        ``missed_waypoints`` in the feedback lists the waypoints that could not be reached;
        with ``stop_on_failure`` the first one ends the task (STOP_ON_MISSED_WAYPOINT).
        """
        points = list(waypoints)

        def make() -> ServerTask:
            return WaypointFollower(
                points,
                lambda pose: self._navigate_task([pose], through_poses=False),
                wait_at_waypoint=wait_at_waypoint,
                stop_on_failure=stop_on_failure,
                loop_rate=self.params.waypoint_loop_rate,
                number_of_loops=number_of_loops,
                goal_index=goal_index,
            )

        def preempt(task: ServerTask) -> bool:
            if not isinstance(task, WaypointFollower):
                return False
            task.preempt(
                points,
                wait_at_waypoint=wait_at_waypoint,
                stop_on_failure=stop_on_failure,
                number_of_loops=number_of_loops,
            )
            return True

        return self.tasks.submit("follow_waypoints", make, preempt)

    def follow_path(self, path: Sequence[Pose2D] | Path) -> TaskHandle:
        """Track ``path`` (map frame) with the controller alone, no planning."""
        plan = path if isinstance(path, Path) else _path_of(path)

        def preempt(task: ServerTask) -> bool:
            if not isinstance(task, FollowPathTask):
                return False
            task.preempt(plan)
            return True

        return self.tasks.submit(
            "follow_path", lambda: FollowPathTask(plan, self.follower), preempt
        )

    def spin(
        self,
        target_yaw: float = 1.57,
        time_allowance: float = 10.0,
        *,
        disable_collision_checks: bool = False,
    ) -> TaskHandle:
        """Turn in place by ``target_yaw`` rad (signed); ``time_allowance`` 0 means no limit."""
        return self.tasks.submit(
            "spin",
            lambda: _checked(
                Spin(self.behavior_context, target_yaw, time_allowance), disable_collision_checks
            ),
            None,
        )

    def back_up(
        self,
        distance: float = 0.15,
        speed: float = 0.025,
        time_allowance: float = 10.0,
        *,
        disable_collision_checks: bool = False,
    ) -> TaskHandle:
        """Reverse ``|distance|`` m at ``|speed|`` m/s (at least 0.10 m/s, Nav2's minimum)."""
        return self.tasks.submit(
            "back_up",
            lambda: _checked(
                BackUp(self.behavior_context, distance, speed, time_allowance),
                disable_collision_checks,
            ),
            None,
        )

    def drive_on_heading(
        self,
        distance: float = 0.15,
        speed: float = 0.025,
        time_allowance: float = 10.0,
        *,
        disable_collision_checks: bool = False,
    ) -> TaskHandle:
        """Drive straight ``distance`` m at ``speed`` m/s (same signs; negative is backwards).

        ``disable_collision_checks`` drives without checking the projected motion (Kilted+).
        """
        return self.tasks.submit(
            "drive_on_heading",
            lambda: _checked(
                DriveOnHeading(self.behavior_context, distance, speed, time_allowance),
                disable_collision_checks,
            ),
            None,
        )

    def wait(self, duration: float) -> TaskHandle:
        """Nav2's Wait behaviour: ``duration`` s of sim time."""
        return self.tasks.submit("wait", lambda: Wait(self.behavior_context, duration), None)

    def assisted_teleop(self, time_allowance: float = 30.0) -> TaskHandle:
        """Drive by :meth:`teleop_command` through the collision projection.

        Ends SUCCEEDED on :meth:`preempt_teleop`, FAILED (TIMEOUT) after ``time_allowance`` s
        (0: no limit), CANCELED on :meth:`cancel`. While it runs, all costmaps are cleared at
        ``params.behaviors.teleop_costmap_clear_frequency`` (2 Hz). Feedback:
        ``current_teleop_duration`` (s) and ``scaling`` (the factor applied this cycle);
        totals over all sessions are in :attr:`teleop_stats`.
        """
        return self.tasks.submit(
            "assisted_teleop",
            lambda: AssistedTeleop(self.behavior_context, time_allowance),
            None,
        )

    def teleop_command(self, linear: float, angular: float) -> None:
        """The teleop twist (m/s, rad/s) assisted teleop passes on (``cmd_vel_teleop``).

        Raises:
            ValueError: if either value is not finite.
        """
        if not (math.isfinite(linear) and math.isfinite(angular)):
            raise ValueError(f"teleop command must be finite, got ({linear}, {angular})")
        self.teleop_input.linear = linear
        self.teleop_input.angular = angular

    def preempt_teleop(self) -> None:
        """End a running assisted teleop with success (``preempt_teleop``)."""
        self.teleop_input.preempt_requested = True

    def cancel(self) -> None:
        """Cancel the running task, if any: CANCELED, robot commanded to stop at once."""
        self.tasks.cancel()

    @property
    def active_task(self) -> TaskHandle | None:
        """The handle of the running task, or None."""
        return self.tasks.handle

    @property
    def current_path(self) -> Path | None:
        """The path the controller follows now (None when no task drives)."""
        return None if self.tasks.handle is None else self.follower.path

    # -- synchronous services -----------------------------------------------------------------

    def robot_pose(self) -> Pose2D:
        """The robot's pose in the map frame."""
        return self.base.pose()

    def compute_path(self, start: Pose2D | None, goal: Pose2D) -> Path:
        """Plan on the global costmap from ``start`` (None: the robot's pose) to ``goal``.

        Raises:
            NavigationError: ComputePathToPose codes (START/GOAL_OUTSIDE_MAP, ..._OCCUPIED,
                NO_VALID_PATH, TIMEOUT).
        """
        origin = self.robot_pose() if start is None else start
        return self.planner.create_plan(origin, goal, self.global_layers.costmap)

    def compute_path_through_poses(self, start: Pose2D | None, goals: Sequence[Pose2D]) -> Path:
        """Plan from ``start`` (None: the robot) through ``goals`` in order, one leg each.

        Raises:
            NavigationError: ComputePathThroughPoses codes (3xx).
        """
        origin = self.robot_pose() if start is None else start
        return self.through_poses.plan(origin, goals, self.global_layers.costmap)

    def smooth_path(self, path: Path, *, check_for_collisions: bool = False) -> Path:
        """Nav2's Simple Smoother on the global costmap.

        Raises:
            NavigationError: SmoothPath INVALID_PATH for an empty path,
                SMOOTHED_PATH_IN_COLLISION when asked to check and a pose collides.
        """
        if len(path) == 0:
            raise NavigationError(SmoothPathError.INVALID_PATH, "the path has no poses")
        costmap = self.global_layers.costmap
        smoothed = self.smoother.smooth(path, costmap).path
        xy = smoothed.xy
        if (
            check_for_collisions
            and collision_mask(costmap, xy[:, 0], xy[:, 1], yaws=smoothed.yaws).any()
        ):
            raise NavigationError(
                SmoothPathError.SMOOTHED_PATH_IN_COLLISION, "the smoothed path collides"
            )
        return smoothed

    def clear_costmaps(self, which: str = "all") -> None:
        """Clear the obstacle layers of the ``local``, ``global`` or ``all`` costmaps, then mark
        the latest scan again: what the lidar still sees stays (see the module docstring).

        Raises:
            ValueError: for any other name.
        """
        self.costmap_updates.clear_and_remark(which)

    def clear_costmap_region(
        self, which: str, x: float, y: float, reset_distance: float, *, inside: bool
    ) -> None:
        """Clear the ``local`` or ``global`` obstacle layer in (``inside``) or outside the
        square of side ``reset_distance`` (m) centred on map point ``(x, y)``
        (:meth:`~baobab.nav.layered_costmap.LayeredCostmap.clear_region`).

        Raises:
            ValueError: ``which`` is neither ``local`` nor ``global``.
        """
        costmaps = {"local": self.local_layers, "global": self.global_layers}
        if which not in costmaps:
            raise ValueError(f"which must be 'local' or 'global', got {which!r}")
        costmaps[which].clear_region(x, y, reset_distance, inside=inside)

    def global_costmap(self) -> Costmap2D:
        """The global costmap, up to date."""
        return self.global_layers.costmap

    def local_costmap(self) -> Costmap2D:
        """The local (rolling) costmap, up to date."""
        return self.local_layers.costmap

    def close(self) -> None:
        """Cancel the running task and stop every callback and subscription."""
        self.cancel()
        for timer in self._timers:
            timer.cancel()
        if self._lidar is not None:
            self._lidar.unsubscribe(self.costmap_updates.on_scan)

    # -- internals ----------------------------------------------------------------------------

    def _navigate_task(self, goals: list[Pose2D], *, through_poses: bool) -> NavigateTask:
        return NavigateTask(
            goals,
            through_poses=through_poses,
            services=self,
            follower=self.follower,
            behaviors=self.behavior_context,
            params=self.params.navigator,
            metrics=self.metrics,
            clock=self._clock,
        )

    def _clock(self) -> float:
        return self.sim.time

    def _update_local(self, _now: float) -> None:
        self.costmap_updates.update_local()
        if self.speed_filter is not None:
            pose = self.base.pose()
            limit = self.speed_filter.update(pose.x, pose.y)
            if limit is not None:
                self.follower.set_speed_limit(limit)

    def _update_global(self, _now: float) -> None:
        self.costmap_updates.update_global()

    def _on_control(self, now: float) -> None:
        pose = self.base.pose()
        self.metrics.distance_driven += math.hypot(
            pose.x - self._last_pose.x, pose.y - self._last_pose.y
        )
        self._last_pose = pose
        self.tasks.tick(now)


def _checked(behavior: Behavior, disable_collision_checks: bool) -> Behavior:
    behavior.collision_checks = not disable_collision_checks
    return behavior


def _preempt_navigation(task: ServerTask, goals: list[Pose2D]) -> bool:
    if not isinstance(task, NavigateTask):
        return False
    task.preempt(goals)
    return True


def _path_of(poses: Sequence[Pose2D]) -> Path:
    return Path(np.array([[pose.x, pose.y, pose.yaw] for pose in poses], dtype=float))


def build_navigation(
    sim: Simulation,
    robot_base: MobileBase,
    lidar: ScanSource | None,
    world: World,
    *,
    params: NavigationParams | None = None,
) -> NavigationServer:
    """Wire a navigation server to an already-built robot (the mission runner's factory).

    Args:
        sim: the simulation the robot lives in.
        robot_base: the robot's base, e.g. a mobile robot's ``DiffDriveBase``.
        lidar: its scanner, e.g. the robot's ``Lidar``, or None.
        world: the world the simulation was built from.
        params: navigation settings (:func:`~baobab.nav.robot_params.navigation_params`;
            the default robot's when omitted).
    """
    return NavigationServer(sim, robot_base, world, lidar=lidar, params=params)
