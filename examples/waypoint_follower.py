#! /usr/bin/env python3
"""Serve two cafe tables and come back to the kitchen door (Nav2 Simple Commander).

Run it in the cafe: ``baobab nav2 examples/waypoint_follower.py --world cafe``. The robot
stops at each waypoint in turn; a waypoint it cannot reach is skipped and reported, as the
waypoint follower of nav2_bringup does. Timing uses the node's clock, as Nav2's own waypoint
example does, which under baobab reads simulation time.
"""

import rclpy
from geometry_msgs.msg import PoseStamped
from nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from rclpy.duration import Duration


def serving_pose(navigator, x, y, z, w):
    """A goal pose in the map frame at (x, y) with the orientation quaternion (0, 0, z, w)."""
    pose = PoseStamped()
    pose.header.frame_id = "map"
    pose.header.stamp = navigator.get_clock().now().to_msg()
    pose.pose.position.x = x
    pose.pose.position.y = y
    pose.pose.position.z = 0.0
    pose.pose.orientation.x = 0.0
    pose.pose.orientation.y = 0.0
    pose.pose.orientation.z = z
    pose.pose.orientation.w = w
    return pose


def main():
    rclpy.init()

    navigator = BasicNavigator()
    navigator.waitUntilNav2Active()

    goal_poses = [
        serving_pose(navigator, -0.96, -0.92, 1.0, 0.0),  # table 1, facing west
        serving_pose(navigator, -2.45, -3.55, 1.0, 0.0),  # table 5, facing west
        serving_pose(navigator, 0.9, 2.8, 0.707, 0.707),  # the kitchen door, facing north
    ]

    nav_start = navigator.get_clock().now()
    navigator.followWaypoints(goal_poses)

    i = 0
    while not navigator.isTaskComplete():
        i = i + 1
        feedback = navigator.getFeedback()
        if feedback and i % 10 == 0:
            print(
                "Executing current waypoint: "
                + str(feedback.current_waypoint + 1)
                + "/"
                + str(len(goal_poses))
            )
            now = navigator.get_clock().now()

            # A timeout, to show cancellation.
            if now - nav_start > Duration(seconds=300.0):
                navigator.cancelTask()

    result = navigator.getResult()
    if result == TaskResult.SUCCEEDED:
        missed = navigator.result_future.result().result.missed_waypoints
        if missed:
            print("Missed waypoints: " + ", ".join(str(m.waypoint_index + 1) for m in missed))
        print("Goal succeeded!")
    elif result == TaskResult.CANCELED:
        print("Goal was canceled!")
    elif result == TaskResult.FAILED:
        (error_code, error_msg) = navigator.getTaskError()
        print(f"Goal failed! {error_code}: {error_msg}")
    else:
        print("Goal has an invalid return status!")

    navigator.lifecycleShutdown()
    exit(0)


if __name__ == "__main__":
    main()
