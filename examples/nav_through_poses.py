#! /usr/bin/env python3
"""Drive down a farm lane and come back up the next one without stopping (Nav2 Simple Commander).

Run it on the farm: ``baobab nav2 examples/nav_through_poses.py --world farm``. The robot
starts at the west end of the southern lane, follows it east, crosses the headland between
the crop rows' ends and the fence, and returns west along the second lane.
"""

import rclpy
from geometry_msgs.msg import PoseStamped
from nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from rclpy.duration import Duration


def lane_pose(navigator, x, y, z, w):
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
        lane_pose(navigator, -4.0, -4.2, 0.0, 1.0),  # along lane 1, heading east
        lane_pose(navigator, -7.0, -3.2, 0.707, 0.707),  # the west headland, heading north
        lane_pose(navigator, -5.0, -2.2, 0.0, 1.0),  # into lane 2, heading east
    ]

    navigator.goThroughPoses(goal_poses)

    i = 0
    while not navigator.isTaskComplete():
        i = i + 1
        feedback = navigator.getFeedback()
        if feedback and i % 10 == 0:
            print(
                f"Distance remaining: {feedback.distance_remaining:.2f} m, "
                f"poses remaining: {feedback.number_of_poses_remaining}."
            )

            # A navigation timeout, to show cancellation.
            if Duration.from_msg(feedback.navigation_time) > Duration(seconds=180.0):
                navigator.cancelTask()

    result = navigator.getResult()
    if result == TaskResult.SUCCEEDED:
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
