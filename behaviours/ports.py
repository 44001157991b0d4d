"""The ports a mission tree talks to, and the ``Capabilities`` bundle the runner fills.

A port is the narrow, goal-style face of a capability server: every long-running request
returns a :class:`~baobab.sim.tasks.TaskHandle` at once and the server advances it inside the
simulation. Behaviour-tree leaves only ever see these Protocols, so the compiler can be tested
with hand-driven fakes and the runner can plug in the real servers.

Units: metres, radians, seconds (sim time); quaternions x, y, z, w.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

from baobab.robots.catalog import (
    ARM,
    BASE_CONTROLLERS,
    COLLISION_MONITOR,
    NAVIGATION,
    ROS_NODES,
    TELEOP,
)
from baobab.sim.errors import BaobabError
from baobab.sim.tasks import TaskHandle
from baobab.sim.world import Pose2D

if TYPE_CHECKING:
    from baobab.sim.geodesy import GeoWaypoint

__all__ = [
    "ARM",
    "BASE_CONTROLLERS",
    "COLLISION_MONITOR",
    "NAVIGATION",
    "PORT_CAPABILITIES",
    "ROS_NODES",
    "TELEOP",
    "ArmPort",
    "BaseControllerPort",
    "Capabilities",
    "CapabilityError",
    "Clock",
    "CollisionMonitorPort",
    "NavigationPort",
    "RosNodesPort",
]

PORT_CAPABILITIES = (NAVIGATION, BASE_CONTROLLERS, ARM, ROS_NODES, COLLISION_MONITOR)
"""Capabilities that behaviour-tree leaves use through a port (teleop is driven by events)."""


class CapabilityError(BaobabError):
    """A leaf needs a capability that the runner did not provide."""


class NavigationPort(Protocol):
    """Nav2-style navigation server: tasks in the ``map`` frame."""

    def navigate_to_pose(self, goal: Pose2D) -> TaskHandle:
        """Plan and drive to ``goal``."""
        ...

    def navigate_through_poses(self, goals: Sequence[Pose2D]) -> TaskHandle:
        """Drive through ``goals`` in order without stopping at the intermediate ones."""
        ...

    def follow_waypoints(
        self,
        waypoints: Sequence[Pose2D],
        wait_at_waypoint: float | None,
        stop_on_failure: bool | None,
    ) -> TaskHandle:
        """Navigate to each waypoint in turn, pausing ``wait_at_waypoint`` s at each; None takes
        the navigation stack's setting (its Nav2 parameter file's)."""
        ...

    def follow_path(self, path: Sequence[Pose2D]) -> TaskHandle:
        """Track ``path`` with the local controller (no global planning)."""
        ...

    def spin(self, target_yaw: float, time_allowance: float) -> TaskHandle:
        """Turn in place by ``target_yaw`` rad (signed, relative) within ``time_allowance`` s."""
        ...

    def back_up(self, distance: float, speed: float, time_allowance: float) -> TaskHandle:
        """Reverse ``distance`` m at ``speed`` m/s (both positive)."""
        ...

    def drive_on_heading(self, distance: float, speed: float, time_allowance: float) -> TaskHandle:
        """Drive straight ahead ``distance`` m at ``speed`` m/s."""
        ...

    def wait(self, duration: float) -> TaskHandle:
        """Nav2's Wait behaviour: stand still for ``duration`` s."""
        ...

    def assisted_teleop(self, time_allowance: float) -> TaskHandle:
        """Pass teleop commands through the collision projection for ``time_allowance`` s."""
        ...

    def dock_robot(self, dock_id: str, dock_pose: Pose2D | None, staging: bool) -> TaskHandle:
        """Dock at the dock ``dock_id`` (or at ``dock_pose`` when the id is empty), navigating
        to its staging pose first when ``staging``."""
        ...

    def undock_robot(self) -> TaskHandle:
        """Back out of the dock the robot is docked at."""
        ...

    def follow_object(self, topic: str, frame: str, max_duration: float) -> TaskHandle:
        """Keep Nav2's desired distance from the moving object whose pose is on ``topic`` (or
        TF ``frame``) for ``max_duration`` s (0: until halted)."""
        ...

    def follow_route(self, start: int | Pose2D | None, goal: int | Pose2D) -> TaskHandle:
        """Drive the world's route graph from ``start`` (a node id, a pose, None: the robot)
        to ``goal`` (a node id or a pose), rerouting round blocked edges."""
        ...

    def follow_gps_waypoints(self, waypoints: Sequence[GeoWaypoint]) -> TaskHandle:
        """Navigate to each geographic waypoint in turn, through the world's datum."""
        ...

    def clear_costmaps(self, which: str) -> None:
        """Clear the ``local``, ``global`` or ``all`` costmaps (synchronous)."""
        ...

    def robot_pose(self) -> Pose2D:
        """The robot's current pose in the map frame."""
        ...


class BaseControllerPort(Protocol):
    """The tutorial controllers that drive the base directly, without planning."""

    def go_to_goal(self, goal: Pose2D) -> TaskHandle:
        """Proportional go-to-goal controller towards ``goal``."""
        ...

    def bug2(self, goal: Pose2D) -> TaskHandle:
        """Bug2: follow the M-line to ``goal``, walls on the left when blocked."""
        ...


class ArmPort(Protocol):
    """Cartesian arm server: tool centre point (TCP) targets in the world frame."""

    def move_to(
        self, position: Sequence[float], orientation_xyzw: Sequence[float], duration: float
    ) -> TaskHandle:
        """Move the TCP to ``position`` (m) and ``orientation_xyzw`` in ``duration`` s."""
        ...

    def gripper(self, command: str) -> TaskHandle:
        """``"open"`` or ``"close"`` the gripper."""
        ...

    def object_position(self, name: str) -> tuple[float, float, float]:
        """World position (m) of the named free object, e.g. ``"cube"``."""
        ...

    def tcp_pose(self) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
        """Current TCP position (m) and orientation (x, y, z, w)."""
        ...


Clock = Callable[[], float]
"""Returns the simulation time in seconds."""


class RosNodesPort(Protocol):
    """rclpy node files run on the mission's simulation, its robot on ROS topics."""

    def start_node(self, path: Path, argv: list[str]) -> TaskHandle:
        """Run the node file at ``path`` with ``argv`` (its ``--ros-args``) until it ends or
        the task is canceled; the task fails when the node code raises."""
        ...


class CollisionMonitorPort(Protocol):
    """Nav2's collision monitor on the base's commands."""

    def toggle(self, enable: bool) -> tuple[bool, str]:
        """Nav2's ``collision_monitor/toggle``: zones on or off; ``(success, message)``."""
        ...


@dataclass
class Capabilities:
    """What a compiled tree may use: the sim clock and one port per capability server.

    The runner fills the ports its robot has and leaves the others ``None``.
    """

    clock: Clock
    navigation: NavigationPort | None = None
    base_controllers: BaseControllerPort | None = None
    arm: ArmPort | None = None
    ros_nodes: RosNodesPort | None = None
    collision_monitor: CollisionMonitorPort | None = None

    def provides(self, capability: str) -> bool:
        """True when the port for ``capability`` (e.g. ``"navigation"``) is present."""
        if capability not in PORT_CAPABILITIES:
            return False
        return getattr(self, capability) is not None

    def navigation_port(self) -> NavigationPort:
        """The navigation port, or :class:`CapabilityError` when the run has none."""
        if self.navigation is None:
            raise CapabilityError("this run provides no 'navigation' capability")
        return self.navigation

    def base_controller_port(self) -> BaseControllerPort:
        """The base-controller port, or :class:`CapabilityError` when the run has none."""
        if self.base_controllers is None:
            raise CapabilityError("this run provides no 'base_controllers' capability")
        return self.base_controllers

    def arm_port(self) -> ArmPort:
        """The arm port, or :class:`CapabilityError` when the run has none."""
        if self.arm is None:
            raise CapabilityError("this run provides no 'arm' capability")
        return self.arm

    def ros_nodes_port(self) -> RosNodesPort:
        """The ROS nodes port, or :class:`CapabilityError` when the run has none."""
        if self.ros_nodes is None:
            raise CapabilityError("this run provides no 'ros_nodes' capability")
        return self.ros_nodes

    def collision_monitor_port(self) -> CollisionMonitorPort:
        """The collision monitor port, or :class:`CapabilityError` when the run has none."""
        if self.collision_monitor is None:
            raise CapabilityError("this run provides no 'collision_monitor' capability")
        return self.collision_monitor
