#! /usr/bin/env python3
"""Drive to a table, pretend to be stuck there, back up, turn round and drive home.

Run it in the cafe: ``baobab nav2 examples/recoveries.py --world cafe``. Nav2's recovery
behaviours are called by hand: ``backup`` reverses away from the table, ``spin`` turns the
robot round, ``driveOnHeading`` moves it straight on, and a last ``goToPose`` takes it back to
where it started. Each behaviour's feedback is printed as it runs.
"""

import rclpy
from geometry_msgs.msg import PoseStamped
from nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from rclpy.duration import Duration


def map_pose(navigator, x, y, z, w):
    """A pose in the map frame at (x, y) with the orientation quaternion (0, 0, z, w)."""
    pose = PoseStamped()
    pose.header.frame_id = "map"
    pose.header.stamp = navigator.get_clock().now().to_msg()
    pose.pose.position.x = x
    pose.pose.position.y = y
    pose.pose.orientation.z = z
    pose.pose.orientation.w = w
    return pose


def finish(navigator, task, label, describe):
    """Poll ``task`` to its end, printing ``describe(feedback)`` now and then; its result."""
    i = 0
    while not navigator.isTaskComplete(task=task):
        i += 1
        feedback = navigator.getFeedback(task=task)
        if feedback and i % 5 == 0:
            print(f"{label}: {describe(feedback)}")
    result = navigator.getResult()
    if result != TaskResult.SUCCEEDED:
        (error_code, error_msg) = navigator.getTaskError()
        print(f"{label} failed! {error_code}: {error_msg}")
        exit(1)
    return result


def main():
    rclpy.init()

    navigator = BasicNavigator()
    initial_pose = map_pose(navigator, 0.0, 0.0, 0.0, 1.0)
    navigator.setInitialPose(initial_pose)
    navigator.waitUntilNav2Active()

    table = map_pose(navigator, -0.96, -0.92, 1.0, 0.0)  # table 1, facing west
    task = navigator.goToPose(table)
    finish(
        navigator,
        task,
        "To the table",
        lambda f: (
            "ETA " + f"{Duration.from_msg(f.estimated_time_remaining).nanoseconds / 1e9:.1f} s"
        ),
    )

    print("Pretending to be stuck: backing up.")
    task = navigator.backup(backup_dist=0.3, backup_speed=0.1)
    finish(navigator, task, "Backing up", lambda f: f"{f.distance_traveled:.2f} m")

    task = navigator.spin(spin_dist=3.14)
    finish(navigator, task, "Spinning", lambda f: f"{f.angular_distance_traveled:.2f} rad")

    task = navigator.driveOnHeading(dist=0.2, speed=0.1)
    finish(navigator, task, "Driving on", lambda f: f"{f.distance_traveled:.2f} m")

    task = navigator.goToPose(initial_pose)
    finish(
        navigator,
        task,
        "Home",
        lambda f: f"{f.distance_remaining:.2f} m left",
    )
    print("Goal succeeded!")

    navigator.lifecycleShutdown()
    exit(0)


if __name__ == "__main__":
    main()
