#! /usr/bin/env python3
"""Plan a path, smooth it and follow it with the controller alone (Nav2 Simple Commander).

Run it in the cafe: ``baobab nav2 examples/follow_path.py --world cafe``. The planner finds a
path from the robot to table 2, the smoother rounds its corners, and the controller follows it
without the navigator's replanning or recoveries; the controller's tracking feedback says how
far the robot is from the path's end and how well it keeps to the path.
"""

import rclpy
from geometry_msgs.msg import PoseStamped
from nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from nav2_simple_commander.utils import euler_to_quaternion


def map_pose(navigator, x, y, yaw):
    """A pose in the map frame at (x, y) facing ``yaw`` (rad)."""
    pose = PoseStamped()
    pose.header.frame_id = "map"
    pose.header.stamp = navigator.get_clock().now().to_msg()
    pose.pose.position.x = x
    pose.pose.position.y = y
    pose.pose.orientation = euler_to_quaternion(yaw=yaw)
    return pose


def main():
    rclpy.init()

    navigator = BasicNavigator()

    initial_pose = map_pose(navigator, 0.0, 0.0, 0.0)
    navigator.setInitialPose(initial_pose)
    navigator.waitUntilNav2Active()

    goal_pose = map_pose(navigator, 1.16, -4.23, -1.5708)  # table 2, facing south

    # The start is only used with use_start=True; by default the planner starts at the robot.
    path = navigator.getPath(initial_pose, goal_pose)
    if path is None:
        (error_code, error_msg) = navigator.getTaskError()
        print(f"Planning failed! {error_code}: {error_msg}")
        exit(1)
    smoothed_path = navigator.smoothPath(path)
    print(f"Path of {len(path.poses)} poses, smoothed to {len(smoothed_path.poses)}.")

    task = navigator.followPath(smoothed_path)

    i = 0
    while not navigator.isTaskComplete(task=task):
        i += 1
        feedback = navigator.getFeedback(task=task)
        if feedback and i % 10 == 0:
            tracking = feedback.tracking_feedback
            print(
                f"Distance to goal: {tracking.distance_to_goal:.2f} m, "
                f"path left: {tracking.remaining_path_length:.2f} m, "
                f"speed: {tracking.speed:.2f} m/s, "
                f"off the path: {tracking.position_tracking_error:+.3f} m, "
                f"heading error: {tracking.heading_tracking_error:+.2f} rad"
            )

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
