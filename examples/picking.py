#! /usr/bin/env python3
"""Fetch an order from the kitchen and take it to a table (Nav2 Simple Commander).

Run it in the cafe: ``baobab nav2 examples/picking.py --world cafe``. As Nav2's picking demo
does with shelves and freight bays, the script looks the pick-up and drop-off poses up in
tables, goes to the first, and only once it got there goes on to the second; a failure ends
the script with the task error.
"""

import math

import rclpy
from geometry_msgs.msg import PoseStamped
from nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from rclpy.duration import Duration

# Where orders are picked up: x, y (m) and the heading (rad) to stop with.
pick_ups = {
    "kitchen": [-0.3, 6.8, math.pi / 2],
}
# Where orders go.
tables = {
    "table_2": [1.16, -4.23, 0.0],
    "table_3": [0.792, -8.27, 0.0],
}

request_pick_up = "kitchen"
request_table = "table_3"


def map_pose(navigator, x, y, yaw):
    pose = PoseStamped()
    pose.header.frame_id = "map"
    pose.header.stamp = navigator.get_clock().now().to_msg()
    pose.pose.position.x = x
    pose.pose.position.y = y
    pose.pose.orientation.z = math.sin(yaw / 2)
    pose.pose.orientation.w = math.cos(yaw / 2)
    return pose


def go(navigator, pose, label):
    """Go to ``pose``, printing the time left now and then; the result."""
    task = navigator.goToPose(pose)
    i = 0
    while not navigator.isTaskComplete(task=task):
        i += 1
        feedback = navigator.getFeedback(task=task)
        if feedback and i % 20 == 0:
            eta = Duration.from_msg(feedback.estimated_time_remaining).nanoseconds / 1e9
            print(f"Estimated time to {label}: {eta:.0f} s.")
    return navigator.getResult()


def main():
    rclpy.init()

    navigator = BasicNavigator()
    navigator.setInitialPose(map_pose(navigator, 0.0, 0.0, 0.0))
    navigator.waitUntilNav2Active()

    result = go(navigator, map_pose(navigator, *pick_ups[request_pick_up]), request_pick_up)
    if result == TaskResult.SUCCEEDED:
        print(f"Got the order at the {request_pick_up}; taking it to {request_table}.")
        result = go(navigator, map_pose(navigator, *tables[request_table]), request_table)

    if result == TaskResult.SUCCEEDED:
        print("Order delivered!")
    elif result == TaskResult.CANCELED:
        print("Delivery was canceled!")
        exit(1)
    else:
        (error_code, error_msg) = navigator.getTaskError()
        print(f"Delivery failed! {error_code}: {error_msg}")
        exit(1)

    navigator.lifecycleShutdown()
    exit(0)


if __name__ == "__main__":
    main()
