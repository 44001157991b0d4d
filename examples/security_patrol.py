#! /usr/bin/env python3
"""Patrol the farm's headlands, back and forth, until the rounds are done (Nav2 Simple Commander).

Run it on the farm: ``baobab nav2 examples/security_patrol.py --world farm``. As Nav2's
security demo does, the robot goes through the patrol route without stopping, then through the
same route reversed, for as long as ROS is up and rounds are left. A round that takes too
long is canceled; a round that fails is reported and the next one starts from the other end.
"""

import math

import rclpy
from geometry_msgs.msg import PoseStamped
from nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from nav2_simple_commander.utils import euler_to_quaternion
from nav_msgs.msg import Goals
from rclpy.duration import Duration

# The patrol route: x, y (m) of the points to pass, in order.
security_route = [
    [-6.5, -4.2],
    [-7.2, 0.0],
    [-6.5, 4.2],
]
rounds = 2


def patrol_goals(navigator, route):
    """The route as a ``nav_msgs/Goals``, each pose facing the next point."""
    goals = Goals()
    goals.header.frame_id = "map"
    goals.header.stamp = navigator.get_clock().now().to_msg()
    for index, (x, y) in enumerate(route):
        pose = PoseStamped()
        pose.header = goals.header
        pose.pose.position.x = x
        pose.pose.position.y = y
        ahead = route[min(index + 1, len(route) - 1)]
        behind = route[max(index - 1, 0)]
        pose.pose.orientation = euler_to_quaternion(
            yaw=math.atan2(ahead[1] - behind[1], ahead[0] - behind[0])
        )
        goals.goals.append(pose)
    return goals


def main():
    rclpy.init()

    navigator = BasicNavigator()
    navigator.waitUntilNav2Active()

    route = list(security_route)
    completed = 0
    while rclpy.ok() and completed < rounds:
        task = navigator.goThroughPoses(patrol_goals(navigator, route))

        i = 0
        while not navigator.isTaskComplete(task=task):
            i += 1
            feedback = navigator.getFeedback(task=task)
            if feedback and i % 20 == 0:
                eta = Duration.from_msg(feedback.estimated_time_remaining).nanoseconds / 1e9
                print(
                    f"Round {completed + 1}: {feedback.number_of_poses_remaining} poses left, "
                    f"about {eta:.0f} s."
                )
                if Duration.from_msg(feedback.navigation_time) > Duration(seconds=180.0):
                    navigator.cancelTask()

        route.reverse()
        result = navigator.getResult()
        if result == TaskResult.SUCCEEDED:
            completed += 1
            print(f"Round {completed} done, patrolling back.")
        elif result == TaskResult.CANCELED:
            print("Patrol was canceled, exiting.")
            exit(1)
        elif result == TaskResult.FAILED:
            (error_code, error_msg) = navigator.getTaskError()
            print(f"Patrol failed! {error_code}: {error_msg}; trying from the other end.")

    print("Patrol complete!")
    navigator.lifecycleShutdown()
    exit(0)


if __name__ == "__main__":
    main()
