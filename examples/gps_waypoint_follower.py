#! /usr/bin/env python3
"""Follow GPS waypoints (Nav2 Simple Commander, as Nav2's GPS waypoint follower demo).

Run it in the farm, whose datum puts the map origin at 38.5382 N, 121.7617 W:
``baobab nav2 examples/gps_waypoint_follower.py --world farm``. The waypoints are latitude
and longitude, as a survey of the field would give them; the waypoint follower converts each
through the local tangent plane at the datum (robot_localization's ``fromLL``) and navigates
to it.
"""

import math

import rclpy
from geographic_msgs.msg import GeoPose
from nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from nav2_simple_commander.utils import euler_to_quaternion


def geo_pose(latitude, longitude, yaw):
    """A geographic pose heading ``yaw`` (rad, map frame, copied as Nav2 copies it)."""
    pose = GeoPose()
    pose.position.latitude = latitude
    pose.position.longitude = longitude
    pose.position.altitude = math.nan  # unknown: the datum's
    pose.orientation = euler_to_quaternion(yaw=yaw)
    return pose


def main():
    rclpy.init()

    navigator = BasicNavigator()
    navigator.waitUntilNav2Active()

    waypoints = [
        geo_pose(38.538162164, -121.761631182, 0.0),  # halfway along the southern lane
        geo_pose(38.538171173, -121.761545160, 1.5708),  # the eastern headland
        geo_pose(38.538180181, -121.761631182, 3.1416),  # halfway back along lane 2
    ]
    navigator.followGpsWaypoints(waypoints)

    i = 0
    while not navigator.isTaskComplete():
        i += 1
        feedback = navigator.getFeedback()
        if feedback and i % 20 == 0:
            print(f"Executing current waypoint: {feedback.current_waypoint + 1}/{len(waypoints)}")

    result = navigator.getResult()
    if result == TaskResult.SUCCEEDED:
        print("Goal succeeded!")
    else:
        (error_code, error_msg) = navigator.getTaskError()
        print(f"Goal failed! {error_code}: {error_msg}")
        exit(1)


if __name__ == "__main__":
    main()
