"""The navigation port a mission's tree drives: the navigation server, counting the costmap
clears the tree asks for (the ``costmap_clears`` metric; Nav2's own recoveries are apart)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from baobab.sim.tasks import TaskHandle
from baobab.sim.world import Pose2D

if TYPE_CHECKING:
    from baobab.nav.server import NavigationServer
    from baobab.sim.geodesy import GeoWaypoint


class ClearCountingPort:
    """The navigation server as the tree's :class:`NavigationPort`, counting its clearings.

    ``clear_costmaps`` is counted on its way through, so the ``costmap_clears`` metric tells
    how often the mission's ``clear_costmaps`` and ``clear_costmaps_when_stuck`` nodes cleared
    (Nav2's own recoveries count as ``number_of_recoveries``); every other request goes to the
    server as it is.
    """

    def __init__(self, server: NavigationServer) -> None:
        self.server = server
        self.clears = 0

    def clear_costmaps(self, which: str = "all") -> None:
        """Count, then clear the ``local``, ``global`` or ``all`` costmaps."""
        self.clears += 1
        self.server.clear_costmaps(which)

    def navigate_to_pose(self, goal: Pose2D) -> TaskHandle:
        """The server's NavigateToPose."""
        return self.server.navigate_to_pose(goal)

    def navigate_through_poses(self, goals: Sequence[Pose2D]) -> TaskHandle:
        """The server's NavigateThroughPoses."""
        return self.server.navigate_through_poses(goals)

    def follow_waypoints(
        self,
        waypoints: Sequence[Pose2D],
        wait_at_waypoint: float | None,
        stop_on_failure: bool | None,
    ) -> TaskHandle:
        """The server's FollowWaypoints."""
        return self.server.follow_waypoints(waypoints, wait_at_waypoint, stop_on_failure)

    def follow_path(self, path: Sequence[Pose2D]) -> TaskHandle:
        """The server's FollowPath."""
        return self.server.follow_path(path)

    def spin(self, target_yaw: float, time_allowance: float) -> TaskHandle:
        """The server's Spin."""
        return self.server.spin(target_yaw, time_allowance)

    def back_up(self, distance: float, speed: float, time_allowance: float) -> TaskHandle:
        """The server's BackUp."""
        return self.server.back_up(distance, speed, time_allowance)

    def drive_on_heading(self, distance: float, speed: float, time_allowance: float) -> TaskHandle:
        """The server's DriveOnHeading."""
        return self.server.drive_on_heading(distance, speed, time_allowance)

    def wait(self, duration: float) -> TaskHandle:
        """The server's Wait."""
        return self.server.wait(duration)

    def assisted_teleop(self, time_allowance: float) -> TaskHandle:
        """The server's AssistedTeleop."""
        return self.server.assisted_teleop(time_allowance)

    def dock_robot(self, dock_id: str, dock_pose: Pose2D | None, staging: bool) -> TaskHandle:
        """The docking server's DockRobot."""
        return self.server.dock_robot(dock_id, dock_pose, staging)

    def undock_robot(self) -> TaskHandle:
        """The docking server's UndockRobot."""
        return self.server.undock_robot()

    def follow_object(self, topic: str, frame: str, max_duration: float) -> TaskHandle:
        """The following server's FollowObject."""
        return self.server.follow_object(topic, frame, max_duration)

    def follow_route(self, start: int | Pose2D | None, goal: int | Pose2D) -> TaskHandle:
        """The server's route driving."""
        return self.server.follow_route(start, goal)

    def follow_gps_waypoints(self, waypoints: Sequence[GeoWaypoint]) -> TaskHandle:
        """The server's FollowGPSWaypoints."""
        return self.server.follow_gps_waypoints(waypoints)

    def robot_pose(self) -> Pose2D:
        """The robot's map-frame pose."""
        return self.server.robot_pose()
