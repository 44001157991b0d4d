#! /usr/bin/env python3
"""Drive a route graph's route (Nav2 Simple Commander, as Nav2's ``example_route.py``).

Run it in the town, whose lanes are a route graph (``sim/worlds/town_routes.geojson``):
``baobab nav2 examples/route_follower.py --world town``. ``getRoute`` plans the cheapest
route from node 3 (the robot's start) to node 22 (the gas station) and its dense path;
``getAndTrackRoute`` then tracks the robot along it, and every new route it sends (the first,
and any reroute round a blocked edge) is followed with ``followPath``.
"""

import rclpy
from geometry_msgs.msg import PoseStamped
from nav2_simple_commander.robot_navigator import BasicNavigator, RunningTask, TaskResult


def main():
    rclpy.init()

    navigator = BasicNavigator()

    initial_pose = PoseStamped()
    initial_pose.header.frame_id = "map"
    initial_pose.header.stamp = navigator.get_clock().now().to_msg()
    navigator.setInitialPose(initial_pose)
    navigator.waitUntilNav2Active()

    start_id, goal_id = 3, 22
    route = navigator.getRoute(start_id, goal_id)
    if route is None:
        (error_code, error_msg) = navigator.getTaskError()
        print(f"Routing failed! {error_code}: {error_msg}")
        exit(1)
    path, sparse = route
    print(
        f"Route {[node.nodeid for node in sparse.nodes]} of cost {sparse.route_cost:.2f}, "
        f"a path of {len(path.poses)} poses."
    )

    route_task = navigator.getAndTrackRoute(start_id, goal_id)
    done = False
    while not done:
        done = navigator.isTaskComplete(task=route_task)
        feedback = navigator.getFeedback(task=route_task)  # queued: read them all
        while feedback is not None:
            if feedback.rerouted:
                print(f"New route: {[node.nodeid for node in feedback.route.nodes]}")
                navigator.followPath(feedback.path)
            elif feedback.next_node_id:
                print(
                    f"Passed node {feedback.last_node_id}, on edge {feedback.current_edge_id} "
                    f"to node {feedback.next_node_id}"
                )
            else:
                print(f"Reached node {feedback.last_node_id}")
            feedback = navigator.getFeedback(task=route_task)

    while not navigator.isTaskComplete(task=RunningTask.FOLLOW_PATH):
        pass

    result = navigator.getResult()
    if result == TaskResult.SUCCEEDED:
        print("Goal succeeded!")
    else:
        (error_code, error_msg) = navigator.getTaskError()
        print(f"Goal failed! {error_code}: {error_msg}")
        exit(1)


if __name__ == "__main__":
    main()
