"""The core of :class:`~baobab.nav.navigator.BasicNavigator`: its node and its simulation.

:class:`NavigatorCore` owns what every Simple Commander call shares: the simulated robot and
its :class:`~baobab.nav.server.NavigationServer`, the sim clock, and advancing the simulation
in bounded slices. The tasks the navigator tracks (sent, polled, canceled, their feedback,
results and errors) are in :mod:`baobab.nav.navigator_tracking`; the task launchers in
:mod:`baobab.nav.navigator_tasks` and :mod:`baobab.nav.navigator_external`; the planning
services, costmaps and maps in :mod:`baobab.nav.navigator`.
"""

from __future__ import annotations

import dataclasses
import enum
import math
from collections.abc import Callable, Mapping
from pathlib import Path as FilePath
from typing import Any

from baobab.nav import msgs
from baobab.nav.collision_monitor import CollisionMonitor
from baobab.nav.collision_monitor_config import layered_collision_monitor, robot_footprint
from baobab.nav.collision_monitor_params import CollisionMonitorConfigError, CollisionMonitorParams
from baobab.nav.defaults import NavigatorDefaults, navigator_defaults
from baobab.nav.nav2_collision_monitor import file_monitor_block, file_monitor_error
from baobab.nav.nav2_configuration import Nav2Configuration, load_nav2_params
from baobab.nav.navigation_stack import build_navigation_stack
from baobab.nav.navigator_robot import (
    NavigatorSetupError,
    SimulatedRobot,
    build_simulated_robot,
    default_start,
    navigator_robot,
)
from baobab.nav.navigator_time import NavigatorWaits
from baobab.nav.robot_params import navigation_params
from baobab.nav.ros.rclpy.node import Node
from baobab.nav.rostime import S_TO_NS, Clock, ClockType, set_sim_time_source
from baobab.nav.server import NavigationServer
from baobab.nav.world_servers import WorldServers
from baobab.robots.catalog import RobotInfo
from baobab.sim.errors import BaobabError
from baobab.sim.viewer import RealTimePacer
from baobab.sim.world import Pose2D, World, load_world

POLL_HORIZON = 0.1
"""Sim seconds one ``isTaskComplete()`` advances at most (Nav2 spins 0.1 s per poll)."""
POLL_SLICE = 0.01
"""Sim seconds between checks whether the task ended (and between real-time pacing waits)."""


class TaskResult(enum.Enum):
    """How the last task ended (Nav2's ``TaskResult``)."""

    UNKNOWN = 0
    SUCCEEDED = 1
    CANCELED = 2
    FAILED = 3


NavigationResult = TaskResult
"""The pre-Galactic name of :class:`TaskResult` (the same class, so comparisons mix freely)."""


class NavigatorCore(Node):
    """The node, the simulation and the task of a :class:`~baobab.nav.navigator.BasicNavigator`.

    Args:
        node_name: the node's name (and its logger's).
        namespace: the node's namespace.
        world: a bundled world name, a world YAML path or a loaded ``World``.
        robot: a bundled mobile robot's name (``baobab list``), a robot file's path, or a
            registry entry; None: what :func:`~baobab.nav.defaults.navigator_defaults` says
            (``baobab nav2 --robot``), else the registry's default mobile robot.
        start: the robot's map-frame start pose; the world's default spawn when None (on a
            map without one, the map origin: :func:`~baobab.nav.navigator_robot.default_start`).
        seed: seed of the simulation's random generator.
        realtime: pace the simulation to the wall clock (for watching a run).
        params_file: a Nav2 parameter file (``nav2_params.yaml``) that configures the
            navigation stack (:mod:`baobab.nav.nav2_configuration`); its unused parameters
            are logged once as a warning.
        nav2_substitute: run the stated substitute of each plugin baobab does not have
            (``--nav2-substitute``) instead of refusing the file.
        collision_monitor: Nav2's ``collision_monitor`` parameters (a mapping with Nav2's
            names, :mod:`baobab.nav.collision_monitor_params`); they override the world's
            ``collision_monitor:`` block and then the parameter file's ``collision_monitor``
            node, parameter by parameter. With none of the three, the robot has no collision
            monitor.

    ``world``, ``robot``, ``start``, ``seed``, ``realtime``, ``params_file`` and
    ``nav2_substitute`` left at None take the values of
    :func:`~baobab.nav.defaults.navigator_defaults` (what ``baobab nav2 --world ...`` sets);
    the default start applies only with the default world. The parameter file applies on top
    of the robot's settings (:func:`~baobab.nav.robot_params.navigation_params`); without
    one, FollowWaypoints goes on past a missed waypoint (nav2_bringup's
    ``stop_on_failure: false``).

    Raises:
        Nav2ParamsError: the parameter file cannot be used, its collision monitor
            parameters included (located message).
        WorldError: the world cannot be loaded (located message).
        NavigatorSetupError: an unknown robot, a start pose that is not free, or collision
            monitor parameters that are not valid.
        RobotFileError: a robot file that cannot be used (located message).
        TypeError: an argument of the wrong type.
    """

    def __init__(
        self,
        node_name: str = "basic_navigator",
        namespace: str = "",
        *,
        world: str | FilePath | World | None = None,
        robot: str | FilePath | RobotInfo | None = None,
        start: Pose2D | None = None,
        seed: int | None = None,
        realtime: bool | None = None,
        params_file: str | FilePath | None = None,
        nav2_substitute: bool | None = None,
        collision_monitor: Mapping[str, Any] | None = None,
    ) -> None:
        defaults = navigator_defaults()
        settings = NavigatorDefaults(
            world=defaults.world if world is None or isinstance(world, World) else world,
            start=(defaults.start if world is None else None) if start is None else start,
            seed=defaults.seed if seed is None else seed,
            realtime=defaults.realtime if realtime is None else realtime,
        )
        loaded = world if isinstance(world, World) else load_world(settings.world)
        self._robot = navigator_robot(defaults.robot if robot is None else robot)
        base = dataclasses.replace(navigation_params(self._robot), waypoint_stop_on_failure=False)
        self._params = base
        self.nav2_configuration: Nav2Configuration | None = None
        """What the parameter file set (None without one)."""
        params_file = defaults.nav2_params if params_file is None else params_file
        if params_file is not None:
            substitute = defaults.nav2_substitute if nav2_substitute is None else nav2_substitute
            self.nav2_configuration = load_nav2_params(params_file, base, substitute=substitute)
            self._params = self.nav2_configuration.params
        self._monitor_parameters = collision_monitor
        self._seed = settings.seed
        self._time_offset = 0.0
        self._world = loaded
        start = settings.start or default_start(loaded, self._robot.mobile_facts.footprint)
        self._rig, self._server = self._build(loaded, start)
        super().__init__(node_name, namespace=namespace)
        self._sim_clock = Clock(clock_type=ClockType.ROS_TIME, source=self._sim_seconds)
        self._pacer = RealTimePacer() if settings.realtime else None
        self._alive = True
        self.initial_pose = msgs.PoseStamped(header=msgs.Header(frame_id="map"))
        set_sim_time_source(self._sim_seconds)
        self._waits = NavigatorWaits(self._advance, lambda: round(self._sim_seconds() * S_TO_NS))
        self._waits.register()
        warning = None if self.nav2_configuration is None else self.nav2_configuration.warning()
        if warning is not None:
            self.get_logger().warning(warning)
        self._setup()

    def _setup(self) -> None:
        """Set up what a subclass adds, at the end of construction (each calls its super's)."""

    # -- the simulation -----------------------------------------------------------------------

    def _build(self, world: World, start: Pose2D) -> tuple[SimulatedRobot, NavigationServer]:
        if self.nav2_configuration is not None:
            world = self.nav2_configuration.filtered(world)
        monitor_params = self._monitor_params(world, self._robot)
        rig = build_simulated_robot(self._robot, world, start, self._seed)
        monitor = None
        if monitor_params is not None:
            footprint = robot_footprint(self._robot)
            monitor = CollisionMonitor(rig.sim, rig.base, rig.lidar, monitor_params, footprint)
        server, self._world_servers = build_navigation_stack(
            rig.sim, rig.base, rig.lidar, world, self._params, monitor
        )
        return rig, server

    @property
    def world_servers(self) -> WorldServers:
        """The route server and GPS waypoint follower of the world, where it has them."""
        return self._world_servers

    def _monitor_params(self, world: World, robot: RobotInfo) -> CollisionMonitorParams | None:
        """The collision monitor of ``world``'s, the parameter file's and the constructor's
        parameters (in that order, the later winning parameter by parameter).

        Raises:
            NavigatorSetupError: naming the parameter that is wrong and where it was given.
            Nav2ParamsError: a mistake in the parameter file's layer (located in the file).
        """
        file = None if self.nav2_configuration is None else self.nav2_configuration.file
        layers = [world.collision_monitor, file_monitor_block(file), self._monitor_parameters]
        try:
            return layered_collision_monitor(layers, robot_footprint(robot))
        except CollisionMonitorConfigError as exc:
            if exc.layer == 1 and file is not None:
                raise file_monitor_error(file, exc) from None
            where = (f"world '{world.name}': ", "", "")[exc.layer]
            raise NavigatorSetupError(where + exc.describe()) from None

    def _sim_seconds(self) -> float:
        return self._time_offset + self._rig.sim.time

    def _live_server(self) -> NavigationServer:
        if not self._alive:
            raise BaobabError(f"navigator '{self.get_name()}' was destroyed")
        return self._server

    def _advance(
        self,
        horizon: float,
        until: Callable[[], bool] | None = None,
        *,
        changes_in_callbacks: bool = False,
    ) -> None:
        """Step the simulation ``horizon`` sim seconds (rounded up to whole physics steps),
        stopping early at the end of the first :data:`POLL_SLICE` slice after which
        ``until()`` is true.

        With ``changes_in_callbacks`` (``until`` reads what only the simulation's callbacks
        change, such as a task's outcome) and no pacing, the checks that cannot have changed
        are skipped: each batch steps to the end of the slice in which the next callback runs.
        It stops at the same step as checking every slice would (a condition that holds
        already stops at the end of the first slice, so it is checked every slice then).
        """
        self._live_server()
        sim = self._rig.sim
        start = sim.step_count
        end = start + max(math.ceil(horizon / sim.physics_dt - 1e-9), 0)
        slice_steps = max(round(POLL_SLICE / sim.physics_dt), 1)
        skip = changes_in_callbacks and until is not None and self._pacer is None and not until()
        while sim.step_count < end:
            wake = sim.step_count
            if skip:  # the next callback runs when stepping from its step, so step past it
                wake = int(min(max(sim.next_callback_step, wake), end))
            sim.step_to(min(start + ((wake - start) // slice_steps + 1) * slice_steps, end))
            if self._pacer is not None:
                self._pacer.wait(self._sim_seconds())
            if until is not None and until():
                break

    def _spin_once(self, timeout_sec: float | None) -> None:
        """``rclpy.spin_once(navigator)``: advance the sim like one completion poll."""
        horizon = POLL_HORIZON if timeout_sec is None else min(max(timeout_sec, 0.0), POLL_HORIZON)
        self._advance(horizon, self._tracked_goal_ended, changes_in_callbacks=True)

    def _tracked_goal_ended(self) -> bool:
        """Whether the goal a poll waits for has ended (the tracking layer says which)."""
        return False

    def _stamp(self) -> msgs.TimeMsg:
        return self._sim_clock.now().to_msg()

    def _stamped(self, pose: Pose2D) -> msgs.PoseStamped:
        return msgs.from_pose2d(pose, stamp=self._stamp())

    # -- node ---------------------------------------------------------------------------------

    def get_clock(self) -> Clock:
        """The navigator's ROS-time clock: simulation seconds."""
        return self._sim_clock

    def destroy_node(self) -> None:
        """Cancel the running task, stop the simulation's navigation, release the node."""
        if self._alive:
            self._alive = False
            self._server.close()
            set_sim_time_source(None)
            self._waits.unregister()
        super().destroy_node()

    def destroyNode(self) -> None:
        """Nav2's spelling of :meth:`destroy_node`."""
        self.destroy_node()

    def info(self, msg: object) -> None:
        """Log at INFO."""
        self.get_logger().info(msg)

    def warn(self, msg: object) -> None:
        """Log at WARN."""
        self.get_logger().warn(msg)

    def error(self, msg: object) -> None:
        """Log at ERROR."""
        self.get_logger().error(msg)

    def debug(self, msg: object) -> None:
        """Log at DEBUG."""
        self.get_logger().debug(msg)
