"""Build the simulation and the capability servers a mission's robot needs: a *rig*.

A rig bundles the :class:`~baobab.sim.simulation.Simulation`, the
:class:`~baobab.behaviours.ports.Capabilities` the compiled tree talks to, the run's metrics,
where events put obstacles and teleop input, and what the trace and plot read from the robot.

Imports are lazy on purpose: a mobile run never imports an arm's package (Pinocchio is slow to
load), and the navigation stack (numba kernels) is imported only when the tree uses the
``navigation`` capability. The robot is whatever the mission's registry entry (or robot file)
describes: a mobile one is built from its facts, a fixed one by the runtime module its entry
names.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING, Any, Protocol, cast

import numpy as np

from baobab.behaviours.ports import NAVIGATION, ROS_NODES, Capabilities, NavigationPort
from baobab.behaviours.poses import Pose
from baobab.missions.language.loader import Mission
from baobab.missions.run.arm_probes import ArmProbe, TrackingProbe
from baobab.missions.run.clear_counting_port import ClearCountingPort
from baobab.missions.run.event_targets import ObstacleSlots, TeleopChannel
from baobab.missions.run.metrics import (
    MetricRegistry,
    register_collision_monitor_metrics,
    register_teleop_metrics,
)
from baobab.missions.run.mobile_probe import MobileProbe
from baobab.missions.run.plot_data import ArmPlot, CostmapImage, MobilePlot, PlotData
from baobab.missions.run.zone_probe import ZoneProbe
from baobab.robots.catalog import RobotInfo
from baobab.robots.diff_drive.controller_tasks import BaseControllerServer
from baobab.robots.diff_drive.robot import MobileRobot
from baobab.sim.errors import BaobabError
from baobab.sim.moving_object_motion import start_moving_objects
from baobab.sim.simulation import Simulation
from baobab.sim.world import Pose2D, World

if TYPE_CHECKING:
    from baobab.nav.collision_monitor import CollisionMonitor, MonitorChange
    from baobab.nav.ros.mission_nodes import MissionNodes
    from baobab.nav.server import NavigationServer
    from baobab.nav.world_servers import WorldServers
    from baobab.robots.diff_drive.base import DiffDriveBase

ARM_CONTACT_NAME_PERIOD = 0.01
"""How often (s) the arm's contacts are looked at for the names of what it touched."""

PATH_SAMPLE_PERIOD = 0.5
"""How often the navigation server's current path is looked at for the plot (s)."""
MAX_PLOTTED_PATHS = 400


class Rig(Protocol):
    """A robot ready to run a mission (see the module docstring)."""

    sim: Simulation
    capabilities: Capabilities
    metrics: MetricRegistry
    obstacles: ObstacleSlots | None
    teleop: TeleopChannel | None
    ros: MissionNodes | None
    """The ROS runtime of a mission that runs node files or publishes messages, else None."""

    def state(self) -> dict[str, Any]:
        """The robot's state for the trace's ``pose`` records (sim-determined numbers)."""
        ...

    def stop(self) -> None:
        """Bring the robot to rest (after the tree was halted)."""
        ...

    def plot_data(self, title: str) -> PlotData:
        """What the run's plot shows."""
        ...

    def sim_records(self) -> list[tuple[float, str, dict[str, Any]]]:
        """What happened inside the simulation since the last call, for the trace: (sim time
        (s), record type, fields), in time order."""
        ...


def uses_capability(mission: Mission, capability: str) -> bool:
    """True when some node of the mission's tree needs ``capability``."""
    return any(node.behaviour.capability == capability for node in mission.tree.walk())


def uses_ros(mission: Mission) -> bool:
    """True when the mission runs node files or publishes messages on ROS topics."""
    from baobab.missions.language.models import PublishEvent

    publishes = any(isinstance(event, PublishEvent) for event in mission.events)
    return publishes or uses_capability(mission, ROS_NODES)


def build_rig(mission: Mission, seed: int) -> Rig:
    """The rig for ``mission``'s robot, seeded with ``seed``.

    Raises:
        BaobabError: the world or the robot cannot be built.
    """
    if mission.robot.mobile:
        return MobileRig(mission, seed)
    return ArmRig(mission, seed)


def mission_goals(mission: Mission) -> list[tuple[str, Pose]]:
    """Every goal pose written in the tree (node parameters holding poses), in tree order."""
    goals: list[tuple[str, Pose]] = []
    for node in mission.tree.walk():
        for key in type(node.params).model_fields:
            value = getattr(node.params, key)
            poses = value if isinstance(value, list) else [value]
            for pose in poses:
                if isinstance(pose, Pose):
                    goals.append((pose.location or f"({pose.x:.1f}, {pose.y:.1f})", pose))
    return goals


def build_navigation(
    sim: Simulation,
    robot: MobileRobot,
    info: RobotInfo,
    world: World,
    teleop: TeleopChannel,
    mission: Mission | None = None,
    monitor: CollisionMonitor | None = None,
) -> tuple[NavigationServer, WorldServers]:
    """The navigation server of the mobile robot ``info`` describes, with its settings (and the
    ``mission``'s Nav2 parameter file's on top, with or without substitutes), fed by teleop
    events, driving through the collision monitor when there is one, and the servers of the
    world's route graph and datum (imported only now)."""
    from baobab.nav.navigation_stack import build_navigation_stack
    from baobab.nav.robot_params import navigation_params

    params = navigation_params(info)
    if mission is not None and mission.nav2_params is not None:
        from baobab.nav.nav2_configuration import configure_navigation

        substitute = mission.nav2_substitute
        params = configure_navigation(mission.nav2_params, params, substitute=substitute).params
    server, world_servers = build_navigation_stack(
        sim, robot.base, robot.lidar, world, params, monitor
    )
    teleop.subscribe(lambda twist: server.teleop_command(*(twist or (0.0, 0.0))))
    return server, world_servers


def _collision_monitor(
    mission: Mission, sim: Simulation, robot: MobileRobot
) -> CollisionMonitor | None:
    """The robot's collision monitor when the mission configures one (imported only then)."""
    if mission.collision_monitor is None:
        return None
    from baobab.nav.collision_monitor import CollisionMonitor
    from baobab.nav.collision_monitor_config import robot_footprint

    footprint = robot_footprint(mission.robot)
    return CollisionMonitor(sim, robot.base, robot.lidar, mission.collision_monitor, footprint)


def monitor_record(change: MonitorChange) -> dict[str, Any]:
    """A monitor state change as trace and recording fields (Nav2's names)."""
    state = change.state
    return {
        "action_type": state.action_type.name,
        "polygon_name": state.polygon_name,
        "enabled": state.enabled,
    }


class MobileRig:
    """A mobile robot in a 2D world with base controllers and, when needed, navigation."""

    def __init__(self, mission: Mission, seed: int) -> None:
        world = mission.world
        if world is None:
            raise BaobabError(f"mission '{mission.name}' has no world for a mobile robot")
        self.world = world
        self.mission = mission
        self.info = mission.robot
        self.sim, self.robot = mission.robot.build_sim(
            world, mission.start, seed=seed, lidar_noise_std=mission.noise.lidar_std
        )
        self.moving_objects = start_moving_objects(self.sim, world)
        self.monitor = _collision_monitor(mission, self.sim, self.robot)
        drive = self.robot.base if self.monitor is None else self.monitor.base
        # the monitor's base takes the commands the drive takes (MobileBase): every driver
        # below commands the base through it
        self.controllers = BaseControllerServer(
            self.sim, cast("DiffDriveBase", drive), self.robot.lidar
        )
        self._monitor_records = 0
        self.teleop: TeleopChannel | None = TeleopChannel()
        self.obstacles: ObstacleSlots | None = ObstacleSlots(self.sim)
        self.navigation: NavigationServer | None = None
        self.world_servers: WorldServers | None = None
        self.planned_paths: list[np.ndarray] = []
        self._sampled_path: object = None
        self.clear_counter: ClearCountingPort | None = None
        port: NavigationPort | None = None
        sim = self.sim
        if uses_capability(mission, NAVIGATION):
            self.navigation, self.world_servers = build_navigation(
                sim, self.robot, self.info, world, self.teleop, mission, self.monitor
            )
            self.clear_counter = ClearCountingPort(self.navigation)
            port = self.clear_counter
            sim.every(PATH_SAMPLE_PERIOD, self._sample_path, name="plot paths")
        self.ros: MissionNodes | None = None
        if uses_ros(mission):
            from baobab.nav.navigator_robot import simulated_robot
            from baobab.nav.ros.mission_nodes import MissionNodes

            robot_on_topics = replace(simulated_robot(self.info, self.robot), base=drive)
            self.ros = MissionNodes(sim, mobile=robot_on_topics)
        self.capabilities = Capabilities(
            clock=lambda: sim.time,
            navigation=port,
            base_controllers=self.controllers,
            ros_nodes=self.ros,
            collision_monitor=self.monitor,
        )
        spawn_names = set(world.spawns) - set(world.locations)
        locations = {
            name: (pose.x, pose.y)
            for name, pose in mission.locations.items()
            if pose.planar and name not in spawn_names
        }
        self.locations = locations
        self.probe = MobileProbe(sim, self.robot.base, locations)
        self.zones = ZoneProbe(
            sim, self.robot.base, world, mission.robot.footprint_radius, self._top_speed()
        )
        self.metrics = self._register_metrics()

    def _register_metrics(self) -> MetricRegistry:
        """The run's metrics (``metric_names.MOBILE_METRICS``), read from this rig."""
        sim = self.sim
        metrics = MetricRegistry()
        metrics.add("sim_time", lambda: sim.time, unit="s", description="run length")
        self.probe.register(metrics)
        self.zones.register(metrics)
        metrics.add(
            "number_of_recoveries",
            self._recoveries,
            description="recovery actions started by the navigation server",
        )
        metrics.add(
            "planned_path_length",
            self._planned_path_length,
            unit="m",
            description="sum of each navigation goal's first plan; null without one",
        )
        metrics.add(
            "costmap_clears",
            lambda: 0 if self.clear_counter is None else self.clear_counter.clears,
            description="costmap clearings by the mission's tree (not Nav2's recoveries)",
        )
        metrics.add(
            "replans",
            lambda: 0 if self.navigation is None else self.navigation.metrics.replans,
            description="paths planned after a goal's first",
        )
        reroutes = "routes planned again round blocked route graph edges"
        metrics.add("route_reroutes", self._reroutes, description=reroutes)
        register_teleop_metrics(
            metrics, lambda: None if self.navigation is None else self.navigation.teleop_stats
        )
        register_collision_monitor_metrics(metrics, lambda: self.monitor)
        return metrics

    def _reroutes(self) -> int:
        routes = None if self.world_servers is None else self.world_servers.routes
        return 0 if routes is None else routes.reroutes

    def _top_speed(self) -> float:
        """The speed (m/s) a speed limit in percent is a part of: the controller's
        ``desired_linear_vel``, or the robot's top speed without navigation."""
        if self.navigation is not None:
            return self.navigation.follower.controller.params.desired_linear_vel
        return self.mission.robot.max_linear_speed

    def _recoveries(self) -> int:
        return 0 if self.navigation is None else self.navigation.metrics.number_of_recoveries

    def _planned_path_length(self) -> float | None:
        if self.navigation is None or self.navigation.metrics.plans == 0:
            return None
        return self.navigation.metrics.planned_path_length

    def _sample_path(self, _now: float) -> None:
        path = None if self.navigation is None else self.navigation.current_path
        if path is None or len(self.planned_paths) >= MAX_PLOTTED_PATHS:
            return
        if path is self._sampled_path:  # a Path never changes: the same one needs no comparison
            return
        self._sampled_path = path
        xy = np.asarray(path.xy, dtype=float)
        last = self.planned_paths[-1] if self.planned_paths else None
        if last is None or last.shape != xy.shape or not np.array_equal(last, xy):
            self.planned_paths.append(xy.copy())

    def state(self) -> dict[str, Any]:
        """Ground-truth pose (m, rad) and body velocity (m/s, rad/s)."""
        x, y, yaw, linear, angular = self.robot.base.ground_truth()
        return {"x": x, "y": y, "yaw": yaw, "v": linear, "w": angular}

    def stop(self) -> None:
        """Command zero velocity."""
        self.robot.base.stop()

    def sim_records(self) -> list[tuple[float, str, dict[str, Any]]]:
        """The collision monitor's state changes since the last call."""
        if self.monitor is None:
            return []
        changes = self.monitor.changes[self._monitor_records :]
        self._monitor_records += len(changes)
        return [(change.time, "collision_monitor", monitor_record(change)) for change in changes]

    def plot_data(self, title: str) -> MobilePlot:
        """The map-view plot of this run."""
        probe = self.probe
        bug2 = self.controllers.bug2_controller
        clearance_at = probe.min_clearance_at
        plot = MobilePlot(
            title=title,
            world=self.world,
            times=probe.times,
            xs=probe.xs,
            ys=probe.ys,
            locations=dict(self.locations),
            goals=[(label, (pose.x, pose.y)) for label, pose in mission_goals(self.mission)],
            obstacles=list(self.obstacles.placed.values()) if self.obstacles else [],
            hit_points=list(bug2.hit_points) if bug2 else [],
            leave_points=list(bug2.leave_points) if bug2 else [],
            min_clearance_at=None if clearance_at is None else clearance_at[1:],
            footprints=[self._footprint_at(*probe.start), self._footprint_at(*self._pose())],
            zones=self.zones.zone_images(),
        )
        self._navigation_layers(plot)
        return plot

    def _pose(self) -> tuple[float, float, float]:
        pose = self.robot.base.pose()
        return pose.x, pose.y, pose.yaw

    def _footprint_at(self, x: float, y: float, yaw: float) -> list[tuple[float, float]]:
        """The footprint the navigation stack uses (padded), map frame (m), at a pose."""
        return self.info.tuning.footprint.at(Pose2D(x=x, y=y, yaw=yaw))

    def _navigation_layers(self, plot: MobilePlot) -> None:
        if self.navigation is None:
            return
        costmap = self.navigation.global_costmap()
        plot.costmap = CostmapImage(costmap.data.copy(), costmap.origin, costmap.resolution)
        plot.planned_paths = list(self.planned_paths)


class ArmRig:
    """A fixed arm in its scene with its server, from the runtime module its registry entry
    names (imported only now: an arm's kinematics library loads slowly)."""

    obstacles: ObstacleSlots | None = None
    teleop: TeleopChannel | None = None

    def __init__(self, mission: Mission, seed: int) -> None:
        self.runtime = runtime = mission.robot.arm_runtime()
        self.mission = mission
        self.sim, self.server = runtime.build(seed)
        self.port = runtime.arm_port(self.sim, self.server)
        sim = self.sim
        self.ros: MissionNodes | None = None
        if uses_ros(mission):
            from baobab.nav.ros.mission_nodes import MissionNodes

            self.ros = MissionNodes(sim, arm=runtime.simulated_arm(sim, self.server))
        self.capabilities = Capabilities(clock=lambda: sim.time, arm=self.port, ros_nodes=self.ros)
        self.objects = list(mission.robot.scene_objects)
        self.probe = ArmProbe(
            sim,
            lambda: self.server.tcp_pose().position,
            self.objects,
            robot_prefix=runtime.PREFIX,
            # Counted at every step by the arm's compiled loop; Python samples the contacts
            # only for the names of what was touched.
            contact_period=ARM_CONTACT_NAME_PERIOD,
            contact_count=lambda: self.server.contact_steps,
        )
        self.place_target = tuple(float(v) for v in runtime.place_target(sim))
        self.metrics = MetricRegistry()
        self.metrics.add("sim_time", lambda: sim.time, unit="s", description="run length")
        self.probe.register(self.metrics, self.place_target)
        self.tracking = TrackingProbe(sim, self._tcp_and_setpoint)
        self.tracking.register(self.metrics)

    def _tcp_and_setpoint(self) -> tuple[np.ndarray, np.ndarray]:
        """The tool and the impedance controller's set-point (m, world frame)."""
        server = self.server
        return np.asarray(server.tcp_pose().position), np.asarray(server.setpoint_position())

    def state(self) -> dict[str, Any]:
        """Tool pose (m, quaternion x, y, z, w), hand opening (m) and object positions (m)."""
        pose = self.server.tcp_pose()
        state: dict[str, Any] = {
            "tcp": list(pose.position),
            "quat": list(pose.quaternion),
            "gripper": float(self.server.hand.width),
        }
        for name in self.objects:
            state[name] = self.probe.position(name)
        return state

    def stop(self) -> None:
        """Hold the tool where it is."""
        self.server.hold()

    def sim_records(self) -> list[tuple[float, str, dict[str, Any]]]:
        """None: the arm has nothing beyond its state to trace."""
        return []

    def plot_data(self, title: str) -> ArmPlot:
        """The 3D tool-path plot of this run."""
        targets = [
            (label, pose.position)
            for label, pose in mission_goals(self.mission)
            if not pose.planar and pose.location
        ]
        x, y, z = self.place_target
        if all(math.dist(position, (x, y, z)) > 0.01 for _, position in targets):
            targets.append(("place target", (x, y, z)))
        tracking = self.tracking
        return ArmPlot(
            title=title,
            tcp_path=self.probe.tcp_path,
            object_paths=dict(self.probe.object_paths),
            targets=targets,
            tracking_times=tracking.times,
            tracking_tcp=tracking.tcp,
            setpoint_path=tracking.setpoint,
            tracking_errors=tracking.errors,
        )
