#! /usr/bin/env python3
"""Send the robot to one goal pose, then change the goal on the way (Nav2 Simple Commander).

Run it in the town: ``baobab nav2 examples/nav_to_pose.py --world town``. The robot heads for
the far end of the street; 15 s into the trip the goal moves behind it (a preemption: the same
task takes the new goal, navigation time starts again), and it turns round to reach it. The
script is plain Nav2 Simple Commander code: under ROS 2 it runs against a real Nav2 stack.
"""

import rclpy
from geometry_msgs.msg import PoseStamped
from nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from rclpy.duration import Duration


def main():
    rclpy.init()

    navigator = BasicNavigator()

    # The robot starts where the simulation puts it; a real robot would set its pose here:
    # navigator.setInitialPose(initial_pose)
    navigator.waitUntilNav2Active()

    goal_pose = PoseStamped()
    goal_pose.header.frame_id = "map"
    goal_pose.header.stamp = navigator.get_clock().now().to_msg()
    goal_pose.pose.position.x = 8.0
    goal_pose.pose.position.y = -2.0
    goal_pose.pose.position.z = 0.0
    goal_pose.pose.orientation.x = 0.0
    goal_pose.pose.orientation.y = 0.0
    goal_pose.pose.orientation.z = 0.0
    goal_pose.pose.orientation.w = 1.0

    task = navigator.goToPose(goal_pose)
    preempted = False

    i = 0
    while not navigator.isTaskComplete(task=task):
        i = i + 1
        feedback = navigator.getFeedback(task=task)
        if feedback and i % 10 == 0:
            eta = Duration.from_msg(feedback.estimated_time_remaining).nanoseconds / 1e9
            print(
                f"Distance remaining: {feedback.distance_remaining:.2f} m, "
                f"estimated time of arrival: {eta:.0f} s, "
                f"off the path: {feedback.position_tracking_error:+.2f} m, "
                f"heading error: {feedback.heading_tracking_error:+.2f} rad."
            )

            # A navigation timeout, to show cancellation.
            if Duration.from_msg(feedback.navigation_time) > Duration(seconds=300.0):
                navigator.cancelTask()

            # A change of mind, to show preemption: the goal moves behind the robot.
            if not preempted and Duration.from_msg(feedback.navigation_time) > Duration(
                seconds=15.0
            ):
                goal_pose.header.stamp = navigator.get_clock().now().to_msg()
                goal_pose.pose.position.x = -1.0
                goal_pose.pose.orientation.z = 1.0
                goal_pose.pose.orientation.w = 0.0
                task = navigator.goToPose(goal_pose)
                preempted = True
                print("Goal changed to x = -1.0.")

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
