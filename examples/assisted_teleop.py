#! /usr/bin/env python3
"""Drive towards a wall by teleop and let assisted teleop stop short of it (Nav2 Simple Commander).

Run it in the walls world: ``baobab nav2 examples/assisted_teleop.py --world walls``. A teleop
node publishes forward twists on ``cmd_vel_teleop``, as a joystick would; assisted teleop
passes them on, slowing and then stopping the robot before the wall ahead. After 12 s the
teleop node publishes on ``preempt_teleop``, which ends the session with success. The loop
paces itself with ``time.sleep(0.2)``, as Nav2's own example does: under baobab the sleep is
simulation time, so the robot drives on while the script sleeps.
"""

import time

import rclpy
from geometry_msgs.msg import PoseStamped, Twist
from nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from rclpy.duration import Duration
from std_msgs.msg import Empty


def main():
    rclpy.init()

    navigator = BasicNavigator()

    initial_pose = PoseStamped()
    initial_pose.header.frame_id = "map"
    initial_pose.header.stamp = navigator.get_clock().now().to_msg()
    initial_pose.pose.position.x = 0.0
    initial_pose.pose.position.y = 0.0
    initial_pose.pose.orientation.w = 1.0  # facing east, towards the wall 1.2 m ahead
    navigator.setInitialPose(initial_pose)
    navigator.waitUntilNav2Active()

    # What a joystick or teleop_twist_keyboard would publish.
    teleop = rclpy.create_node("teleop")
    drive = teleop.create_publisher(Twist, "cmd_vel_teleop", 10)
    preempt = teleop.create_publisher(Empty, "preempt_teleop", 10)
    forward = Twist()
    forward.linear.x = 0.2

    teleop_task = navigator.assistedTeleop(time_allowance=20)
    start = time.monotonic()
    while not navigator.isTaskComplete(task=teleop_task):
        # Publish twist commands to be filtered by the assisted teleop action
        drive.publish(forward)
        if time.monotonic() - start > 12.0:
            preempt.publish(Empty())
        feedback = navigator.getFeedback(task=teleop_task)
        if feedback:
            seconds = Duration.from_msg(feedback.current_teleop_duration).nanoseconds / 1e9
            print(f"Teleop for {seconds:.1f} s")
        time.sleep(0.2)

    result = navigator.getResult()
    if result == TaskResult.SUCCEEDED:
        print("Assisted teleop succeeded!")
    else:
        (error_code, error_msg) = navigator.getTaskError()
        print(f"Assisted teleop failed! {error_code}: {error_msg}")

    navigator.lifecycleShutdown()
    exit(0)


if __name__ == "__main__":
    main()
